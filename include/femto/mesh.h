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
/// Default of fmMeshLoadDef::maxFileBytes: 1 GiB, about 14 million points written with full
/// precision. A file is read into one buffer of its size, so this bounds the text held in memory.
#define FM_DEFAULT_MESH_FILE_LIMIT ((size_t)1 << 30)

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

/// Options of fmLoadTetGenWithDef(); start from fmDefaultMeshLoadDef().
typedef struct fmMeshLoadDef
{
	/// Bytes; a .node or .ele file larger than this is refused (fm_errLimit) before anything is
	/// read or allocated. Default FM_DEFAULT_MESH_FILE_LIMIT (1 GiB); SIZE_MAX leaves only memory
	/// as the limit.
	size_t maxFileBytes;
	int internalValue; ///< set by fmDefaultMeshLoadDef; load calls check it
} fmMeshLoadDef;

/// The defaults: files up to FM_DEFAULT_MESH_FILE_LIMIT bytes.
FM_API fmMeshLoadDef fmDefaultMeshLoadDef(void);

/// Load a TetGen mesh from @p nodePath and @p elePath (.node and .ele) with @p def's limits.
/// Only regular files are read (a FIFO, device or directory is refused with fm_errIo without
/// waiting on it); a file over def->maxFileBytes is refused with fm_errLimit before reading.
/// Each file is read into one buffer of its size and released before the next one is read.
/// On failure @p mesh is left zeroed and @p diag (optional) names the file, line and what was
/// expected. A NULL @p mesh or an uninitialised @p def is fm_errParameter (and an assert).
FM_API fmResult fmLoadTetGenWithDef(const char* nodePath, const char* elePath,
                                    const fmMeshLoadDef* def, fmTetMesh* mesh, fmDiagnostic* diag);

/// fmLoadTetGenWithDef() with fmDefaultMeshLoadDef(): files up to 1 GiB.
FM_API fmResult fmLoadTetGen(const char* nodePath, const char* elePath, fmTetMesh* mesh,
                             fmDiagnostic* diag);

/// Same as fmLoadTetGen() from text in memory; the names are used in diagnostics.
/// The texts need not be NUL-terminated; embedded NUL bytes are errors. A NULL @p mesh is
/// fm_errParameter (and an assert).
FM_API fmResult fmLoadTetGenFromMemory(const char* nodeText, size_t nodeSize, const char* nodeName,
                                       const char* eleText, size_t eleSize, const char* eleName,
                                       fmTetMesh* mesh, fmDiagnostic* diag);

/// Load a TetGen .face file (boundary triangles) into @p triangles (3 per face, 0-based using
/// @p firstIndex and checked against @p nodeCount). Free with fmFree(). NULL outputs,
/// nodeCount < 1 or firstIndex not 0 or 1 are fm_errParameter (and an assert).
FM_API fmResult fmLoadTetGenFaceFromMemory(const char* text, size_t size, const char* name,
                                           int nodeCount, int firstIndex, int** triangles,
                                           int* triangleCount, fmDiagnostic* diag);

/// Mesh file formats femto reads (docs/mesh-format.md), chosen by the file name's extension.
typedef enum fmMeshFormat
{
	fm_meshFormatUnknown, ///< an extension femto does not read
	fm_meshFormatTetGen,  ///< TetGen .node + .ele (the two files side by side)
	fm_meshFormatGmsh,    ///< Gmsh .msh, versions 2.2 and 4.1, ASCII or binary
	fm_meshFormatVtk,     ///< VTK legacy .vtk, DATASET UNSTRUCTURED_GRID, ASCII or BINARY
	fm_meshFormatVtu,     ///< VTK XML .vtu (UnstructuredGrid): ascii, binary or appended arrays
	fm_meshFormatMedit,   ///< Medit .mesh (ASCII)
} fmMeshFormat;

/// The format of @p path by its extension, ignoring case: .node and .ele are TetGen, .msh Gmsh,
/// .vtk, .vtu, .mesh. fm_meshFormatUnknown for anything else or NULL.
FM_API fmMeshFormat fmMeshFormatFromPath(const char* path);

/// A format's name for messages ("TetGen", "Gmsh", "VTK legacy", "VTK XML", "Medit").
FM_API const char* fmMeshFormatName(fmMeshFormat format);

/// True when this build reads zlib-compressed .vtu data (zlib was found when femto was built).
FM_API bool fmMeshFormatHasZlib(void);

/// Load a tet mesh from @p path in the format its extension names (fmMeshFormatFromPath), with
/// @p def's limits. A .node path loads the .ele beside it and a .ele path the .node beside it.
/// Only tetrahedra are read: other elements (triangles, lines, hexahedra, ...) are skipped with
/// one warning in @p diag that counts them; quadratic (10-node) tets are read by their 4 corners
/// and their mid-edge nodes dropped. Gmsh physical tags, Medit references and a .vtu "region"
/// cell array become each tet's first attribute (tetAttributeCount 1) when any is not zero.
/// Errors name the file, the line (binary data: the byte offset in the message) and what was
/// expected; an unknown extension is fm_errSyntax. On failure @p mesh is left zeroed. A NULL
/// @p mesh or an uninitialised @p def is fm_errParameter (and an assert).
FM_API fmResult fmLoadMeshWithDef(const char* path, const fmMeshLoadDef* def, fmTetMesh* mesh,
                                  fmDiagnostic* diag);

/// fmLoadMeshWithDef() with fmDefaultMeshLoadDef(): files up to 1 GiB.
FM_API fmResult fmLoadMesh(const char* path, fmTetMesh* mesh, fmDiagnostic* diag);

/// Load a mesh of @p format (not TetGen: use fmLoadTetGenFromMemory) from @p size bytes in
/// memory; @p name is used in diagnostics. The bytes need not be NUL-terminated. An unknown
/// format, TetGen or a NULL @p mesh is fm_errParameter (and an assert for NULL).
FM_API fmResult fmLoadMeshFromMemory(const void* data, size_t size, const char* name,
                                     fmMeshFormat format, fmTetMesh* mesh, fmDiagnostic* diag);

/// Write @p positions (3 * mesh->nodeCount, or NULL for the mesh's own) as a TetGen .node file
/// with the mesh's numbering, attributes and markers. A NULL path, a mesh without points or
/// whose attribute array is missing is fm_errParameter (and an assert).
FM_API fmResult fmWriteTetGenNode(const char* path, const fmTetMesh* mesh, const double* positions,
                                  fmDiagnostic* diag);

/// Write the tets of @p mesh as a TetGen .ele file in the mesh's numbering (firstIndex), with its
/// tet attributes. A NULL path or a mesh whose tets refer to missing nodes is fm_errParameter
/// (and an assert); fm_errIo when the file cannot be written.
FM_API fmResult fmWriteTetGenEle(const char* path, const fmTetMesh* mesh, fmDiagnostic* diag);

/// Write @p mesh (with @p positions, or its own when NULL) as a Gmsh .msh 4.1 ASCII file: all
/// nodes on one volume entity, tets as type 4 in one block per region. When the first tet
/// attribute holds positive integers each becomes a volume with that physical tag, so regions
/// survive a round trip (the tets are then grouped by region). Errors as fmWriteTetGenEle;
/// fm_errRange for a non-finite coordinate.
FM_API fmResult fmWriteGmsh(const char* path, const fmTetMesh* mesh, const double* positions,
                            fmDiagnostic* diag);

/// Write @p mesh (with @p positions, or its own when NULL) as an ASCII .vtu (VTK XML
/// UnstructuredGrid, tets as cell type 10, Float64 points written to round trip exactly), with
/// the first tet attribute as a CellData array "region" when there is one. Errors as fmWriteGmsh.
FM_API fmResult fmWriteVtu(const char* path, const fmTetMesh* mesh, const double* positions,
                           fmDiagnostic* diag);

/// Write @p mesh in the format @p path's extension names: .node (and the .ele beside it), .ele
/// (and the .node beside it), .msh or .vtu. Other extensions are fm_errParameter with a message.
FM_API fmResult fmWriteMesh(const char* path, const fmTetMesh* mesh, const double* positions,
                            fmDiagnostic* diag);

/// Release the arrays of a mesh and zero it. Safe on a zeroed mesh and on NULL.
FM_API void fmFreeTetMesh(fmTetMesh* mesh);

/// Release memory returned by femto (e.g. a surface array). Safe on NULL.
FM_API void fmFree(void* memory);

/// Deep copy. Returns fm_errOutOfMemory on failure; fm_errParameter (and an assert) for NULL or
/// a @p source whose counts and arrays disagree. @p copy (when not NULL) is zeroed on failure.
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

/// Apply a transform to the node positions. A NULL or inconsistent mesh, a NULL transform, a
/// scale that is not finite and > 0 or a non-finite translation asserts and changes nothing.
FM_API void fmTetMesh_Transform(fmTetMesh* mesh, const fmMeshTransform* transform);

/// Make every tet positively oriented (swap two nodes of tets with negative volume).
/// Returns fm_errDegenerate naming the first tet whose volume is zero (relative to its edges),
/// fm_errIndex for out-of-range or repeated nodes, fm_errRange for a non-finite coordinate or a
/// well-shaped tet whose volume a double cannot hold (edges beyond about 1e102 m or below about
/// 1e-102 m). The tests are scale-free. @p flipped (optional) gets the count. A NULL or
/// inconsistent mesh is fm_errParameter (and an assert). A failing mesh is left untouched.
FM_API fmResult fmTetMesh_Orient(fmTetMesh* mesh, int* flipped, fmDiagnostic* diag);

/// Signed volume of tet @p tet at @p positions (or the mesh's own if NULL), in m^3; +-inf or 0
/// when it lies beyond the range of a double. NaN (and an assert) for a NULL mesh, a tet out of
/// range or a tet with invalid node references; NaN for a non-finite coordinate.
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
	int volumeOutOfRangeTets; ///< well-shaped tets whose volume overflows or underflows a double
	fmVec3 boundsMin;         ///< m
	fmVec3 boundsMax;         ///< m
} fmMeshInfo;

/// Shape of one tet. Angles, the radius ratio and degeneracy are measured after scaling the tet
/// so its longest edge is about 1: they do not depend on the mesh's units or scale.
typedef struct fmTetQuality
{
	double volume;         ///< m^3, signed; +-inf or 0 when beyond the range of a double
	double longestEdge;    ///< m; inf when beyond the range of a double
	double minDihedralDeg; ///< smallest dihedral angle, degrees
	double maxDihedralDeg; ///< largest dihedral angle, degrees
	double radiusRatio;    ///< 3 r_in / r_circ in [0, 1]: 1 regular, 0 degenerate
	bool degenerate;       ///< |6 V| <= 1e-12 (longest edge)^3: zero volume relative to its size
	bool volumeOutOfRange; ///< not degenerate, but the volume overflows or underflows a double
} fmTetQuality;

/// Measure tet @p tet (0-based). fm_errIndex for invalid node references, fm_errRange for a
/// non-finite coordinate; fm_errParameter (and an assert) for NULL pointers, an inconsistent
/// mesh or a tet out of range. @p quality is zeroed on failure.
FM_API fmResult fmTetMesh_GetTetQuality(const fmTetMesh* mesh, int tet, fmTetQuality* quality);

/// Compute mesh statistics (does not modify the mesh); scale-free like fmTetMesh_GetTetQuality.
/// fm_errIndex for invalid node references, fm_errRange for a non-finite coordinate;
/// fm_errParameter (and an assert) for NULL pointers or an inconsistent mesh.
FM_API fmResult fmTetMesh_GetInfo(const fmTetMesh* mesh, fmMeshInfo* info);

/// Boundary triangles (faces used by one tet), wound counter-clockwise seen from outside
/// (normals point out of the body for positively oriented tets). Free with fmFree().
/// fm_errIndex for invalid node references; fm_errParameter (and an assert) for NULL pointers
/// or an inconsistent mesh. The outputs (when not NULL) are NULL and 0 on failure.
FM_API fmResult fmTetMesh_ExtractSurface(const fmTetMesh* mesh, int** triangles,
                                         int* triangleCount);

/// A box [min, max] split into nx * ny * nz cubes of 6 tets each (conforming, positive).
/// fm_errParameter for counts < 1 or a box that is empty or not finite, fm_errLimit when the
/// counts exceed FM_MAX_TETS or FM_MAX_NODES (any int is safe), fm_errParameter (and an assert)
/// for a NULL @p mesh.
FM_API fmResult fmMakeBoxMesh(int nx, int ny, int nz, fmVec3 min, fmVec3 max, fmTetMesh* mesh);

// ---- triangle surfaces (OBJ) -------------------------------------------------------------------

/// Largest vertex count an OBJ file may hold.
#define FM_MAX_SURFACE_VERTICES FM_MAX_NODES
/// Largest triangle count an OBJ file may hold (after its polygons are fan-triangulated).
#define FM_MAX_SURFACE_TRIANGLES FM_MAX_TETS

/// A triangle surface (a Wavefront OBJ's faces, polygons fan-triangulated): plain data the user
/// owns; release with fmFreeSurfaceMesh(). A mesh collider's vertices and triangles
/// (fmColliderDef) come from one.
typedef struct fmSurfaceMesh
{
	int vertexCount;   ///< number of vertices
	double* positions; ///< 3 * vertexCount, xyz per vertex (m)
	int triangleCount; ///< number of triangles
	int* triangles;    ///< 3 * triangleCount, 0-based, in the file's (counter-clockwise) winding
} fmSurfaceMesh;

/// Read a Wavefront OBJ's polygons from @p path (a regular file of at most def->maxFileBytes,
/// refused with fm_errLimit before reading): `v x y z [w]` (w ignored; `v x y z r g b`
/// vertex colours are accepted and ignored too), `f` with `v`, `v/vt`, `v//vn` or `v/vt/vn`
/// references, negative (relative) references, polygons of up to 79 vertices fan-triangulated;
/// `vt`, `vn`, `vp`, `o`, `g`, `s`, `mg`, `usemtl`, `mtllib`, `l`, `p` and the other display
/// statements ignored; '#' comments. Line continuations ('\' at the end of a line) and
/// free-form geometry (`curv`, `surf`, ...) are refused. On failure @p surface is left zeroed
/// and @p diag names the file, line, column and what was expected (docs/mesh-format.md).
FM_API fmResult fmLoadObjWithDef(const char* path, const fmMeshLoadDef* def, fmSurfaceMesh* surface,
                                 fmDiagnostic* diag);

/// fmLoadObjWithDef() with fmDefaultMeshLoadDef(): files up to 1 GiB.
FM_API fmResult fmLoadObj(const char* path, fmSurfaceMesh* surface, fmDiagnostic* diag);

/// fmLoadObj() from text in memory (need not be NUL-terminated; a NUL byte is an error);
/// @p name is used in diagnostics. A NULL @p surface is fm_errParameter (and an assert).
FM_API fmResult fmLoadObjFromMemory(const char* text, size_t size, const char* name,
                                    fmSurfaceMesh* surface, fmDiagnostic* diag);

/// Apply @p transform (scale, center on the vertex centroid, swap y and z, translate) to the
/// vertices. Swapping y and z mirrors the surface, so every triangle's winding is reversed with
/// it (fronts stay fronts). A NULL or inconsistent surface, a NULL transform, a scale that is not
/// finite and > 0 or a non-finite translation asserts and changes nothing.
FM_API void fmSurfaceMesh_Transform(fmSurfaceMesh* surface, const fmMeshTransform* transform);

/// Release the arrays of a surface and zero it. Safe on a zeroed surface and on NULL.
FM_API void fmFreeSurfaceMesh(fmSurfaceMesh* surface);

FM_C_END
