// Barrier contact inside the implicit solve (barrier_contact.h).
#include "contact/barrier_contact.h"

#include "body/fracture.h"
#include "body/loads.h"
#include "contact/barrier_pairs.h"
#include "contact/collider.h"
#include "contact/contact.h"
#include "contact/contact_response.h"
#include "contact/contact_state.h"
#include "contact/friction_anchor.h"
#include "contact/penalty.h"
#include "core/det_math.h"
#include "math/barrier.h"
#include "math/ccd.h"
#include "math/distance.h"
#include "math/geometry.h"
#include "world/world.h"

#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

// CCD stops at (1 - FM_BARRIER_ETA) of a pair's gap (additive CCD's conservative advance).
#define FM_BARRIER_ETA 0.9

// ---- the bodies' surfaces ----------------------------------------------------------------------

bool fmBarrierContact_Active(const fmWorld* w)
{
	return w->def.integrator == fm_implicit && fmContact_BodiesMeet(w);
}

// Edges as keys low * n + high: sorted, equal keys are the same edge.
static int fmKeyCompare(const void* a, const void* b)
{
	int64_t x = *(const int64_t*)a, y = *(const int64_t*)b;
	return (x > y) - (x < y);
}

bool fmBarrierContact_Edges(fmBody* b)
{
	if (b->contact.surfaceEdge != NULL)
		return true;
	const int64_t n = b->mesh.vertexCount;
	int all = 3 * b->mesh.triangleCount;
	int64_t* keys = FM_ALLOC_ARRAY(int64_t, (size_t)(all > 0 ? all : 1));
	if (keys == NULL)
		return false;
	for (int t = 0; t < b->mesh.triangleCount; ++t)
		for (int k = 0; k < 3; ++k)
		{
			int64_t a = b->mesh.surface[3 * t + k], c = b->mesh.surface[3 * t + (k + 1) % 3];
			keys[3 * t + k] = a < c ? a * n + c : c * n + a;
		}
	qsort(keys, (size_t)all, sizeof *keys, fmKeyCompare);
	int count = 0;
	for (int k = 0; k < all; ++k)
		count += k == 0 || keys[k] != keys[k - 1];
	b->contact.surfaceEdge = FM_ALLOC_ARRAY(int, 2 * (size_t)(count > 0 ? count : 1));
	if (b->contact.surfaceEdge != NULL)
	{
		int e = 0;
		for (int k = 0; k < all; ++k)
			if (k == 0 || keys[k] != keys[k - 1])
			{
				b->contact.surfaceEdge[2 * e] = (int)(keys[k] / n);
				b->contact.surfaceEdge[2 * e + 1] = (int)(keys[k] % n);
				e += 1;
			}
		b->contact.surfaceEdgeCount = count;
	}
	FM_FREE_ARRAY(keys, int64_t, (size_t)(all > 0 ? all : 1));
	return b->contact.surfaceEdge != NULL;
}

// ---- the barrier -------------------------------------------------------------------------------

static double fmPairMass(const fmWorld* w, const fmBarrierStencil* st)
{
	double m = 0.0;
	for (int k = 0; k < 4; ++k)
		m += w->bodies[st->body[k]].mesh.mass[st->vertex[k]];
	return 0.25 * m;
}

// The barrier at squared distance s (J per unit kappa) and its first and second derivatives,
// continued as the quadratic at sFloor below it.
static void fmBarrierAt(const fmBarrierContact* bc, double s, double out[3])
{
	double floor2 = FM_BARRIER_FLOOR * FM_BARRIER_FLOOR * bc->sHat;
	double at = s > floor2 ? s : floor2;
	double b0 = fmBarrier(at, bc->sHat), b1 = fmBarrier_First(at, bc->sHat);
	double b2 = fmBarrier_Second(at, bc->sHat), d = s - at;
	out[0] = b0 + b1 * d + 0.5 * b2 * d * d;
	out[1] = b1 + b2 * d;
	out[2] = b2;
}

// A pair's squared distance's gradient (12): with r the vector between the closest points
// (weights w at them), s = |r|^2 and, the closest points being where r is shortest,
// ds/dx_j = 2 w_j r (the weights' own change does not enter: the envelope theorem).
static void fmPairGradient(const fmBarrierPair* pair, double gradient[12])
{
	for (int j = 0; j < 4; ++j)
	{
		gradient[3 * j] = 2.0 * pair->w[j] * pair->r.x;
		gradient[3 * j + 1] = 2.0 * pair->w[j] * pair->r.y;
		gradient[3 * j + 2] = 2.0 * pair->w[j] * pair->r.z;
	}
}

// ---- friction ----------------------------------------------------------------------------------

// The motion of stencil point k in the step: the solved body's from xStart to @p x, another
// body's from its substep start to where it stands.
static fmVec3 fmStepMotion(const fmBarrierContact* bc, const fmBarrierStencil* st, int k,
                           const double* x)
{
	const fmBody* o = &bc->world->bodies[st->body[k]];
	int v = st->vertex[k];
	if (st->body[k] == bc->slot)
		return fmSub(fmLoad(x, v), fmLoad(bc->xStart, v));
	return fmSub(fmLoad(o->state.x, v), fmLoad(o->contact.start, v));
}

// The lagged friction of every pair within dHat at the step's start.
static bool fmLagFriction(fmBarrierContact* bc)
{
	fmBarrierScratch* s = bc->scratch;
	const fmWorld* w = bc->world;
	s->frictionCount = 0;
	if (!fmBarrierPairs_Find(bc, bc->xStart))
		return false;
	for (int k = 0; k < s->pairCount; ++k)
	{
		const fmBarrierPair* pair = &s->pairs[k];
		const fmBarrierStencil* st = &pair->stencil;
		double mu =
		    fmContactResponse_PairFriction(w, &w->bodies[st->body[0]], &w->bodies[st->body[3]]);
		double d2 = pair->d2, b[3];
		if (!(mu > 0.0) || !(d2 > 0.0))
			continue;
		fmBarrierAt(bc, d2, b);
		fmBarrierFriction f;
		f.stencil = *st;
		memcpy(f.w, pair->w, sizeof f.w);
		fmVec3 r = pair->r;
		double length = fmLength(r);
		if (!(length > 0.0))
			continue;
		f.normal = fmScale(1.0 / length, r);
		double lambda = -bc->stiffness * fmPairMass(w, st) * b[1] * 2.0 * sqrt(d2);
		f.limit = mu * fmMax(lambda, 0.0);
		// The stick spring 2 mu lambda / slip is kept no stiffer than the pair's normal stiffness
		// (the barrier's curvature in the distance): a stiffer one only stalls Newton (measured:
		// ten piled houses took 20 Newton iterations a step, against 3-5).
		double normal = bc->stiffness * fmPairMass(w, st) * (4.0 * d2 * b[2] + 2.0 * b[1]);
		f.slip = normal > 0.0 ? fmMax(bc->slip, 2.0 * f.limit / normal) : bc->slip;
		// ... and no stiffer than FM_FRICTION_STIFFNESS times the pair's inertia m / h^2.
		double inertia = bc->stiffness * bc->sHat / FM_BARRIER_STIFFNESS * fmPairMass(w, st);
		f.slip = fmMax(f.slip, 2.0 * f.limit / (FM_FRICTION_STIFFNESS * inertia));
		f.stretch = fmFrictionAnchor_Carried(bc, &f);
		if (!fmGrowArray((void**)&s->friction, &s->frictionCapacity, s->frictionCount,
		                 s->frictionCount + 1, sizeof *s->friction))
			return false;
		s->friction[s->frictionCount++] = f;
	}
	return true;
}

// Friction's slip u of @p f at @p x: FM_FRICTION_GAIN times the tangential relative motion, plus
// the stretch carried over (penalty.h).
static fmVec3 fmFrictionSlip(const fmBarrierContact* bc, const fmBarrierFriction* f,
                             const double* x)
{
	fmVec3 r = f->stretch;
	for (int j = 0; j < 4; ++j)
		r = fmMulAdd(r, FM_FRICTION_GAIN * f->w[j], fmStepMotion(bc, &f->stencil, j, x));
	return fmMulAdd(r, -fmDot(r, f->normal), f->normal);
}

// f0 of the smoothed friction (IPC eq. 15 in displacement form) and f1 = f0' over y.
static double fmFrictionF0(double y, double eps)
{
	return y < eps ? -y * y * y / (3.0 * eps * eps) + y * y / eps + eps / 3.0 : y;
}

static double fmFrictionF1OverY(double y, double eps)
{
	return y < eps ? (2.0 - y / eps) / eps : 1.0 / y;
}

// ---- the term ----------------------------------------------------------------------------------

static double fmBarrierEnergy(const void* context, const double* x, const double* xStart,
                              double* gradient)
{
	(void)xStart;
	const fmBarrierContact* bc = context;
	fmBarrierScratch* s = bc->scratch;
	if (s->failed || !fmBarrierPairs_Find(bc, x))
	{
		s->failed = true;
		return NAN;
	}
	double energy = 0.0;
	for (int k = 0; k < s->pairCount; ++k)
	{
		const fmBarrierPair* pair = &s->pairs[k];
		const fmBarrierStencil* st = &pair->stencil;
		double g[12], b[3];
		if (gradient != NULL)
			fmPairGradient(pair, g);
		double kappa = bc->stiffness * fmPairMass(bc->world, st);
		fmBarrierAt(bc, pair->d2, b);
		energy += kappa * b[0];
		for (int j = 0; gradient != NULL && j < 4; ++j)
			if (st->body[j] == bc->slot)
				for (int e = 0; e < 3; ++e)
					gradient[3 * st->vertex[j] + e] += kappa * b[1] * g[3 * j + e];
	}
	for (int k = 0; k < s->frictionCount; ++k)
	{
		const fmBarrierFriction* f = &s->friction[k];
		fmVec3 u = fmFrictionSlip(bc, f, x);
		double y = fmLength(u);
		energy += f->limit * fmFrictionF0(y, f->slip) / FM_FRICTION_GAIN; // force: limit f1
		fmVec3 pull = fmScale(f->limit * fmFrictionF1OverY(y, f->slip), u);
		for (int j = 0; gradient != NULL && j < 4; ++j)
			if (f->stencil.body[j] == bc->slot)
			{
				double* gj = gradient + 3 * f->stencil.vertex[j];
				gj[0] += f->w[j] * pull.x, gj[1] += f->w[j] * pull.y, gj[2] += f->w[j] * pull.z;
			}
	}
	return energy;
}

// Adds c a b^T (3x3) to the block of (row, column); with @p pattern NULL only diagonal blocks
// exist (9 doubles a vertex). False when the pattern has no such block.
static bool fmAddOuter(const fmBsrMatrix* pattern, double* values, int row, int column, double c,
                       const double* a, const double* b)
{
	int slot = pattern == NULL ? (row == column ? row : -1)
	           : row == column ? pattern->diagonal[row]
	                           : fmBsr_Find(pattern, row, column);
	if (slot < 0)
		return false;
	double* out = values + 9 * (size_t)slot;
	for (int r = 0; r < 3; ++r)
		for (int q = 0; q < 3; ++q)
			out[3 * r + q] += c * a[r] * b[q];
	return true;
}

// Whether every pair of the solved body's stencil points has a block in @p pattern.
static bool fmCoupled(const fmBarrierContact* bc, const fmBsrMatrix* pattern,
                      const fmBarrierStencil* st)
{
	for (int i = 0; i < 4; ++i)
		for (int j = 0; j < 4; ++j)
			if (st->body[i] == bc->slot && st->body[j] == bc->slot &&
			    st->vertex[i] != st->vertex[j] &&
			    (pattern == NULL || fmBsr_Find(pattern, st->vertex[i], st->vertex[j]) < 0))
				return false;
	return true;
}

// A pair's Hessian, kappa (b'' + b' / 2s) grad s grad s^T: the distance's normal curvature
// alone, positive on (0, dHat) (design: IPC's full local Hessian, projected, keeps mostly this).
// Where the pattern lacks a coupling block the diagonal blocks alone go in (still PSD).
static void fmPairHessian(const fmBarrierContact* bc, const fmBarrierPair* pair,
                          const fmBsrMatrix* pattern, double* values)
{
	const fmBarrierStencil* st = &pair->stencil;
	double g[12], b[3], d2 = pair->d2;
	fmPairGradient(pair, g);
	fmBarrierAt(bc, d2, b);
	double c = bc->stiffness * fmPairMass(bc->world, st) * fmMax(0.0, b[2] + b[1] / (2.0 * d2));
	bool coupled = fmCoupled(bc, pattern, st);
	for (int i = 0; i < 4; ++i)
		for (int j = 0; j < 4; ++j)
			if (st->body[i] == bc->slot && st->body[j] == bc->slot &&
			    (i == j || (coupled && st->vertex[i] != st->vertex[j])))
				fmAddOuter(pattern, values, st->vertex[i], st->vertex[j], c, g + 3 * i, g + 3 * j);
}

// Friction's 3x3 inner matrix M (the Hessian of limit f0(|u|) / gain in the relative position r,
// u's derivative being FM_FRICTION_GAIN P): gain (f1/y P + c u u^T), PSD.
static void fmFrictionInner(const fmBarrierContact* bc, const fmBarrierFriction* f, const double* x,
                            double m[9])
{
	fmVec3 u = fmFrictionSlip(bc, f, x), n = f->normal;
	double y = fmLength(u), eps = f->slip;
	double a = fmFrictionF1OverY(y, eps);
	double c = y <= 0.0 ? 0.0 : y < eps ? -1.0 / (y * eps * eps) : -1.0 / (y * y * y);
	double nv[3] = {n.x, n.y, n.z}, uv[3] = {u.x, u.y, u.z};
	for (int r = 0; r < 3; ++r)
		for (int q = 0; q < 3; ++q)
			m[3 * r + q] =
			    FM_FRICTION_GAIN * f->limit * (a * ((r == q) - nv[r] * nv[q]) + c * uv[r] * uv[q]);
}

static void fmBarrierHessian(const void* context, const double* x, const fmBsrMatrix* pattern,
                             double* values)
{
	const fmBarrierContact* bc = context;
	fmBarrierScratch* s = bc->scratch;
	if (s->failed || !fmBarrierPairs_Find(bc, x))
	{
		s->failed = true;
		return;
	}
	for (int k = 0; k < s->pairCount; ++k)
		fmPairHessian(bc, &s->pairs[k], pattern, values);
	for (int k = 0; k < s->frictionCount; ++k)
	{
		const fmBarrierFriction* f = &s->friction[k];
		double m[9];
		fmFrictionInner(bc, f, x, m);
		bool coupled = fmCoupled(bc, pattern, &f->stencil);
		for (int i = 0; i < 4; ++i)
			for (int j = 0; j < 4; ++j)
			{
				int vi = f->stencil.vertex[i], vj = f->stencil.vertex[j];
				if (f->stencil.body[i] != bc->slot || f->stencil.body[j] != bc->slot ||
				    !(i == j || (coupled && vi != vj)))
					continue;
				int slot = pattern == NULL ? vi
				           : vi == vj      ? pattern->diagonal[vi]
				                           : fmBsr_Find(pattern, vi, vj);
				double* out = values + 9 * (size_t)slot;
				for (int e = 0; e < 9; ++e)
					out[e] += f->w[i] * f->w[j] * m[e];
			}
	}
}

static void fmBarrierProduct(const void* context, const double* x, const double* dx, double* y)
{
	const fmBarrierContact* bc = context;
	fmBarrierScratch* s = bc->scratch;
	if (s->failed || !fmBarrierPairs_Find(bc, x))
	{
		s->failed = true;
		return;
	}
	for (int k = 0; k < s->pairCount; ++k)
	{
		const fmBarrierPair* pair = &s->pairs[k];
		const fmBarrierStencil* st = &pair->stencil;
		double g[12], b[3], d2 = pair->d2;
		fmPairGradient(pair, g);
		fmBarrierAt(bc, d2, b);
		double c = bc->stiffness * fmPairMass(bc->world, st) * fmMax(0.0, b[2] + b[1] / (2.0 * d2));
		double along = 0.0;
		for (int j = 0; j < 4; ++j)
			if (st->body[j] == bc->slot)
				for (int e = 0; e < 3; ++e)
					along += g[3 * j + e] * dx[3 * st->vertex[j] + e];
		for (int j = 0; j < 4; ++j)
			if (st->body[j] == bc->slot)
				for (int e = 0; e < 3; ++e)
					y[3 * st->vertex[j] + e] += c * along * g[3 * j + e];
	}
	for (int k = 0; k < s->frictionCount; ++k)
	{
		const fmBarrierFriction* f = &s->friction[k];
		double m[9], r[3] = {0.0, 0.0, 0.0};
		fmFrictionInner(bc, f, x, m);
		for (int j = 0; j < 4; ++j)
			if (f->stencil.body[j] == bc->slot)
				for (int e = 0; e < 3; ++e)
					r[e] += f->w[j] * dx[3 * f->stencil.vertex[j] + e];
		for (int j = 0; j < 4; ++j)
			if (f->stencil.body[j] == bc->slot)
				for (int e = 0; e < 3; ++e)
					y[3 * f->stencil.vertex[j] + e] +=
					    f->w[j] * (m[3 * e] * r[0] + m[3 * e + 1] * r[1] + m[3 * e + 2] * r[2]);
	}
}

// ---- the step bound ----------------------------------------------------------------------------

// The largest t <= @p t keeping every free coordinate of the body within the reach of xStart.
static double fmReachBound(const fmBarrierContact* bc, const double* x, const double* dx, double t)
{
	const fmBody* b = &bc->world->bodies[bc->slot];
	for (int k = 0; k < 3 * b->mesh.vertexCount; ++k)
	{
		double to = dx[k] > 0.0   ? bc->xStart[k] + bc->reach - x[k]
		            : dx[k] < 0.0 ? x[k] - (bc->xStart[k] - bc->reach)
		                          : INFINITY;
		double step = fabs(dx[k]);
		if (step > 0.0 && to < t * step)
			t = fmMax(0.0, to / step);
	}
	return t;
}

// The earliest time of impact in [0, t] of the candidate @p st along @p dx from @p x: additive
// CCD, which stops at (1 - eta) of the gap, for pairs whose sides' boxes swept to t come within
// dHat.
static double fmEarlierImpact(const fmBarrierContact* bc, const fmBarrierStencil* st,
                              const double* x, const double* dx, double t)
{
	fmVec3 pts[4], motion[4], swept[4];
	fmBarrierPairs_Points(bc, st, x, pts);
	for (int j = 0; j < 4; ++j)
	{
		motion[j] = st->body[j] == bc->slot ? fmLoad(dx, st->vertex[j]) : fmMakeVec3(0, 0, 0);
		swept[j] = fmScale(t, motion[j]);
	}
	if (t <= 0.0 || fmBarrierPairs_SidesApart(bc, st, pts, swept))
		return t;
	return fmMin(t, fmCcd_Additive(st->edgeEdge, pts, motion, 0.0, FM_BARRIER_ETA, t));
}

// The largest fraction of the step @p dx from @p x that no pair crosses (additive CCD, each
// pair kept at a tenth of its gap or more) and that stays within the body's reach, over
// candidates that cover the segment.
static double fmBarrierStepBound(const void* context, const double* x, const double* dx)
{
	const fmBarrierContact* bc = context;
	fmBarrierScratch* s = bc->scratch;
	double t = fmReachBound(bc, x, dx, 1.0);
	const int n3 = 3 * bc->world->bodies[bc->slot].mesh.vertexCount;
	bool room = fmGrowArray((void**)&s->gradient, &s->gradientCapacity, 0, n3, sizeof(double));
	for (int k = 0; room && k < n3; ++k)
		s->gradient[k] = t * dx[k]; // the segment (the work's buffer, free here)
	if (!room || !fmBarrierPairs_Cover(bc, x, s->gradient))
	{
		s->failed = true;
		return 0.0;
	}
	for (int k = 0; k < n3; ++k)
		s->gradient[k] += x[k]; // the segment's end
	for (int k = 0; k < s->candidateCount; ++k)
		if (!fmBarrierPairs_SurelyFar(bc, k, x) || !fmBarrierPairs_SurelyFar(bc, k, s->gradient))
			t = fmEarlierImpact(bc, &s->candidates[k], x, dx, t);
	return t;
}

fmNewtonTerm fmBarrierContact_Term(const fmBarrierContact* bc)
{
	fmNewtonTerm term;
	memset(&term, 0, sizeof term);
	if (bc->scratch == NULL)
		return term;
	term.context = bc;
	term.energy = fmBarrierEnergy;
	term.addHessian = fmBarrierHessian;
	term.addProduct = fmBarrierProduct;
	term.stepBound = fmBarrierStepBound;
	return term;
}

// ---- the step ----------------------------------------------------------------------------------

// The body's reach in a step whose fastest vertex moves @p motion by inertia alone: twice that
// and gravity's (g / inertia), dHat and 2% of its size.
static double fmReachOf(const fmWorld* w, const fmBody* b, double motion, double inertia,
                        double dHat)
{
	double g = fmLength(w->def.gravity);
	return 2.0 * (motion + g / inertia) + dHat + 0.02 * b->mesh.restSize;
}

static double fmStepReach(const fmWorld* w, const fmBody* b, const double* xStart,
                          const double* xPred, double inertia, double dHat)
{
	double motion = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		motion = fmMax(motion, fmLength(fmSub(fmLoad(xPred, i), fmLoad(xStart, i))));
	return fmReachOf(w, b, motion, inertia, dHat);
}

// The box around @p x's vertices.
static void fmVertexBox(const fmBody* b, const double* x, fmVec3* lo, fmVec3* hi)
{
	fmVec3 l = fmMakeVec3(INFINITY, INFINITY, INFINITY), u = fmScale(-1.0, l);
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		fmVec3 p = fmLoad(x, i);
		l = fmMakeVec3(fmMin(l.x, p.x), fmMin(l.y, p.y), fmMin(l.z, p.z));
		u = fmMakeVec3(fmMax(u.x, p.x), fmMax(u.y, p.y), fmMax(u.z, p.z));
	}
	*lo = l;
	*hi = u;
}

// The step box's margin relative to its growth: a bound never tighter than Begin's region
// (whose prediction x + h v rounds differently from h |v|).
#define FM_STEP_BOX_MARGIN 1e-9

void fmBarrierContact_StepBox(const fmWorld* w, const fmBody* b, double inertia, fmVec3* lo,
                              fmVec3* hi)
{
	if (fmLoads_Moving(b))
	{
		*lo = fmMakeVec3(-INFINITY, -INFINITY, -INFINITY);
		*hi = fmScale(-1.0, *lo);
		return;
	}
	// The inertial prediction's motion as the implicit step makes it (x + h v, h = 1 / sqrt of
	// the inertia term; pinned axes stay), to the margin's rounding.
	const double lead = 1.0 / sqrt(inertia);
	double motion = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
	{
		double d[3];
		for (int e = 0; e < 3; ++e)
			d[e] = fmIsDofPinned(&b->state, 3 * i + e) ? 0.0 : lead * b->state.v[3 * i + e];
		motion = fmMax(motion, fmLength(fmMakeVec3(d[0], d[1], d[2])));
	}
	double dHat = fmContact_Thickness(w);
	fmVertexBox(b, b->state.x, lo, hi);
	// (x + h v) - x rounds to the ulps of x: the margin covers them too.
	double far = fmMax(fmMax(fmMax(fabs(lo->x), fabs(lo->y)), fmMax(fabs(lo->z), fabs(hi->x))),
	                   fmMax(fabs(hi->y), fabs(hi->z)));
	double grow = (fmReachOf(w, b, motion, inertia, dHat) + dHat) * (1.0 + FM_STEP_BOX_MARGIN) +
	              8.0 * DBL_EPSILON * far;
	*lo = fmSub(*lo, fmMakeVec3(grow, grow, grow));
	*hi = fmAdd(*hi, fmMakeVec3(grow, grow, grow));
}

// The mean length of the body's surface edges at rest (the broad phases' cell).
static double fmMeanEdge(const fmBody* b)
{
	double sum = 0.0;
	for (int e = 0; e < b->contact.surfaceEdgeCount; ++e)
		sum += fmLength(fmSub(fmLoad(b->mesh.x0, b->contact.surfaceEdge[2 * e]),
		                      fmLoad(b->mesh.x0, b->contact.surfaceEdge[2 * e + 1])));
	return b->contact.surfaceEdgeCount > 0 ? sum / b->contact.surfaceEdgeCount : b->mesh.restSize;
}

bool fmBarrierContact_Begin(fmBarrierContact* bc, const fmWorld* w, int slot, const double* xStart,
                            const double* xPred, double inertia, int worker)
{
	memset(bc, 0, sizeof *bc);
	const fmBody* b = &w->bodies[slot];
	fmContactState* state = w->contactState;
	if (state == NULL || b->contact.surfaceEdge == NULL)
		return false;
	bc->world = w;
	bc->slot = slot;
	bc->dHat = fmContact_Thickness(w);
	bc->sHat = bc->dHat * bc->dHat;
	if (!(bc->sHat > 0.0))
		return true;
	bc->stiffness = FM_BARRIER_STIFFNESS * inertia / bc->sHat;
	bc->reach = fmStepReach(w, b, xStart, xPred, inertia, bc->dHat);
	bc->slip = FM_FRICTION_SLIP_SPEED / sqrt(inertia);
	bc->cell = fmMax(2.0 * fmMeanEdge(b), 2.0 * bc->dHat);
	bc->self = fmFracture_MeetsItself(b);
	bc->xStart = xStart;
	bc->scratch = &state->barrier[worker];
	bc->scratch->failed = false;
	bc->scratch->pairsKnown = false;
	// The region the body can reach in the step, and the other primitives in it.
	fmVec3 lo, hi;
	fmVertexBox(b, xStart, &lo, &hi);
	double grow = bc->reach + bc->dHat;
	if (!fmBarrierPairs_GatherOthers(bc, fmSub(lo, fmMakeVec3(grow, grow, grow)),
	                                 fmAdd(hi, fmMakeVec3(grow, grow, grow))))
		return false;
	if (bc->scratch->otherCount == 0 && !bc->self)
	{
		bc->scratch = NULL;
		return true;
	}
	// The candidates cover the path to the inertial prediction (where the first guess and, in
	// motion, the first iterations lie), not only the start: one gather a step, not two.
	fmBarrierScratch* s = bc->scratch;
	const int n3 = 3 * b->mesh.vertexCount;
	s->candidateCount = -1;
	if (!fmGrowArray((void**)&s->gradient, &s->gradientCapacity, 0, n3, sizeof(double)))
		return false;
	for (int k = 0; k < n3; ++k)
		s->gradient[k] = xPred[k] - xStart[k]; // (the work's buffer, free here)
	if (!fmBarrierPairs_Cover(bc, xStart, s->gradient))
		return false;
	bool ok = fmLagFriction(bc);
	bc->touching = ok && bc->scratch->pairCount > 0;
	return ok;
}

double fmBarrierContact_Work(const fmBarrierContact* bc, const double* x)
{
	if (bc->scratch == NULL)
		return 0.0;
	const fmBody* b = &bc->world->bodies[bc->slot];
	const int n3 = 3 * b->mesh.vertexCount;
	fmBarrierScratch* s = bc->scratch;
	if (!fmGrowArray((void**)&s->gradient, &s->gradientCapacity, 0, n3, sizeof(double)))
		return 0.0;
	memset(s->gradient, 0, sizeof(double) * (size_t)n3);
	fmBarrierEnergy(bc, x, bc->xStart, s->gradient);
	double work = 0.0;
	for (int k = 0; k < n3; ++k)
		work -= s->gradient[k] * (x[k] - bc->xStart[k]);
	return work;
}

void fmBarrierContact_NoteSurface(fmBody* b)
{
	fmVec3 l = fmMakeVec3(INFINITY, INFINITY, INFINITY), u = fmScale(-1.0, l);
	for (int k = 0; k < b->contact.surfaceVertexCount; ++k)
	{
		fmVec3 q = fmLoad(b->state.x, b->contact.surfaceVertex[k]);
		l = fmMakeVec3(fmMin(l.x, q.x), fmMin(l.y, q.y), fmMin(l.z, q.z));
		u = fmMakeVec3(fmMax(u.x, q.x), fmMax(u.y, q.y), fmMax(u.z, q.z));
	}
	b->contact.surfaceLower = l;
	b->contact.surfaceUpper = u;
}

void fmBarrierContact_NoteOverlaps(fmBody* b)
{
	int count = 0;
	memset(b->contact.overlapWith, 0, sizeof b->contact.overlapWith);
	for (int i = 0; i < b->mesh.vertexCount && count < FM_OVERLAP_SLOTS; ++i)
	{
		int holder = b->contact.embeddedHolder[i];
		bool known = holder == 0;
		for (int k = 0; k < count && !known; ++k)
			known = b->contact.overlapWith[k] == holder;
		if (!known)
			b->contact.overlapWith[count++] = holder;
	}
}

static bool fmOverlapsOne(const fmBody* b, int other)
{
	for (int k = 0; k < FM_OVERLAP_SLOTS; ++k)
		if (b->contact.overlapWith[k] == other + 1)
			return true;
	return false;
}

bool fmBarrierContact_Overlapping(const fmWorld* w, int a, int b)
{
	return fmOverlapsOne(&w->bodies[a], b) || fmOverlapsOne(&w->bodies[b], a);
}

void fmBarrierScratch_Free(fmBarrierScratch* s)
{
	FM_FREE_ARRAY(s->others, fmBarrierPrimitive, s->otherCapacity);
	FM_FREE_ARRAY(s->otherLower, fmVec3, s->otherCapacity);
	FM_FREE_ARRAY(s->otherUpper, fmVec3, s->otherCapacity);
	FM_FREE_ARRAY(s->own, fmBarrierPrimitive, s->ownCapacity);
	FM_FREE_ARRAY(s->ownLower, fmVec3, s->ownCapacity);
	FM_FREE_ARRAY(s->ownUpper, fmVec3, s->ownCapacity);
	for (int kind = 0; kind < 3; ++kind)
		fmSpatialHash_Free(&s->otherHash[kind]);
	FM_FREE_ARRAY(s->meets, int, s->meetsCapacity);
	FM_FREE_ARRAY(s->sides, uint32_t, s->sidesCapacity);
	fmSpatialHash_Free(&s->ownHash);
	fmHashQuery_Free(&s->query);
	FM_FREE_ARRAY(s->pairs, fmBarrierPair, s->pairCapacity);
	FM_FREE_ARRAY(s->pairsAt, double, s->pairsAtCapacity);
	FM_FREE_ARRAY(s->friction, fmBarrierFriction, s->frictionCapacity);
	FM_FREE_ARRAY(s->gradient, double, s->gradientCapacity);
	FM_FREE_ARRAY(s->candidates, fmBarrierStencil, s->candidateCapacity);
	FM_FREE_ARRAY(s->candidateSlack, double, s->slackCapacity);
	FM_FREE_ARRAY(s->candidateCentre, double, s->centreCapacity);
	memset(s, 0, sizeof *s);
}
