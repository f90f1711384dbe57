// Intersection-free contact between bodies inside the implicit solve (barrier_contact.c): IPC's
// barrier (Li et al. 2020) on the squared distances of vertex-triangle and edge-edge pairs of
// surfaces, its lagged smoothed friction, and the continuous collision detection that bounds
// every line-search step. The bodies of a substep are solved one after another (block
// Gauss-Seidel): the body being solved moves, every other body's surface stands where it is (the
// ones solved before it at their new positions), so each line-search step is checked against
// surfaces that do not move while it is taken, and no state the solve passes through has two
// surfaces crossing. Rules (docs/contact.md, "Barrier contact"):
// - a pair closer than dHat (the world's contact thickness) adds kappa b(s, dHat^2), s its squared
//   distance, b the log barrier (math/barrier.h), kappa = FM_BARRIER_STIFFNESS m / (h^2 dHat^2)
//   with m the mean mass of the pair's four vertices (the same from both sides: the forces the
//   two bodies feel are equal and opposite);
// - below FM_BARRIER_FLOOR dHat the barrier continues as its quadratic at that distance (finite:
//   a start already that close, from bodies made overlapping, still solves; it pushes them apart);
// - a step never takes a vertex further than the body's reach from where the step started (its
//   last motion doubled, gravity's, dHat and 2% of its size), so the surfaces gathered before the
//   solve are all a step can meet;
// - friction is lagged as in IPC: each pair within dHat at the step's start pulls against the
//   relative tangential motion of its closest points with mu lambda f0(|u|), lambda its barrier
//   force at the start, f0 the C1 blend of a spring below a slip of FM_FRICTION_SLIP_SPEED h; u
//   starts from the stretch the same pair's spring ended the last step with (clamped to the slip
//   width), so a pair that holds stays anchored and does not creep.
#pragma once

#include "body/body.h"
#include "contact/broad_phase.h"
#include "core/core.h"
#include "solver/newton.h"

struct fmWorld;

// The barrier's stiffness relative to the inertia of its pair (dimensionless): at half dHat its
// curvature is 15 times m / h^2.
#define FM_BARRIER_STIFFNESS 1.0

// Fraction of dHat below which the barrier continues as a quadratic.
#define FM_BARRIER_FLOOR 1e-3

// Fraction of dHat below which a pair counts as touching: the step bound's CCD lets it move no
// more than a tenth of its gap a step, so it could not slide or part (bodies made touching, gap
// 0). The contact stage hands such a pair to its projection as if overlapping (contact.c).
#define FM_BARRIER_TOUCHING 1e-6

// Other bodies whose primitives near a solved body keep a box each, for a quick test before a
// hash query.
#define FM_BARRIER_NEAR_BOXES 8

// A pair's four vertices: a point and a triangle (p, t0, t1, t2) or two edges (a0, a1, b0, b1),
// each a body slot and a vertex of that body.
typedef struct fmBarrierStencil
{
	int body[4];
	int vertex[4];
	bool edgeEdge;
} fmBarrierStencil;

// A pair within dHat at the last evaluation: its stencil, its closest points' weights (the
// vector between them is r = sum_j w[j] x[j]), r and its squared length.
typedef struct fmBarrierPair
{
	fmBarrierStencil stencil;
	double w[4];
	fmVec3 r;
	double d2;
} fmBarrierPair;

// A pair's lagged friction: its closest points' weights (the relative position is
// sum_j w[j] x[j]), the normal and the Coulomb limit mu lambda (N).
typedef struct fmBarrierFriction
{
	fmBarrierStencil stencil;
	double w[4];
	fmVec3 normal;
	double limit;
	double slip; // m, the slip width below which it is a spring (at least FM_FRICTION_SLIP_SPEED h)
	fmVec3 stretch; // m, the spring's stretch at the end of the body's last step (zero: new)
} fmBarrierFriction;

// A surface primitive in a broad phase: a vertex (kind 0), a surface edge (1) or a triangle (2)
// of body `body`.
typedef struct fmBarrierPrimitive
{
	int body;
	int index;
	int kind;
} fmBarrierPrimitive;

// The world's buffers for the solves' barrier terms (one solve at a time uses them).
typedef struct fmBarrierScratch
{
	// The other bodies' primitives within reach of the solved body, by kind: those of kind k are
	// [kindStart[k], kindStart[k + 1]), hashed in otherHash[k] (items counted from kindStart[k]);
	// othersBoxes[k] bodies have some, each within its box [othersLower[k][j], othersUpper[k][j]]
	// (kept for the first FM_BARRIER_NEAR_BOXES bodies: with more, none is looked at).
	fmBarrierPrimitive* others;
	fmVec3* otherLower;
	fmVec3* otherUpper;
	int otherCount, otherCapacity;
	int kindStart[4];
	fmVec3 othersLower[3][FM_BARRIER_NEAR_BOXES], othersUpper[3][FM_BARRIER_NEAR_BOXES];
	int othersBoxes[3];
	fmSpatialHash otherHash[3];
	int* meets; // the slots of the bodies whose surfaces are within reach, ascending
	int meetCount;
	int meetsCapacity;
	uint32_t* sides; // per vertex of the solved body: the sides of the others' boxes it lies past
	int sidesCapacity;
	fmBarrierPrimitive* own; // the solved body's own primitives (self-contact)
	fmVec3* ownLower;
	fmVec3* ownUpper;
	int ownCount, ownCapacity;
	fmSpatialHash ownHash;
	fmHashQuery query;
	fmBarrierPair* pairs; // the pairs within dHat at pairsAt (when pairsKnown)
	int pairCount, pairCapacity;
	double* pairsAt;
	int pairsAtCapacity;
	bool pairsKnown;
	// Every pair that can come within dHat while each coordinate of the body stays within
	// candidateRadius of candidateCentre (-1 candidates: none gathered in this step): the
	// energy, its derivatives and the step bound inside that box filter these instead of
	// searching, and gather them again around a point or segment outside it.
	// candidateSlack[k] is candidate k's distance at the centre less dHat: a candidate none of
	// whose vertices moved half of it from the centre is not within dHat.
	fmBarrierStencil* candidates;
	double* candidateSlack;
	int candidateCount, candidateCapacity, slackCapacity;
	double* candidateCentre;
	int centreCapacity;
	double candidateRadius;
	fmBarrierFriction* friction;
	int frictionCount, frictionCapacity;
	double* gradient; // the work's forces, or the step bound's segment
	int gradientCapacity;
	bool failed; // memory ran short: the solve's energy is reported non-finite
} fmBarrierScratch;

// One body's barrier term for one implicit step.
typedef struct fmBarrierContact
{
	const struct fmWorld* world;
	int slot;             // the body being solved
	double dHat, sHat;    // the barrier's reach (m) and its square
	double stiffness;     // FM_BARRIER_STIFFNESS / (h^2 sHat): kappa = stiffness * m
	double reach;         // m, the furthest a vertex may go from xStart in the step
	double slip;          // friction's slip width FM_FRICTION_SLIP_SPEED h (m)
	double cell;          // m, the broad phases' cell
	bool self;            // the body collides with itself
	bool touching;        // a pair was within dHat at the step's start
	const double* xStart; // the body's positions at the step's start
	fmBarrierScratch* scratch;
} fmBarrierContact;

// Whether the implicit solves hold bodies apart with barriers: an implicit world whose bodies can
// meet (two or more, or self-collision on).
bool fmBarrierContact_Active(const struct fmWorld* world);

// Prepare body @p slot's barrier for the step from @p xStart, whose inertial prediction is
// @p xPred and inertia term 1 / h^2 @p inertia (the barrier is scaled like the inertia term):
// its reach, the other bodies' primitives it can meet, and its lagged friction. The substep's
// contact stage must have begun (fmContact_BeginSubstep: the buffers and surface edges). False when
// memory is short. With nothing in reach and no self-collision, @p bc->scratch is NULL (no term).
// The terms use worker @p worker's scratch (fmContactState.barrier): solves running at once
// on different workers never share one.
bool fmBarrierContact_Begin(fmBarrierContact* bc, const struct fmWorld* world, int slot,
                            const double* xStart, const double* xPred, double inertia, int worker);

// The box body @p body's vertices can reach in an implicit step whose inertia term is
// @p inertia (1 / h^2), from where they stand, grown by the gap: it holds the region
// fmBarrierContact_Begin gathers other bodies' surfaces from (a surface box grown by the gap
// that misses it is not read in the step). Unbounded for a body whose prescribed displacements
// are moving it (they move it before the step begins).
void fmBarrierContact_StepBox(const struct fmWorld* world, const fmBody* body, double inertia,
                              fmVec3* lo, fmVec3* hi);

// The barrier and its friction as a term of the step's potential (energy, Hessian, products and
// the line search's step bound); absent (energy NULL) when @p bc->scratch is NULL.
fmNewtonTerm fmBarrierContact_Term(const fmBarrierContact* bc);

// The work (J) the barrier and friction did on the body over the step from xStart to @p x:
// backward Euler's forces at the end times the motion.
double fmBarrierContact_Work(const fmBarrierContact* bc, const double* x);

// Take @p body's surface box where it stands (body->contact.surfaceLower, surfaceUpper), which
// the other bodies' solves test it by: when the substep begins and after the body's own solve.
void fmBarrierContact_NoteSurface(fmBody* body);

// The surface edges of @p body (2 ints each, low vertex first), made on first use in
// body->contact; false when memory is short.
bool fmBarrierContact_Edges(fmBody* body);

// Keep, from @p body's embedded marks of the frame that ends, the bodies it was found inside.
void fmBarrierContact_NoteOverlaps(fmBody* body);

// Whether bodies @p a and @p b (slots) were found overlapping in the last frame: they meet
// through the contact stage's projection until apart (a barrier cannot separate surfaces that
// cross).
bool fmBarrierContact_Overlapping(const struct fmWorld* world, int a, int b);

// Release the scratch's buffers; safe on a zeroed one.
void fmBarrierScratch_Free(fmBarrierScratch* scratch);
