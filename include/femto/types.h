/// @file types.h
/// femto value types: result codes, diagnostics, materials and the definition structs
/// (fill one with its fmDefault*() function, change what you need, pass it to a create call).
///
/// "The seeds" in these comments are the documents femto grew from: the GAMES103 course's
/// homework 3, the "bouncy house" (a Unity program stepping a tet mesh of a house with explicit
/// St. Venant-Kirchhoff FEM, a stick floor, damping 0.999, Laplacian velocity smoothing and a
/// space-bar jump). femto's defaults reproduce it; docs/materials.md and docs/robustness.md say
/// where femto departs from it.
#pragma once

#include "base.h"
#include "fm_math.h"

#include <stdbool.h>

FM_C_BEGIN

/// Every result code, from one list: X(name, message).
#define FM_RESULT_LIST(X)                                                                          \
	X(fm_ok, "success")                                                                            \
	X(fm_errIo, "cannot open, read or write the file")                                             \
	X(fm_errSyntax, "malformed input")                                                             \
	X(fm_errRange, "value out of range")                                                           \
	X(fm_errCount, "count does not match the data")                                                \
	X(fm_errLimit, "size exceeds a limit")                                                         \
	X(fm_errIndex, "reference out of range")                                                       \
	X(fm_errDegenerate, "degenerate element")                                                      \
	X(fm_errEmpty, "nothing to simulate")                                                          \
	X(fm_errParameter, "invalid parameter")                                                        \
	X(fm_errOutOfMemory, "out of memory")                                                          \
	X(fm_errNumerical, "numerical failure")                                                        \
	X(fm_errNotConverged, "solver did not converge")                                               \
	X(fm_errInvalidId, "invalid or stale id")                                                      \
	X(fm_errBusy, "the world is in a step (on another thread, or from its substep callback)")

#define FM_RESULT_ENUM(name, message) name,
/// Result of every call that can fail on bad input or numerical trouble.
typedef enum fmResult
{
	FM_RESULT_LIST(FM_RESULT_ENUM) fm_resultCount
} fmResult;
#undef FM_RESULT_ENUM

/// The identifier of a result code, e.g. "fm_errSyntax".
FM_API const char* fmResultName(fmResult result);

/// A short English description of a result code.
FM_API const char* fmResultMessage(fmResult result);

/// Where and why an input was rejected. Optional everywhere (pass NULL); filled on failure,
/// and its warning fields are filled on success when the input was accepted with a doubt.
typedef struct fmDiagnostic
{
	fmResult result;   ///< the code the call returned
	char file[256];    ///< file (or scene JSON path) the problem is in; empty if none
	int line;          ///< 1-based line, 0 if not applicable
	int column;        ///< 1-based column, 0 if not applicable
	char message[512]; ///< what was found and what was expected
	int warningCount;  ///< warnings issued (each also goes to the log hook)
	char warning[512]; ///< the first warning, with file and line
} fmDiagnostic;

/// Write "file:line:column: message" (the parts that are set) into @p buffer. Returns @p buffer.
FM_API const char* fmDiagnostic_Format(const fmDiagnostic* diag, char* buffer, size_t size);

/// Constitutive models. See docs/materials.md.
typedef enum fmMaterialModel
{
	fm_linear,          ///< small-strain linear elasticity (not rotation invariant)
	fm_corotated,       ///< linear elasticity in the rotated frame of F (polar decomposition)
	fm_stvk,            ///< St. Venant-Kirchhoff, the seeds' model
	fm_neoHookean,      ///< compressible Neo-Hookean, defined for inverted tets
	fm_mooneyRivlin,    ///< compressible Mooney-Rivlin
	fm_stretchEnergy,   ///< user energy of the principal stretches (fmMaterial.stretchEnergy)
	fm_invariantEnergy, ///< user energy of the invariants I1, I2, J (fmMaterial.invariantEnergy)
	/// CalculiX's and Abaqus's Neo-Hookean, with the isochoric split:
	/// psi = C10 (J^-2/3 I1 - 3) + (J - 1)^2 / D1, C10 = mu/2, D1 = 2/kappa,
	/// kappa = lambda + 2/3 mu (docs/materials.md); defined for inverted tets
	fm_neoHookeanIsochoric,
	/// orthotropic small-strain elasticity in the material's axes (fmMaterial.orthotropy, fibre,
	/// sheet): sigma = C eps, C from nine engineering constants (CalculiX's *ELASTIC,
	/// TYPE=ENGINEERING CONSTANTS); transversely isotropic as a special case
	fm_orthotropicLinear,
	/// the same stiffness on Green's strain, S = C E in the material's axes: large rotations
	/// (CalculiX's orthotropic elasticity under NLGEOM), with StVK's volume floor
	fm_orthotropicStvk,
	/// Neo-Hookean (lambda, mu) reinforced along the fibre a:
	/// psi_NH + fibreStiffness / 8 (I4 - 1)^2, I4 = |F a|^2 (in tension and compression); at
	/// small strain the modulus along the fibre is E + fibreStiffness
	fm_fibreNeoHookean,
	fm_materialModelCount
} fmMaterialModel;

/// User energy density of the signed principal stretches s[0..2] (Pa). Write psi, its gradient
/// dpsi[i] = d psi / d s_i, and, when @p d2psi is not NULL, the Hessian d2psi[3 * i + j].
/// Must be symmetric in its arguments (isotropy) and zero with zero gradient at s = (1,1,1).
typedef void fmStretchEnergyFcn(const double s[3], const void* params, double* psi, double dpsi[3],
                                double* d2psi);

/// User energy density of the invariants v = {I1 = tr(F^T F), I2 = ((tr C)^2 - tr(C^2))/2,
/// J = det F}. Write psi, dpsi[i] = d psi / d v_i and, when @p d2psi is not NULL, d2psi[3i+j].
typedef void fmInvariantEnergyFcn(const double v[3], const void* params, double* psi,
                                  double dpsi[3], double* d2psi);

/// Orthotropic elastic constants in the material's axes 1 (the fibre), 2 (the sheet) and 3
/// (fibre x sheet), as CalculiX's and Abaqus's engineering constants: nu[k] is the strain across
/// over the strain along when pulled along the first axis of the pair (nu12 = -eps2/eps1).
/// Valid when every modulus is positive and the compliance is positive definite.
typedef struct fmOrthotropy
{
	double E[3];  ///< Young's moduli E1, E2, E3 along axes 1, 2, 3 (Pa)
	double nu[3]; ///< Poisson ratios nu12, nu13, nu23
	double G[3];  ///< shear moduli G12, G13, G23 (Pa)
} fmOrthotropy;

/// Von Mises plasticity on top of a material's elastic law (docs/materials.md, "Plasticity"):
/// multiplicative, F = Fe Fp, each tet's plastic part updated by a return map on the
/// logarithmic strain of Fe after every step. All zero (the default): elastic.
typedef struct fmPlasticity
{
	double yieldStress; ///< Pa, the uniaxial (von Mises) yield stress sigma_y; 0 = elastic
	/// Pa, >= 0: linear isotropic hardening, the yield stress grows by this times the
	/// equivalent plastic strain
	double hardening;
	/// 1/s, >= 0: 0 returns the stress to the yield surface at once (rate-independent); > 0
	/// relaxes the overstress at this rate (viscoplastic creep: slow loads bend, quick ones
	/// bounce)
	double creepRate;
	/// >= 0: the equivalent plastic strain a tet may gather before it hardens into an elastic
	/// one (a cap on how far a body can be bent for good); 0 = no cap
	double maxPlasticStrain;
} fmPlasticity;

/// Fracture along tet faces (docs/materials.md, "Fracture"): after each frame a face shared by
/// two tets breaks when the tensile traction across it, n . sigma n with sigma the two tets'
/// Cauchy stress averaged over `length`, reaches `strength` (Rankine's maximum normal stress
/// on the mesh's faces); a vertex whose tets no longer hold together across unbroken faces is
/// split in two, its mass shared by tet volume. The fem force model. All zero: unbreakable.
typedef struct fmFracture
{
	double strength; ///< Pa, >= 0: the tensile strength sigma_t; 0 = never breaks
	/// m, >= 0: the stress a face reads is averaged over the tets whose centres lie within this
	/// distance of each side's (at rest): the theory of critical distances' L = (K_Ic /
	/// sigma_t)^2 / pi, which makes the tearing load independent of the mesh once the mesh
	/// resolves it; 0: the two tets of the face alone
	double length;
	/// m^3, >= 0: a tear that would cut off a piece smaller waits until it cuts a bigger one
	/// (no slivers); 0: eight times the body's mean tet volume. The body's material sets it
	double minVolume;
} fmFracture;

/// A material. Make one with fmMakeMaterial(), fmMakeMaterialLame() or
/// fmMakeOrthotropicMaterial(); the anisotropic models read their axes from fibre and sheet.
typedef struct fmMaterial
{
	fmMaterialModel model; ///< constitutive model
	double lambda;         ///< first Lame constant, Pa, > -2/3 mu
	double mu;             ///< shear modulus (second Lame constant), Pa, > 0
	double c01;            ///< Mooney-Rivlin second constant, Pa, in [0, mu/2]; C10 = mu/2 - c01
	fmStretchEnergyFcn* stretchEnergy;     ///< for fm_stretchEnergy
	fmInvariantEnergyFcn* invariantEnergy; ///< for fm_invariantEnergy
	const void* userParams;                ///< passed to the user energy
	fmOrthotropy orthotropy;               ///< for fm_orthotropicLinear and fm_orthotropicStvk
	double fibreStiffness;                 ///< for fm_fibreNeoHookean: Pa, >= 0
	/// material axis 1 of the anisotropic models in the body's rest frame (any length but 0;
	/// all zero: x); a body's per-tet fibres (fmBodyDef.tetFibres) replace it
	fmVec3 fibre;
	/// material axis 2, made orthogonal to the fibre (all zero, or along the fibre: y, or z when
	/// the fibre is along y); axis 3 is fibre x sheet
	fmVec3 sheet;
	/// von Mises plasticity (stvk, corotated, neohookean, mooney-rivlin, neohookean-isochoric;
	/// the fem force model); all zero: elastic
	fmPlasticity plasticity;
	/// the volume term on vertex patches instead of per tet (Bonet and Burton's averaged nodal
	/// pressure tet): no volumetric locking at a Poisson ratio near 0.5. For linear, neohookean,
	/// mooney-rivlin and neohookean-isochoric, whose volume term is a function of J alone; the
	/// fem force model (docs/materials.md, "Nearly incompressible bodies")
	bool nodalPressure;
	/// tearing along tet faces (the fem force model); all zero: unbreakable
	fmFracture fracture;
} fmMaterial;

/// A material from Young's modulus @p youngsModulus (Pa, > 0) and Poisson ratio
/// @p poissonRatio (in (-1, 0.5)): lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)).
/// Mooney-Rivlin gets the default split c01 = mu / 8 (a quarter of the shear from I2).
FM_API fmMaterial fmMakeMaterial(fmMaterialModel model, double youngsModulus, double poissonRatio);

/// A material from the Lame constants directly (the seeds give lambda = 20000, mu = 5000).
FM_API fmMaterial fmMakeMaterialLame(fmMaterialModel model, double lambda, double mu);

/// An orthotropic material (fm_orthotropicLinear or fm_orthotropicStvk) with axes x, y, z (set
/// fibre and sheet to turn them); lambda and mu get the Voigt average of its stiffness (the
/// scale femto's tolerances use).
FM_API fmMaterial fmMakeOrthotropicMaterial(fmMaterialModel model, fmOrthotropy constants);

/// The orthotropic constants of a transversely isotropic solid whose axis of symmetry is the
/// fibre: E1 = @p eAlong, E2 = E3 = @p eAcross, nu12 = nu13 = @p nuAlong, nu23 = @p nuAcross,
/// G12 = G13 = @p gAlong, G23 = eAcross / (2 (1 + nuAcross)).
FM_API fmOrthotropy fmTransverselyIsotropic(double eAlong, double eAcross, double nuAlong,
                                            double nuAcross, double gAlong);

/// lambda / mu above which a material is nearly incompressible (a Poisson ratio above 0.49):
/// accepted with a warning (fmMaterial_Validate), since linear tets lock under it.
#define FM_NEARLY_INCOMPRESSIBLE 49.0

/// Check a material; on failure the diagnostic says which parameter and what would work. A
/// nearly incompressible one (lambda > FM_NEARLY_INCOMPRESSIBLE mu) passes with a warning.
FM_API fmResult fmMaterial_Validate(const fmMaterial* material, fmDiagnostic* diag);

/// The model's scene name ("linear", "corotated", "stvk", "neohookean", "mooney-rivlin", ...).
FM_API const char* fmMaterialModelName(fmMaterialModel model);

/// Look a model up by scene name. Returns false if unknown.
FM_API bool fmMaterialModelFromName(const char* name, fmMaterialModel* model);

/// How energy becomes vertex forces (docs/force-models.md).
typedef enum fmForceModel
{
	fm_fem,        ///< finite elements: f = -V0 P Dm^-T
	fm_fvm,        ///< finite volumes: stress on area-weighted face normals (Teran et al. 2003)
	fm_massSpring, ///< springs on the tet edges, stiffness from E
	fm_forceModelCount
} fmForceModel;

/// Scene name of a force model ("fem", "fvm", "mass-spring").
FM_API const char* fmForceModelName(fmForceModel model);

/// Look a force model up by scene name. Returns false if unknown.
FM_API bool fmForceModelFromName(const char* name, fmForceModel* model);

/// Time integrators.
typedef enum fmIntegrator
{
	fm_explicit, ///< symplectic Euler, as the seeds (needs small steps)
	fm_implicit, ///< backward Euler by Newton on the incremental potential
} fmIntegrator;

/// How the implicit integrator minimises each step's incremental potential
/// (fmWorldDef.implicitSolver); docs/implicit.md compares them.
typedef enum fmImplicitSolver
{
	fm_solverNewton, ///< Newton with preconditioned CG and a line search (default)
	fm_solverVbd,    ///< vertex block descent (Chen et al. 2024): 3x3 Newton steps per vertex
	fm_implicitSolverCount
} fmImplicitSolver;

/// The instruction sets the explicit step's element kernels may use (fmWorldDef.simd). The
/// batched kernels take 16 tets at once in float (linear, StVK, Neo-Hookean and corotated, FEM
/// force model; other bodies use the double-precision reference kernel); every level gives the same
/// bits, only the speed differs. docs/performance.md has the accuracy.
typedef enum fmSimdLevel
{
	fm_simdAuto,   ///< the best the CPU has, found at run time (default)
	fm_simdOff,    ///< no batched kernels: the double-precision reference kernel for every body
	fm_simdScalar, ///< the batched kernels in plain C, one lane at a time
	fm_simdSse2,   ///< 128-bit vectors (the target's baseline vectors off x86-64)
	fm_simdAvx2,   ///< 256-bit vectors; falls back to the best below when the CPU lacks it
	fm_simdAvx512, ///< 512-bit vectors; falls back likewise
	fm_simdLevelCount
} fmSimdLevel;

/// Look a SIMD level up by scene name ("auto", "off", "scalar", "sse2", "avx2", "avx512").
/// Returns false if unknown.
FM_API bool fmSimdLevelFromName(const char* name, fmSimdLevel* level);

/// The scene name of a SIMD level ("unknown" out of range).
FM_API const char* fmSimdLevelName(fmSimdLevel level);

/// Floor friction behaviour.
typedef enum fmFloorFriction
{
	fm_floorStick,   ///< the seeds: tangential velocity zeroed on contact
	fm_floorCoulomb, ///< Coulomb friction with a coefficient and restitution
} fmFloorFriction;

/// Collision filtering: two things collide when each one's category is in the other's mask.
typedef struct fmFilter
{
	uint32_t categoryBits; ///< what this is (default 1)
	uint32_t maskBits;     ///< what it collides with (default all bits)
} fmFilter;

/// The default filter: category 1, collides with everything.
FM_API fmFilter fmDefaultFilter(void);

/// A horizontal floor plane y = height; bodies stay above it. The floor is the world's
/// half-space collider (fmWorld_GetFloorCollider): its contacts, begin and end events and the
/// force the bodies exert on it are reported as a collider's (docs/contact.md).
typedef struct fmFloorDef
{
	bool enabled;               ///< false: no floor
	double height;              ///< m
	fmFloorFriction friction;   ///< stick or Coulomb
	double frictionCoefficient; ///< Coulomb coefficient, >= 0
	double restitution;         ///< normal restitution, in [0, 1]
	/// m/s, > 0 (default 1): the fastest a vertex found below the floor is pushed out. A body
	/// that starts (or is dragged) deep below the floor rises at this speed instead of being
	/// catapulted; penetration that the step's own motion explains is removed at once (as
	/// PhysX's max depenetration velocity). See docs/robustness.md.
	double maxDepenetrationSpeed;
	/// Which bodies the floor holds (default fmDefaultFilter(): every body); a body whose
	/// filter does not meet it falls through, as through a collider
	fmFilter filter;
} fmFloorDef;

/// The default floor: enabled at y = 0, the seeds' stick friction, depenetration at 1 m/s.
FM_API fmFloorDef fmDefaultFloorDef(void);

/// Check a floor; the diagnostic says which field is wrong.
FM_API fmResult fmFloorDef_Validate(const fmFloorDef* floor, fmDiagnostic* diag);

/// How soft bodies touch each other (fmWorldDef.contact; docs/contact.md).
typedef struct fmContactDef
{
	bool bodies;        ///< body-body contact (default true)
	double thickness;   ///< m, > 0: the gap contact keeps; 0 (default): 1% of the smallest
	                    ///< body's bounding-box diagonal when the first step runs
	double friction;    ///< Coulomb coefficient between bodies, >= 0 (default 0.5)
	double restitution; ///< between bodies, in [0, 1] (default 0)
	int iterations;     ///< projection passes over the contacts a substep, in [1, 64] (default 4)
	/// Islands that stay slower than sleepSpeed for sleepTime fall asleep: they are not
	/// stepped until something touches them or the API wakes them (fmBody_SetAwake) (default
	/// false, so that a body's motion never depends on a threshold unless asked)
	bool enableSleep;
	double sleepSpeed; ///< m/s, > 0: the fastest vertex of a body that may sleep (default 0.05)
	double sleepTime;  ///< s, > 0: how long an island stays that slow before it sleeps (0.5)
} fmContactDef;

/// Shapes of rigid colliders.
typedef enum fmShapeType
{
	fm_shapePlane,   ///< the half-space normal . x <= offset is solid
	fm_shapeSphere,  ///< center, radius
	fm_shapeBox,     ///< center, halfExtents, rotation
	fm_shapeCapsule, ///< segment a-b, radius
	fm_shapeMesh,    ///< triangle mesh (vertices, triangles) placed at center with rotation
	fm_shapeTypeCount
} fmShapeType;

/// A rigid collider that soft bodies rest on and are pushed by: static, or kinematic when it
/// has a velocity or angular velocity (it then moves every step, and reports the force the
/// bodies exert on it: fmCollider_GetContactForce). Get one from fmDefaultColliderDef().
typedef struct fmColliderDef
{
	fmShapeType shape;
	fmVec3 normal;      ///< plane: the outward normal (any length > 0; normalised)
	double offset;      ///< plane: the plane is normal . x = offset (normal normalised)
	fmVec3 center;      ///< sphere, box: the centre (m); mesh: where its local origin goes
	double radius;      ///< sphere, capsule: m, > 0
	fmVec3 halfExtents; ///< box: m, each > 0
	fmVec3 rotation;    ///< box, mesh: axis-angle (rad), the orientation
	fmVec3 a;           ///< capsule: one end of the segment (m)
	fmVec3 b;           ///< capsule: the other end
	/// mesh: vertices (m, in the mesh's own frame), copied at creation
	const fmVec3* vertices;
	int vertexCount; ///< mesh: >= 3, at most FM_MAX_COLLIDER_TRIANGLES * 3
	/// mesh: 3 vertex indices (0-based) per triangle, copied. Closed meshes are solid inside;
	/// an open mesh (a level's ground) is solid behind its triangles' fronts, the side their
	/// counter-clockwise winding faces away from (docs/contact.md)
	const int* triangles;
	int triangleCount;  ///< mesh: in [1, FM_MAX_COLLIDER_TRIANGLES]
	double friction;    ///< Coulomb coefficient, >= 0 (default 0.5)
	double restitution; ///< in [0, 1] (default 0)
	/// Infinite friction, as the seeds' floor (fm_floorStick): a vertex in contact has its
	/// velocity along the surface, relative to the collider's, zeroed; `friction` is then
	/// ignored, restitution still acts on the normal (default false; docs/contact.md)
	bool stick;
	fmVec3 velocity;        ///< m/s: kinematic translation (default 0)
	fmVec3 angularVelocity; ///< rad/s about the shape's centre (default 0)
	fmFilter filter;        ///< default: fmDefaultFilter()
	int internalValue;      ///< set by fmDefaultColliderDef; create calls check it
} fmColliderDef;

/// A collider with every default: a plane y = 0, friction 0.5, static.
FM_API fmColliderDef fmDefaultColliderDef(void);

/// Check a collider def; the diagnostic says which field is wrong and what would work.
FM_API fmResult fmColliderDef_Validate(const fmColliderDef* def, fmDiagnostic* diag);

/// Colliders a world holds at most.
#define FM_MAX_COLLIDERS 1024
/// Triangles a mesh collider holds at most.
#define FM_MAX_COLLIDER_TRIANGLES (1 << 22)

/// Largest fmWorldDef.newtonIterations: beyond it a solve has stagnated, not converged.
#define FM_MAX_NEWTON_ITERATIONS 1000
/// Largest fmWorldDef.cgIterations.
#define FM_MAX_CG_ITERATIONS 100000
/// Smallest fmWorldDef.tolerance: relative residuals below it are round-off in double.
#define FM_MIN_TOLERANCE 1e-12
/// The accurate tolerance preset (the default of fmWorldDef.tolerance).
#define FM_TOLERANCE_ACCURATE 1e-6
/// The game tolerance preset: about 3 times fewer Newton and 4 times fewer CG iterations on the
/// house, whose drop then follows the accurate path to 0.1% (docs/implicit.md).
#define FM_TOLERANCE_GAME 1e-2
/// Most substeps fmWorld_Step takes in one call.
#define FM_MAX_SUBSTEPS 100000
/// Longest substep (s) fmWorld_Step takes: beyond it use fmBody_SolveStatic for equilibrium.
#define FM_MAX_SUBSTEP 1000.0
/// Shortest substep (s) fmWorld_Step takes.
#define FM_MIN_SUBSTEP 1e-12

/// The default fmWorldDef.memoryBudget: 4 GiB (all of the address space on 32-bit systems).
#define FM_DEFAULT_MEMORY_BUDGET                                                                   \
	((size_t)(SIZE_MAX >> 31 > 1 ? ((uint64_t)4 << 30) : (uint64_t)SIZE_MAX))

/// Most workers a world runs its stages on.
#define FM_MAX_WORKERS 64

/// A task: process items [@p startIndex, @p endIndex) on worker @p workerIndex (0 to
/// workerCount - 1) with @p taskContext. Tasks of one loop write disjoint outputs.
typedef void fmTaskCallback(int startIndex, int endIndex, int workerIndex, void* taskContext);

/// Engine hook (as Box2D v3's): run @p task over @p itemCount items, split into ranges of at
/// least @p minRange items that may run in parallel, each with a distinct worker index below
/// fmWorldDef.workerCount. Return a handle for fmFinishTaskCallback, or NULL when the task has
/// already run to the end.
typedef void* fmEnqueueTaskCallback(fmTaskCallback* task, int itemCount, int minRange,
                                    void* taskContext, void* userContext);

/// Engine hook: wait until the task behind @p userTask has finished.
typedef void fmFinishTaskCallback(void* userTask, void* userContext);

/// Called after every substep of fmWorld_Step, when the bodies and the contact stage have
/// stepped (the state is a whole substep's): @p substep counts the frame's substeps from 0,
/// @p time is the frame's time reached (s). It may read the world (copy positions, query,
/// fmWorld_AuditContact) but not change it or step it (fmWorld_Step from it is refused with
/// fm_errParameter); @p userContext is
/// fmWorldDef.substepContext (where the caller keeps the world's id).
typedef void fmSubstepCallback(int substep, double time, void* userContext);

/// World definition. Get one from fmDefaultWorldDef().
typedef struct fmWorldDef
{
	fmVec3 gravity;          ///< m/s^2, |g| <= 1e4 (about 1000 g), default (0, -9.8, 0): y is up
	fmFloorDef floor;        ///< default: enabled at y = -3, stick (the seeds)
	fmIntegrator integrator; ///< default fm_explicit
	int newtonIterations;    ///< implicit: maximum Newton iterations a step, in [1, 1000] (20)
	/// implicit: relative residual to stop at, in [1e-12, 1) (default 1e-6), see docs/implicit.md
	double tolerance;
	int cgIterations; ///< implicit: maximum CG iterations a Newton step, in [1, 100000] (500)
	/// implicit: a step that ends above the tolerance is an error (fm_errNotConverged, state
	/// restored) instead of a warning counted in fmStepStats.unconvergedSteps (default false)
	bool notConvergedIsError;
	/// explicit: substeps of at most 0.3 of the stability limit at the bodies' current
	/// deformation (fmWorld_EstimateExplicitStep), and at least the count given to
	/// fmWorld_Step; the limit is re-evaluated when the deformation moves (docs/robustness.md)
	/// (default false)
	bool autoSubstep;
	int maxBodies; ///< capacity, >= 1 (default 64)
	/// Bytes the world's body table, bodies and colliders may take, >= the table (maxBodies
	/// bodies of a few hundred bytes each); default 4 GiB (FM_DEFAULT_MEMORY_BUDGET), SIZE_MAX
	/// for no limit. fmCreateBody() estimates a body before allocating anything
	/// (fmEstimateBodyMemory(), the implicit solver's matrix included) and fmCreateCollider() a
	/// mesh collider's copy, and each refuses with fm_errLimit beyond the budget.
	size_t memoryBudget;
	/// Workers the stages run on, in [1, FM_MAX_WORKERS] (default 1: serial, no threads).
	/// Results are bit-identical for any count. Without task callbacks femto starts
	/// workerCount - 1 threads of its own.
	int workerCount;
	/// Cross-machine determinism, for lockstep networked games (docs/determinism.md): the same
	/// bits on any x86-64, ARM or WebAssembly target and C library, as long as femto is built
	/// without FMA contraction (-ffp-contract=off) and without -ffast-math. The hot path then
	/// uses femto's own log and pow instead of the C library's (whose last bits differ between
	/// libms). The floating-point state (round to nearest, no flush-to-zero, no
	/// denormals-are-zero) is set and restored by every call whether or not this is on.
	/// Costs a few percent of an implicit Neo-Hookean frame, nothing for models without ln J
	/// (docs/performance.md) (default false)
	bool crossPlatformDeterminism;
	/// The frame budget: Newton iterations all implicit steps of one fmWorld_Step() may take
	/// together, >= 1 (default 1000000). Checked between substeps: once it is spent, the
	/// remaining steps get one iteration each (their residuals are reported as usual) and
	/// fmStepStats.budgetHit is set, so one bad body cannot stall a game's frame.
	int maxNewtonPerFrame;
	/// The frame budget of autoSubstep: substeps one fmWorld_Step() may take, in
	/// [1, FM_MAX_SUBSTEPS] (default FM_MAX_SUBSTEPS). Once spent, the rest of the frame is
	/// taken in that many steps, beyond the stability limit, and fmStepStats.budgetHit is set.
	int maxSubstepsPerFrame;
	/// explicit: the instruction sets the element kernels may use (default fm_simdAuto: the
	/// best the CPU has; fm_simdOff: the double-precision reference kernel)
	fmSimdLevel simd;
	/// implicit: the minimiser of each step (default fm_solverNewton, measured faster; vertex
	/// block descent for comparison; Rayleigh stiffness damping and kinematic targets always
	/// take Newton)
	fmImplicitSolver implicitSolver;
	fmContactDef contact;               ///< body-body contact (fmContactDef)
	fmEnqueueTaskCallback* enqueueTask; ///< the engine's job system, or NULL (both or neither)
	fmFinishTaskCallback* finishTask;   ///< waits for a task enqueueTask returned
	void* userTaskContext;              ///< passed to the two callbacks
	fmSubstepCallback* substepCallback; ///< after every substep, or NULL (tests, debugging)
	void* substepContext;               ///< passed to substepCallback
	int internalValue;                  ///< set by fmDefaultWorldDef; create calls check it
} fmWorldDef;

/// The default world: the seeds' gravity and floor, explicit integration.
FM_API fmWorldDef fmDefaultWorldDef(void);

/// Most materials a body may have by region (fmBodyDef.regionCount).
#define FM_MAX_REGIONS 1024

/// How vertex masses are found.
typedef enum fmMassMode
{
	fm_massFromDensity, ///< lumped: each tet gives density * V0 / 4 to each of its nodes
	fm_massPerParticle, ///< every vertex has particleMass (the seeds: 1 kg)
} fmMassMode;

struct fmTetMesh;

/// Body definition. Get one from fmDefaultBodyDef().
typedef struct fmBodyDef
{
	const struct fmTetMesh* mesh; ///< rest shape (copied; the caller keeps ownership)
	fmMaterial material;          ///< default: the seeds' StVK, lambda 20000 Pa, mu 5000 Pa
	fmForceModel forceModel;      ///< default fm_fem
	fmMassMode massMode;          ///< default fm_massPerParticle (the seeds)
	double density;               ///< kg/m^3, > 0, for fm_massFromDensity (default 1000)
	double particleMass;          ///< kg, > 0, for fm_massPerParticle (default 1)
	double damping;      ///< velocity factor per 3 ms (the seeds' step; other steps get the same
	                     ///< rate per second), in (0, 1]; 1 = none (default 0.999)
	double smoothing;    ///< Laplacian velocity blend per 3 ms, in [0, 1] (default 0.1)
	double rayleighMass; ///< Rayleigh alpha, 1/s, >= 0 (default 0)
	double rayleighStiffness; ///< Rayleigh beta, s, >= 0 (default 0)
	double springDamping;     ///< mass-spring: damping ratio of each spring, >= 0 (default 0.1)
	/// Coulomb coefficient against other bodies, >= 0, or -1 (default) for the world's
	/// fmContactDef.friction; a pair uses sqrt(mu_a mu_b). Colliders have their own.
	double friction;
	fmFilter filter; ///< collision filtering (default fmDefaultFilter())
	/// the body's surface vertices against its own surface triangles that do not share a tet
	/// with them: a beam folding onto itself (default false; costs a broad phase of its own)
	bool selfCollision;
	bool enableSleep; ///< may fall asleep when fmContactDef.enableSleep (default true)
	/// Per-region materials (docs/materials.md): a tet whose region, the mesh's first tet
	/// attribute (TetGen's region attribute, Gmsh's physical group), equals regionIds[k] gets
	/// regionMaterials[k]; the other tets get `material`. regionCount in [0, FM_MAX_REGIONS]
	/// (default 0: one material); both arrays are copied. The mesh must have tet attributes
	/// when regionCount > 0; ids must be distinct. Mass still comes from `density` (or
	/// particleMass) for every tet.
	const fmMaterial* regionMaterials;
	const int* regionIds; ///< regionCount region numbers
	int regionCount;
	/// Per-tet fibre directions (tet count entries, the mesh's numbering; copied), or NULL: the
	/// first material axis of every tet whose material is anisotropic, in place of the
	/// material's fibre (docs/materials.md, "Anisotropy"). Each must be finite and non-zero.
	const fmVec3* tetFibres;
	int internalValue; ///< set by fmDefaultBodyDef; create calls check it
} fmBodyDef;

/// The default body: the seeds' bouncy house parameters (no mesh).
FM_API fmBodyDef fmDefaultBodyDef(void);

/// World handle. Zero-initialised means null. Generations are 32-bit and a slot is retired
/// before its generation would wrap, so an id of a destroyed world never becomes valid again.
typedef struct fmWorldId
{
	int32_t index1;      ///< 1-based slot, 0 for the null id
	uint32_t generation; ///< catches stale ids
} fmWorldId;

/// Body handle. Zero-initialised means null. It names its world's slot and generation too, so an
/// id of a body in a destroyed world never reaches a body of a later world in that slot.
typedef struct fmBodyId
{
	int32_t index1;           ///< 1-based slot in the world, 0 for the null id
	uint32_t generation;      ///< catches stale ids
	int32_t world0;           ///< world slot (0-based)
	uint32_t worldGeneration; ///< generation of the world the body was created in
} fmBodyId;

/// Collider id (fmCreateCollider). Zero-initialised means null.
typedef struct fmColliderId
{
	int32_t index1;           ///< 1-based slot in the world, 0 for the null id
	uint32_t generation;      ///< catches stale ids
	int32_t world0;           ///< world slot (0-based)
	uint32_t worldGeneration; ///< generation of the world the collider was created in
} fmColliderId;

/// One contact of the last substep (fmWorld_GetContacts): a surface vertex of a body against a
/// collider or against a triangle of another body.
typedef struct fmContactPoint
{
	fmBodyId body;         ///< the body whose vertex touches
	int vertex;            ///< that vertex (user numbering)
	fmBodyId otherBody;    ///< the other body (null id for a collider)
	fmColliderId collider; ///< the collider (null id for a body)
	fmVec3 point;          ///< m, the vertex after the contact's response
	fmVec3 normal;         ///< unit, from the other thing toward the vertex
	double depth;          ///< m, how far inside the contact thickness the vertex was found
	double impulse;        ///< N s, the normal impulse the contact gave the vertex
} fmContactPoint;

/// A pair that started or stopped touching during the last fmWorld_Step().
typedef struct fmContactEvent
{
	bool begin;            ///< true: began touching; false: stopped
	fmBodyId body;         ///< the body (for a body pair, the one of the lower slot)
	fmBodyId otherBody;    ///< the other body, or the null id
	fmColliderId collider; ///< the collider, or the null id
} fmContactEvent;

/// A body that fell asleep or woke during the last fmWorld_Step() (fmWorld_GetSleepEvents).
typedef struct fmSleepEvent
{
	fmBodyId body;
	bool asleep; ///< true: fell asleep; false: woke
} fmSleepEvent;

/// Something a sphere overlaps (fmWorld_OverlapSphere).
typedef struct fmOverlap
{
	fmBodyId body;         ///< the body, or the null id
	fmColliderId collider; ///< the collider, or the null id
	int vertex;      ///< body: its surface vertex nearest the centre (user numbering), else -1
	fmVec3 point;    ///< m: the nearest point of the body's surface or the collider to the centre
	double distance; ///< m from the centre to point (0 when the centre is inside)
} fmOverlap;

/// Where a ray hit (fmWorld_CastRay).
typedef struct fmRayHit
{
	fmBodyId body;         ///< the body hit, or the null id
	fmColliderId collider; ///< the collider hit, or the null id
	int triangle;          ///< the body's surface triangle (fmBody_GetSurface order), or -1
	int vertex;            ///< the triangle's vertex nearest the hit (user numbering), or -1
	fmVec3 point;          ///< m
	fmVec3 normal;         ///< unit, the surface's outward normal
	double fraction;       ///< of the ray's translation, in [0, 1]
} fmRayHit;

/// How a grab holds a body (fmBody_Grab, fmWorld_GrabRay): a damped spring from the grabbed
/// point to the target the caller moves, spread over the vertices around the point (each pulls
/// in proportion to its mass and a smooth falloff with its distance) and bounded: beyond the
/// stretch maxForce / stiffness the pull stays maxForce, however fast or far the target goes.
/// Start from fmDefaultGrabDef(); 0 picks the default that scales with the body.
typedef struct fmGrabDef
{
	/// m, the patch: vertices within it of the grabbed point share the pull (default 0: 12% of
	/// the body's size, its box's diagonal; at least twice the distance to the nearest vertex)
	double radius;
	/// N/m, the whole spring (default 0: the body's weight over 2 mm, so a slow pointer lifting
	/// the body leads the grabbed point by a few mm)
	double stiffness;
	/// the dashpot against the body's mass, 1 critical (default 1): relative to the target's
	/// velocity, so a steadily moving target is followed without lag
	double dampingRatio;
	/// N, the bound on the whole pull (default 0: three times the body's weight, lifting it at
	/// 2 g)
	double maxForce;
	int internalValue; ///< set by fmDefaultGrabDef; grab calls check it
} fmGrabDef;

/// The default grab (every member scaled from the body's weight with the world's gravity, at
/// least 9.81 m/s^2).
FM_API fmGrabDef fmDefaultGrabDef(void);

/// How attached vertices hold on (fmBody_AttachToCollider, fmBody_Weld): each by a zero-length
/// spring and dashpot, bounded like a grab's. Start from fmDefaultAttachDef(); a stiffness of 0
/// picks the default that scales with the body.
typedef struct fmAttachDef
{
	/// N/m on each vertex (default 0: the body's weight over 1 mm shared by the call's vertices,
	/// so a body hung by them sags about 1 mm; a weld takes the lighter body's weight)
	double stiffness;
	/// the dashpot against each vertex's share of the body's mass, 1 critical (default 1), on the
	/// vertex's velocity relative to its anchor's
	double dampingRatio;
	/// N, the bound on each vertex's force (default 0: none); beyond it the vertex slides
	/// away from its anchor pulled by this force, as a grab's
	double maxForce;
	int internalValue; ///< set by fmDefaultAttachDef; attach calls check it
} fmAttachDef;

/// The default attachment: the body's weight over 1 mm, critically damped, unbounded.
FM_API fmAttachDef fmDefaultAttachDef(void);

/// Attachments a body holds at most, per vertex of the body (glue and weld ends together).
#define FM_MAX_ANCHORS_PER_VERTEX 8

/// A fixed-step clock for a game loop (docs/embedding.md, "A game loop"): the game adds the real
/// time that passed each rendered frame (fmWorld_Advance), the world steps whole frames of
/// frameTime, and what is left over is where the picture stands between the last two frames
/// (alpha), for the interpolated copies (fmBody_CopyInterpolatedPositionsFloat).
typedef struct fmFixedStep
{
	double frameTime;   ///< s, one frame of the world, in [FM_MIN_SUBSTEP, FM_MAX_SUBSTEP] (1/60)
	int substeps;       ///< substeps of each frame, in [1, FM_MAX_SUBSTEPS] (1)
	int maxFrames;      ///< most frames one fmWorld_Advance steps, in [1, 1000] (4): the real
	                    ///< time beyond them is dropped, so a machine too slow for real time
	                    ///< slows the game down instead of falling further behind each frame
	double accumulator; ///< s of real time not stepped yet, in [0, frameTime) after an advance
	double alpha;       ///< accumulator / frameTime, in [0, 1): the render's interpolation factor
	int internalValue;  ///< set by fmDefaultFixedStep; fmWorld_Advance checks it
} fmFixedStep;

/// The default clock: 60 frames a second of one substep each, at most 4 a call, nothing
/// accumulated.
FM_API fmFixedStep fmDefaultFixedStep(void);

/// Health of a body after a step.
typedef struct fmBodyStats
{
	double kineticEnergy; ///< J
	double elasticEnergy; ///< J
	double gravityEnergy; ///< J, m g.(-x) summed (relative to the origin)
	fmVec3 centerOfMass;  ///< m
	double lowestY;       ///< m, lowest vertex
	int invertedTets;     ///< tets with det F <= 0
	/// J, the body's energy ledger: work done on it since creation by gravity, contacts
	/// (depenetration), kinematic targets and the caller (impulses, set positions or
	/// velocities). Kinetic plus
	/// elastic energy never exceeds its initial value plus this work (docs/robustness.md).
	double work;
	double initialEnergy; ///< J, kinetic plus elastic energy when the body was created
	/// J, the plastic work since creation: the stress times the plastic flow, summed over the
	/// tets (dissipated, and stored in hardening); work = kinetic + elastic + plasticWork + what
	/// damping took, to the steps' order (the return map's own loss shrinks with the step)
	double plasticWork;
	double plasticStrain; ///< the largest equivalent plastic strain of any tet
} fmBodyStats;

/// One finding of fmWorld_AuditContact(): the first of its kind, in body slot order.
typedef struct fmAuditFinding
{
	fmBodyId body;      ///< the edge's, vertex's or tet's body; the null id when none was found
	fmBodyId otherBody; ///< the body crossed or entered (itself for a self crossing); tet: null
	int vertex[2];      ///< crossing: the edge's vertices; inside: the vertex, -1 (user numbering)
	int index;          ///< crossing: the other's surface triangle (fmBody_GetSurface order);
	                    ///< inverted: the tet (user numbering); inside: -1
	double depth;       ///< m, inside: the vertex's distance to the surface it is inside; else 0
} fmAuditFinding;

/// What fmWorld_AuditContact() found: intersections between the bodies as they are now.
typedef struct fmContactAudit
{
	int bodies;         ///< live bodies audited
	int crossings;      ///< surface edges of one body properly crossing a surface triangle of
	                    ///< another, over both orders of every pair of bodies
	int selfCrossings;  ///< the same within each self-colliding body (fmBodyDef.selfCollision),
	                    ///< between an edge and a triangle that share no vertex
	int verticesInside; ///< surface vertices strictly inside another body's closed surface
	double deepest;     ///< m, the largest such vertex's distance to that surface (0 when none)
	int invertedTets;   ///< tets with det F <= 0, all live bodies
	fmAuditFinding firstCrossing;     ///< the first edge-triangle crossing between two bodies
	fmAuditFinding firstSelfCrossing; ///< the first crossing within one body
	fmAuditFinding firstInside;       ///< the first vertex inside another body
	fmAuditFinding firstInverted;     ///< the first inverted tet
} fmContactAudit;

/// Counters of the last world step.
typedef struct fmStepStats
{
	int steps;            ///< substeps taken
	int newtonIterations; ///< implicit: total Newton iterations
	int cgIterations;     ///< implicit: total CG iterations
	double residual;      ///< implicit: last relative residual reached
	double maxResidual;   ///< implicit: largest relative residual a step of the frame ended at
	int unconvergedSteps; ///< implicit: steps that ended above the tolerance (warning given)
	bool budgetHit;       ///< the frame budget (maxNewtonPerFrame, maxSubstepsPerFrame) was spent
	int invertedTets;     ///< all bodies, after the step
	int contacts;         ///< the last substep's contacts (fmWorld_GetContacts), the floor's too
} fmStepStats;

/// Where the last world step spent its time (ms, wall clock), for a HUD (fmWorld_GetProfile).
/// Stages are summed over the step's substeps and bodies; `step` is the whole fmWorld_Step().
typedef struct fmProfile
{
	double step;        ///< the whole step
	double forces;      ///< explicit: gravity, elastic and damping forces
	double integrate;   ///< explicit: velocities, smoothing, positions, floor
	double solve;       ///< implicit: first guess, Newton iterations (assembly, CG, line search)
	double finish;      ///< implicit: velocities, smoothing, floor friction
	double check;       ///< the frame's health check and energy ledger
	double contact;     ///< the contact stage: colliders and body-body contact (docs/contact.md)
	double broadPhase;  ///< of contact: the spatial hash's build and queries between bodies
	double narrowPhase; ///< of contact: the closest-point tests, projections and responses
} fmProfile;

/// An RGB colour as 0xRRGGBB (fmDebugDraw).
typedef uint32_t fmHexColor;

/// What fmWorld_Draw() draws, or'ed into fmDebugDraw.flags.
typedef enum fmDrawFlags
{
	fm_drawSurfaces = 1u << 0,     ///< every body's surface triangles with smooth normals
	fm_drawStress = 1u << 1,       ///< surfaces coloured by strain (fmDrawTriangles.colors)
	fm_drawTetEdges = 1u << 2,     ///< the edges of every tet (wireframe)
	fm_drawInvertedTets = 1u << 3, ///< the edges of inverted tets, in red
	fm_drawPins = 1u << 4,         ///< pinned vertices as points
	fm_drawTargets = 1u << 5,      ///< kinematic targets: points and lines to their vertices
	fm_drawFloor = 1u << 6,        ///< the floor plane
	fm_drawContacts = 1u << 7,     ///< the last substep's contacts, the floor's too
	fm_drawColliders = 1u << 8,    ///< colliders: triangles (planes through drawPlane)
	/// the fibres of anisotropic tets: a line through each one's centre along its deformed
	/// fibre F a, half the tet's size times the fibre's stretch
	fm_drawFibres = 1u << 9,
	/// surfaces coloured by plastic strain (the mean equivalent plastic strain of the tets
	/// around each vertex, the strain ramp's colours; fm_drawStress wins when both are set)
	fm_drawPlastic = 1u << 10,
	/// surfaces coloured by fracture damage (each vertex: the largest traction over strength of
	/// the tets around it, fmBody_ComputeDamage; 1, the ramp's end, tears; fm_drawStress and
	/// fm_drawPlastic win when set)
	fm_drawDamage = 1u << 11,
	fm_drawAll = 0xfffu, ///< everything above
} fmDrawFlags;

/// One body's surface for fmDebugDraw.drawTriangles: the surface vertices only (compacted),
/// in float, valid during the callback.
typedef struct fmDrawTriangles
{
	fmBodyId body;         ///< the body, or the null id for a collider
	fmColliderId collider; ///< the collider (fm_drawColliders), or the null id
	int vertexCount;
	int triangleCount;
	const float* positions; ///< 3 per vertex (m)
	const float* normals;   ///< 3 per vertex: unit, area-weighted over the vertex's triangles
	const float* colors;    ///< 3 per vertex (RGB in [0, 1]) with fm_drawStress, else NULL
	const int* indices;     ///< 3 per triangle, counter-clockwise seen from outside
	const int* vertices;    ///< vertexCount: each drawn vertex's index in the body (user's);
	                        ///< NULL for a collider
	fmHexColor color;       ///< the body's colour when colors is NULL
} fmDrawTriangles;

/// Batched debug drawing (fmWorld_Draw): the library fills arrays, the caller's callbacks draw
/// them (OpenGL, a game engine, a file). A callback left NULL is skipped. Arrays are valid
/// during the callback only. Like Box2D's b2DebugDraw, but one call per batch, not per shape.
typedef struct fmDebugDraw
{
	/// A body's surface (fm_drawSurfaces, fm_drawStress).
	void (*drawTriangles)(const fmDrawTriangles* triangles, void* context);
	/// Line segments: 6 floats each (two points) (tet edges, inverted tets, targets).
	void (*drawLines)(const float* points, int lineCount, fmHexColor color, void* context);
	/// Points: 3 floats each, @p size in pixels as a hint (pins, targets, contacts).
	void (*drawPoints)(const float* points, int pointCount, float size, fmHexColor color,
	                   void* context);
	/// The floor: the plane through @p point with unit normal @p normal.
	void (*drawPlane)(fmVec3 point, fmVec3 normal, fmHexColor color, void* context);
	unsigned flags; ///< fmDrawFlags
	void* context;  ///< passed to every callback
} fmDebugDraw;

/// A debug draw with no callbacks and the flags fm_drawSurfaces | fm_drawFloor | fm_drawTargets |
/// fm_drawColliders.
FM_API fmDebugDraw fmDefaultDebugDraw(void);

FM_C_END
