/// @file mesh.h
/// Tetrahedral meshes and their I/O (TetGen .node/.ele/.face), usable without a world.
#pragma once

#include "types.h"

FM_C_BEGIN

/// Hard limits the readers enforce before allocating (a header may claim anything).
#define FM_MAX_NODES (1 << 26)
/// Largest tet count a file may declare.
#define FM_MAX_TETS (1 << 27)
/// Largest attribute count per node or element.
#define FM_MAX_ATTRIBUTES 64
/// Longest line a reader accepts, in bytes.
#define FM_MAX_LINE 4096

/// A tetrahedral mesh: plain data the user owns; release with fmFreeTetMesh().
typedef struct fmTetMesh
{
	int nodeCount;          ///< number of nodes
	double* positions;      ///< 3 * nodeCount, xyz per node (m)
	int tetCount;           ///< number of tets
	int* tets;              ///< 4 * tetCount, 0-based node indices
	int firstIndex;         ///< numbering of the source file (0 or 1), kept for export
	int nodeAttributeCount; ///< attributes per node
	double* nodeAttributes; ///< nodeCount * nodeAttributeCount, or NULL
	int* nodeMarkers;       ///< boundary marker per node, or NULL if the file has none
	int tetAttributeCount;  ///< attributes per tet (e.g. region numbers)
	double* tetAttributes;  ///< tetCount * tetAttributeCount, or NULL
} fmTetMesh;

/// Load a TetGen mesh from @p nodePath and @p elePath (.node and .ele). On failure @p mesh is
/// left zeroed and @p diag (optional) names the file, line and what was expected.
FM_API fmResult fmLoadTetGen(const char* nodePath, const char* elePath, fmTetMesh* mesh,
                             fmDiagnostic* diag);

/// Same as fmLoadTetGen() from text in memory; the names are used in diagnostics.
/// The texts need not be NUL-terminated; embedded NUL bytes are errors.
FM_API fmResult fmLoadTetGenFromMemory(const char* nodeText, size_t nodeSize, const char* nodeName,
                                       const char* eleText, size_t eleSize, const char* eleName,
                                       fmTetMesh* mesh, fmDiagnostic* diag);

/// Load a TetGen .face file (boundary triangles) into @p triangles (3 per face, 0-based using
/// @p firstIndex and checked against @p nodeCount). Free with fmFree().
FM_API fmResult fmLoadTetGenFaceFromMemory(const char* text, size_t size, const char* name,
                                           int nodeCount, int firstIndex, int** triangles,
                                           int* triangleCount, fmDiagnostic* diag);

/// Write @p positions (3 * mesh->nodeCount, or NULL for the mesh's own) as a TetGen .node file
/// with the mesh's numbering, attributes and markers.
FM_API fmResult fmWriteTetGenNode(const char* path, const fmTetMesh* mesh, const double* positions,
                                  fmDiagnostic* diag);

/// Release the arrays of a mesh and zero it. Safe on a zeroed mesh.
FM_API void fmFreeTetMesh(fmTetMesh* mesh);

/// Release memory returned by femto (e.g. a surface array).
FM_API void fmFree(void* memory);

/// Deep copy. Returns fm_errOutOfMemory on failure.
FM_API fmResult fmCopyTetMesh(const fmTetMesh* source, fmTetMesh* copy);

/// A placement applied in this order: scale, center (move the node centroid to the origin),
/// swap y and z, translate. The bouncy house: scale 0.4, center, swap_yz.
typedef struct fmMeshTransform
{
	double scale;     ///< uniform scale, > 0 (default 1)
	bool center;      ///< subtract the node centroid (default false)
	bool swapYZ;      ///< exchange y and z (default false); flips every tet's orientation
	fmVec3 translate; ///< m, added last (default 0)
} fmMeshTransform;

/// The identity transform.
FM_API fmMeshTransform fmDefaultMeshTransform(void);

/// Apply a transform to the node positions.
FM_API void fmTetMesh_Transform(fmTetMesh* mesh, const fmMeshTransform* transform);

/// Make every tet positively oriented (swap two nodes of tets with negative volume).
/// Returns fm_errDegenerate naming the first tet whose volume is zero (relative to its edges),
/// fm_errIndex for out-of-range or repeated nodes. @p flipped (optional) gets the count.
FM_API fmResult fmTetMesh_Orient(fmTetMesh* mesh, int* flipped, fmDiagnostic* diag);

/// Signed volume of tet @p tet at @p positions (or the mesh's own if NULL).
FM_API double fmTetMesh_TetVolume(const fmTetMesh* mesh, const double* positions, int tet);

/// Statistics of a mesh for `femto info`.
typedef struct fmMeshInfo
{
	int nodeCount;            ///< nodes
	int tetCount;             ///< tets
	int surfaceTriangleCount; ///< boundary triangles
	int unreferencedNodes;    ///< nodes no tet uses
	double totalVolume;       ///< m^3, sum of |V|
	double minVolume;         ///< m^3, smallest signed volume
	double maxVolume;         ///< m^3, largest signed volume
	double minDihedralDeg;    ///< smallest dihedral angle, degrees
	double maxDihedralDeg;    ///< largest dihedral angle, degrees
	double minQuality;        ///< smallest radius ratio 3 r_in / r_circ in [0, 1]
	int invertedTets;         ///< tets with negative volume
	int degenerateTets;       ///< tets with (near) zero volume
	int badTets;              ///< degenerate tets and slivers (a dihedral angle below 5 degrees)
	fmVec3 boundsMin;         ///< m
	fmVec3 boundsMax;         ///< m
} fmMeshInfo;

/// Compute mesh statistics (does not modify the mesh).
FM_API fmResult fmTetMesh_GetInfo(const fmTetMesh* mesh, fmMeshInfo* info);

/// Boundary triangles (faces used by one tet), wound counter-clockwise seen from outside
/// (normals point out of the body for positively oriented tets). Free with fmFree().
FM_API fmResult fmTetMesh_ExtractSurface(const fmTetMesh* mesh, int** triangles,
                                         int* triangleCount);

/// A box [min, max] split into nx * ny * nz cubes of 6 tets each (conforming, positive).
FM_API fmResult fmMakeBoxMesh(int nx, int ny, int nz, fmVec3 min, fmVec3 max, fmTetMesh* mesh);

FM_C_END
