// The meshes `femto bench` times (meshes.c): the bouncy house, generated boxes of about 1k to 1M
// tets and TetGen beams of the same sizes, and the world each one is timed in.
#pragma once

#include "options.h"
#include "scene.h"

/// The floor of every bench world (y, m): the house's stick floor.
#define CLI_BENCH_FLOOR_Y (-3.0)

/// A family of benchmark meshes; `--meshes` names them.
typedef enum cliBenchFamily
{
	cli_benchHouse, ///< data/house2, the demo (1389 tets)
	cli_benchBox,   ///< a 1 m cube of cells x cells x cells cubes, 6 tets each (fmMakeBoxMesh)
	cli_benchBeam,  ///< a 4 x 1 x 1 m beam meshed by tetgen in TetGen's ordering (beams.h)
	/// the contact scenes: ten houses piled, a 100k box on a mesh ground (contact.h); no mesh of
	/// the set, rows of their own
	cli_benchContact,
	/// the scenes in motion (motion.h): a drop, a clamped swing, a drag and the seeds' jump on
	/// the house and on bars of the boxes' sizes; rows of their own
	cli_benchMotion,
	/// the start-up rows (startup.h): a TetGen file to a first implicit step
	cli_benchStartup,
	cli_benchFamilyCount
} cliBenchFamily;

/// Every family, the default of `--meshes`.
#define CLI_BENCH_ALL_FAMILIES ((1u << cli_benchFamilyCount) - 1u)

/// One benchmark mesh.
typedef struct cliBenchMesh
{
	char label[16];        ///< "house2", "box 10k", "beam 10k"
	cliBenchFamily family; ///< which kind
	int nominal;           ///< the size it is chosen by (--max-tets): 1389, 1000, 10000, ...
	int tets;              ///< the actual tet count
	int cells[3];          ///< cli_benchBox: cells along x, y, z
	double length; ///< cli_benchBox: m along x, cells cubic (0: a 1 m cube of cells[] cells)
	char nodePath[CLI_MAX_PATH]; ///< cli_benchBeam: tetgen's .node
	char elePath[CLI_MAX_PATH];  ///< cli_benchBeam: tetgen's .ele
} cliBenchMesh;

/// The meshes of one run, in the order they are timed.
typedef struct cliBenchMeshSet
{
	cliBenchMesh* meshes; ///< malloc'd
	int count;
} cliBenchMeshSet;

/// The family's name in `--meshes` ("house", "box", "beam").
const char* cliBenchFamilyName(cliBenchFamily family);

/// Parse a `--meshes` list ("house,box,beam", any order, at least one) into a bit mask of
/// families. Prints a usage error and returns false on an unknown or empty name.
bool cliBenchParseFamilies(const char* text, unsigned* mask);

/// The meshes of the families in @p mask whose nominal size is at most @p maxTets, smallest
/// first (the house, then the boxes and beams of each size side by side). Beams are generated
/// in @p folder (NULL: there is none) when tetgen is on PATH; otherwise the bench prints why
/// they are skipped and goes on. False (with a message) only when tetgen fails or memory runs
/// out. Free with cliBenchMeshSet_Free().
bool cliBenchMeshSet_Make(unsigned mask, int maxTets, const char* folder, cliBenchMeshSet* set);

/// Release a mesh set (safe on a zeroed one).
void cliBenchMeshSet_Free(cliBenchMeshSet* set);

/// The material the mesh is timed with for @p model: the house's seeds (lambda 20000 Pa, mu
/// 5000 Pa); E = 1 MPa and nu = 0.3 for boxes and beams.
fmMaterial cliBenchMesh_Material(const cliBenchMesh* mesh, fmMaterialModel model);

/// How a timed world is set up.
typedef struct cliBenchWorld
{
	fmIntegrator integrator;
	fmMaterialModel model;
	int workers;
	double tolerance;        ///< implicit
	fmSimdLevel simd;        ///< --simd (default fm_simdAuto)
	bool deterministic;      ///< --deterministic: fmWorldDef.crossPlatformDeterminism
	fmImplicitSolver solver; ///< --implicit-solver
	bool autoSubstep;        ///< explicit: substeps from the stability limit
	double lift;             ///< m the body starts above its resting place (boxes and beams)
	bool noFloor;            ///< no floor at all
	int newtonIterations;    ///< implicit: a step's most (0: the default)
	double yieldStrain;      ///< > 0: the material flows (von Mises, yield stress this times E)
	bool nodalPressure;      ///< the volume term on vertex patches (fmMaterial.nodalPressure)
	double fractureStrength; ///< > 0: the body may tear (fmMaterial.fracture.strength, Pa)
} cliBenchWorld;

/// The world def of the bench's Coulomb-floor scenes (the props, the start-up): implicit at the
/// game tolerance on @p workers, the run's instruction set, determinism and solver, a floor at
/// y = 0 with friction 0.5.
fmWorldDef cliBenchFloorWorldDef(const cliBenchOptions* options, int workers);

/// The body def of those scenes' boxes: Neo-Hookean at E = 1 MPa, nu = 0.3, 1000 kg/m^3, of
/// @p mesh.
fmBodyDef cliBenchBoxBodyDef(const fmTetMesh* mesh);

/// A world with the mesh as its one body resting on (or, the house, falling to) the stick floor
/// at y = -3 (@p settings->lift above it): the house as the demo (1 kg a vertex), boxes and beams
/// at 1000 kg/m^3.
bool cliBenchMesh_World(const cliBenchMesh* mesh, const cliBenchWorld* settings,
                        cliSimulation* sim);
