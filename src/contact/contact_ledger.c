// The contact stage's entries in the energy ledger (contact_ledger.h).
#include "contact/contact_ledger.h"

#include "core/core.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "fem/nodal_pressure.h"
#include "material/material.h"

#include <string.h>

// Swap the state (positions and velocities) of body @p slot's logged vertices with their
// state before the stage.
static void fmSwapLoggedStates(fmWorld* w, fmContactState* s, int slot)
{
	fmBody* b = &w->bodies[slot];
	for (int k = 0; k < s->loggedCount; ++k)
	{
		fmLoggedVertex* t = &s->logged[k];
		if (t->body != slot)
			continue;
		fmVec3 x = fmLoad(b->state.x, t->vertex), v = fmLoad(b->state.v, t->vertex);
		fmStore(b->state.x, t->vertex, t->x);
		fmStore(b->state.v, t->vertex, t->v);
		t->x = x;
		t->v = v;
	}
}

// Elastic energy (J) and power sum v . f (W) of the tets in @p tets: the parts of a body's
// energy and of symplectic Euler's shadow term that a change of their vertices changes.
static void fmTetsEnergy(const fmBody* b, const int* tets, int count, double* energy, double* power)
{
	*energy = *power = 0.0;
	for (int k = 0; k < count; ++k)
	{
		int t = tets[k];
		fmMat3 F = fmTetDeformation(&b->mesh, b->state.x, t), P;
		double V0 = b->mesh.restVolume[t];
		*energy += V0 * fmTetEvaluate(&b->mesh, t, &F, &P, NULL, false);
		fmMat3 H = fmMatMulT(&P, &b->mesh.DmInv[t]);
		fmVec3 sum = {0.0, 0.0, 0.0};
		for (int a = 1; a < 4; ++a)
		{
			fmVec3 fa = fmScale(-V0, fmColumn(&H, a - 1));
			sum = fmAdd(sum, fa);
			*power += fmDot(fa, fmLoad(b->state.v, b->mesh.tets[4 * t + a]));
		}
		*power -= fmDot(sum, fmLoad(b->state.v, b->mesh.tets[4 * t]));
	}
}

// The same over a whole body (springs, or the nodal pressure's patches).
static bool fmSpringEnergyPower(fmContactState* s, const fmBody* b, double* energy, double* power)
{
	int n3 = 3 * b->mesh.vertexCount;
	if (!fmGrowArray((void**)&s->forces, &s->forceCapacity, 0, n3, sizeof(double)))
		return false;
	memset(s->forces, 0, sizeof(double) * (size_t)n3);
	*energy = fmAddElasticForces(&b->mesh, b->state.x, s->forces);
	*power = 0.0;
	for (int k = 0; k < n3; ++k)
		*power += s->forces[k] * b->state.v[k];
	return true;
}

// The tets around body @p slot's logged vertices into s->tets; returns how many (-1 when
// memory is short).
static int fmTetsAroundLogged(fmWorld* w, fmContactState* s, int slot)
{
	fmBody* b = &w->bodies[slot];
	int count = 0;
	for (int k = 0; k < s->loggedCount; ++k)
	{
		int i = s->logged[k].vertex;
		if (s->logged[k].body != slot)
			continue;
		for (int e = b->mesh.vertexTetStart[i]; e < b->mesh.vertexTetStart[i + 1]; ++e)
		{
			int t = b->mesh.vertexTets[e] / 4;
			if (b->contact.tetMark[t])
				continue;
			if (!fmGrowArray((void**)&s->tets, &s->tetCapacity, count, count + 1, sizeof(int)))
				return -1;
			b->contact.tetMark[t] = 1;
			s->tets[count++] = t;
		}
	}
	for (int k = 0; k < count; ++k)
		b->contact.tetMark[s->tets[k]] = 0;
	return count;
}

// How the stage changed body @p slot's elastic energy (J) and its power sum v . f (W): over
// the tets around its logged vertices (a spring body, or one whose volume term lives on vertex
// patches reaching past those tets: over the whole body), after minus before.
static bool fmElasticChange(fmWorld* w, fmContactState* s, int slot, double* energy, double* power)
{
	fmBody* b = &w->bodies[slot];
	double e1 = 0.0, p1 = 0.0, e0 = 0.0, p0 = 0.0;
	if (b->mesh.forceModel == fm_massSpring || fmNodalPressure_On(&b->mesh))
	{
		bool ok = fmSpringEnergyPower(s, b, &e1, &p1);
		fmSwapLoggedStates(w, s, slot);
		ok = ok && fmSpringEnergyPower(s, b, &e0, &p0);
		fmSwapLoggedStates(w, s, slot);
		*energy = e1 - e0;
		*power = p1 - p0;
		return ok;
	}
	int count = fmTetsAroundLogged(w, s, slot);
	if (count < 0)
		return false;
	fmTetsEnergy(b, s->tets, count, &e1, &p1);
	fmSwapLoggedStates(w, s, slot);
	fmTetsEnergy(b, s->tets, count, &e0, &p0);
	fmSwapLoggedStates(w, s, slot);
	*energy = e1 - e0;
	*power = p1 - p0;
	return true;
}

bool fmContactLedger_AddStageWork(fmWorld* w, fmContactState* s, const fmStepContext* ctx,
                                  double shadowWeight, int slot)
{
	fmBody* b = &w->bodies[slot];
	if (b->asleep)
		return true; // nothing moved it, and its ledger is closed while it sleeps
	double gained = 0.0, gravityPower = 0.0;
	bool logged = false;
	for (int k = 0; k < s->loggedCount; ++k)
	{
		const fmLoggedVertex* t = &s->logged[k];
		if (t->body != slot)
			continue;
		logged = true;
		double m = b->mesh.mass[t->vertex];
		fmVec3 x = fmLoad(b->state.x, t->vertex), v = fmLoad(b->state.v, t->vertex);
		gained += 0.5 * m * (fmDot(v, v) - fmDot(t->v, t->v));
		gained -= m * fmDot(w->def.gravity, fmSub(x, t->x));
		gravityPower += m * fmDot(w->def.gravity, fmSub(v, t->v));
	}
	if (!logged)
		return true;
	double elastic, power;
	if (!fmElasticChange(w, s, slot, &elastic, &power))
		return false;
	gained += elastic;
	if (w->def.integrator == fm_explicit)
		gained += shadowWeight * (power + gravityPower);
	fmStepContext_AddContactWork(ctx, slot, gained);
	return true;
}
