// The implicit step's contact penalty (penalty.c): inside the Newton solve, each surface vertex
// closer than the gap to a collider, or to the frozen plane of another body's surface near it
// (and each surface edge closer than the gap to its frozen edge plane, fmEdgePlane), adds the
// energy k/2 (gap - d)^2, with d the signed distance and k = kappa m / h^2 (a stiffness that scales
// with the step's own inertia term), its gradient and its Gauss-Newton Hessian k n n^T. Friction
// against colliders is in the solve too, lagged one step as in IPC (Li et al. 2020): a vertex that
// pressed on a collider with normal force lambda in the last step adds D = mu lambda f0(|u|), u its
// tangential motion relative to the collider's surface (times FM_FRICTION_GAIN) plus the stretch
// the last step ended with,
// f0 the C1 blend of a stiff spring below a slip of FM_FRICTION_SLIP_SPEED h and |u| above it:
// static friction holds without creeping (the stretch carried over anchors it), sliding friction
// is Coulomb's. A stick collider's contact (fmColliderDef.stick) is the limit of infinite mu: the
// spring k/2 |u|^2 at the normal penalty's k = kappa m / h^2, with no Coulomb limit. The contact
// stage after the solve then removes what penetration is left and applies friction to new contacts
// (contact.c).
#pragma once

#include "body/body.h"
#include "contact/collider.h"
#include "solver/bsr.h"
#include "solver/newton.h"

// A surface edge's frozen plane for one implicit step (in body->edgePlanes; the step no longer
// makes them since the barrier, barrier_contact.h: the term and its tests remain): the edge's point
// (1 - s) x[a] + s x[b], closest to another body's edge, is kept the thickness in front of the
// plane n . x = offset through that edge's point, with the same penalty as a vertex (its mass the
// edge point's, (1 - s) m[a] + s m[b]). Where two bodies' edges cross, vertex-triangle planes alone
// let coarse meshes pass through each other.
typedef struct fmEdgePlane
{
	int a, b;      // the edge's vertices
	double s;      // the point's place along the edge, in (0, 1)
	fmVec3 normal; // unit, away from the other body's edge
	double offset; // n . (the other edge's closest point) (m)
} fmEdgePlane;

// Stiffness of the penalty relative to the inertia term m / h^2 (dimensionless): a vertex
// resting on a collider under its own weight sinks g h^2 / kappa into it.
#define FM_PENALTY_KAPPA 100.0

typedef struct fmContactPenalty
{
	const fmCollider* colliders; // the world's collider slots
	int colliderCount;           // slots (unused ones are skipped)
	double stiffness;            // kappa / h^2 (1/s^2): k = stiffness * m
	double thickness;            // m, the gap kept from the planes of other bodies
	                             // (body->contactPlane; no longer made by the step), and the
	                             // colliders' barrier's reach dHat
	const double* xStart;        // 3n: positions at the start of the step (friction's anchors)
	double step;                 // s, the step (h)
	const fmBody* body;          // the body being solved
	bool barrier;                // colliders hold the body off with the barrier (below), not
	                             // the penalty, and bound the line search's steps
	const double* gap;           // n: the vertices' collider gaps at xStart
	                             // (fmContactPenalty_Prepare; NULL: every vertex is queried)
	const double* sink;          // n: how deep inside a collider each vertex may stay in the
	                             // step, <= 0 (fmContactPenalty_Prepare; NULL: 0)
} fmContactPenalty;

// The colliders' barrier (fmContact_ColliderBarrier): a surface vertex at signed distance d
// from a collider, closer than dHat, adds kappa G(d), G(d) = b(d^2, dHat^2) the log barrier of
// math/barrier.h on its squared distance, continued as its quadratic below FM_BARRIER_FLOOR dHat
// (finite inside), and
// kappa = FM_BARRIER_STIFFNESS m / (h^2 dHat^2) as between bodies (barrier_contact.h). Its
// gradient is kappa G'(d) n and its Gauss-Newton Hessian kappa G''(d) n n^T. Every line-search
// step keeps each vertex outside at a tenth of its distance or more: convex shapes bound the
// step by the distance's tangent (a convex function lies above it), meshes by the distance
// itself (a distance moves no faster than the point). No vertex enters a collider in the solve.
// A vertex that starts inside one (made there, or a collider moved or set into it) is held at
// d - s instead of d, s <= 0 its sink: as deep as it started less what the floor's depenetration
// speed (fmFloorDef.maxDepenetrationSpeed) and the collider's own push toward it take out in the
// step, so it comes out at that speed, as from under the floor, not at once (which catapulted a
// body made half inside a collider, or crushed it flat with its tets inside out). A vertex has
// one sink, its deepest collider's, held against every collider it meets.

// The colliders' barrier push on a vertex at signed distance @p d (m) for reach @p dHat (m)
// over a step @p h (s): the normal impulse per unit mass (m/s), kappa |G'(d)| h / m; 0 from
// dHat on.
double fmColliderBarrier_Push(double d, double dHat, double h);

// Friction's slip speed (m/s): the spring of static friction stretches at most this speed times
// h before the contact slides (its slip width).
#define FM_FRICTION_SLIP_SPEED 1e-2

// The stiffest static friction spring 2 mu lambda / eps on the Coulomb floor and between bodies,
// over the inertia term m / h^2 (colliders: FM_PENALTY_KAPPA, their push's own stiffness): its
// slip width eps is widened to keep it there. (That is the spring on the stretch; a step's own
// motion sees FM_FRICTION_GAIN times it, the dashpot included.) With the stretch anchored a softer
// spring costs no creep, only a static offset within the slip width, and Newton fewer iterations
// (measured: the house on a Coulomb floor took 4.3 times the old frame time at 100, 1.7 at 10
// and 1.4 at 3). Against colliders, whose push lambda can be thousands of times the weight while
// they drive a body, a spring that soft lets the slip width grow to metres: they keep their
// penalty's cap.
#define FM_FRICTION_STIFFNESS 3.0

// The slip's gain on the step's own motion: u = stretch + FM_FRICTION_GAIN d, d the step's
// tangential motion and the stretch carried over (FM_FRICTION_STRIDE) moving by d alone: a
// spring to where the contact is anchored (no creep) and a dashpot beside it as strong as the
// spring on one step's motion (the lagged friction's own damping: without it a stack rocks on
// its friction springs), both within the Coulomb limit.
#define FM_FRICTION_GAIN 2.0

// Before the solve: each surface vertex's distance to the nearest collider it meets at the
// step's start, and its sink (above) for the depenetration speed @p speed (m/s), into
// body->contact.colliderGap (when the body has its contact arrays). A distance moves no faster
// than the point: while a vertex is closer to its start than that gap less the barrier's reach
// (the penalty's: 0), no collider is within reach of it, and the energy, its derivatives and the
// step bound skip its collider queries.
void fmContactPenalty_Prepare(fmContactPenalty* penalty, fmBody* body, double speed);

// Vertex @p i's sink in the step (m, <= 0; 0 without fmContactPenalty_Prepare's).
double fmContactPenalty_Sink(const fmBody* body, int i);

// Whether a surface vertex was within the barrier's reach of a collider (the penalty's: on or
// inside one) at the step's start, by the gaps fmContactPenalty_Prepare found.
bool fmContactPenalty_Touches(const fmContactPenalty* penalty, const fmBody* body);

// The penalty's energy at @p x (J), with its gradient added to @p gradient when not NULL.
double fmContactPenalty_Energy(const fmContactPenalty* penalty, const fmBody* body, const double* x,
                               double* gradient);

// The friction force (N) on vertex @p i at positions @p x (zero where it has none).
fmVec3 fmContactFriction_Force(const fmBody* body, int i, const double* x, const double* xStart,
                               double step);

// The stretch of vertex @p i's static friction spring at positions @p x (m, its slip clamped to
// the slip width: what a sliding contact carries into the next step; zero where it has none).
fmVec3 fmContactFriction_Stretch(const fmBody* body, int i, const double* x, const double* xStart,
                                 double step);

// The penalty as a term of the implicit step's potential (energy, Hessian, products) of
// @p penalty->body, for fmNewtonProblem.contact; @p penalty must outlive the solve.
fmNewtonTerm fmContactPenalty_Term(const fmContactPenalty* penalty);

// The work (J) the penalty's push did on the body over a step from @p xStart to its positions:
// the forces at the end (backward Euler's) times the motion, its positive part.
double fmContactPenalty_Work(const fmContactPenalty* penalty, const fmBody* body,
                             const double* xStart);

// Its Gauss-Newton Hessian k (w w^T) (x) n n^T added into the blocks of @p pattern (9 doubles a
// block, an edge's term coupling its two vertices); with a NULL @p pattern, one block per vertex
// and the diagonal blocks only (a preconditioner's).
void fmContactPenalty_AddHessian(const fmContactPenalty* penalty, const fmBody* body,
                                 const double* x, const fmBsrMatrix* pattern, double* values);

// y += the Hessian at @p at times @p dx (the matrix-free product).
void fmContactPenalty_AddProduct(const fmContactPenalty* penalty, const fmBody* body,
                                 const double* at, const double* dx, double* y);
