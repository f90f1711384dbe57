// The energy ledger (energy_ledger.h): E <= E0 + W + 1% (E0 + W_in) + floor.
#include "world/energy_ledger.h"
#include "core/det_math.h"
#include "solver/solver_cache.h"

#include "body/body.h"
#include "body/loads.h"
#include "fem/forces.h"
#include "fem/tet_blocks.h"

#include <math.h>
#include <string.h>

// Relative tolerance of the ledger: symplectic Euler's energy oscillates within a band around
// the conserved one, and contacts change elastic energy in ways the ledger does not book.
#define FM_LEDGER_RELATIVE 0.01

double fmBodyEnergy(fmBody* b, fmVec3 gravity, double shadowStep, double* plain, int* inverted,
                    const fmEnergyPass* pass)
{
	double shadow = 0.0, elastic;
	if (inverted != NULL)
		*inverted = -1;
	if (shadowStep > 0.0)
	{
		size_t mark = fmArena_Mark(pass->arena);
		double* f = fmArena_Doubles(pass->arena, 3 * (size_t)b->mesh.vertexCount);
		if (f == NULL)
			return NAN;
		const fmTetBlocks* blocks = fmTetBlocks_Used(&b->mesh, pass->simd);
		elastic = blocks ? fmTetBlocks_AddForces(blocks, &b->mesh, b->state.x, NULL, f, pass->simd,
		                                         pass->tasks, true, inverted, NULL)
		                 : fmAddElasticForcesOn(&b->mesh, b->state.x, f, pass->tasks, pass->arena);
		fmLoads_AddForces(b, b->state.x, f); // the loads' part of the shadow energy, as gravity's
		for (int i = 0; i < b->mesh.vertexCount; ++i)
		{
			fmVec3 force = fmMulAdd(fmLoad(f, i), b->mesh.mass[i], gravity);
			shadow += fmDot(fmLoad(b->state.v, i), force);
		}
		fmArena_Release(pass->arena, mark);
	}
	else
		elastic =
		    fmSolverCache_Energy(&b->mesh, b->solverCache, b->state.x, pass->tasks, pass->arena);
	double kinetic = fmBodyKineticEnergy(b);
	if (plain)
		*plain = kinetic + elastic;
	return kinetic + elastic + 0.5 * shadowStep * shadow;
}

// Sum of m g . x: gravity's work over a frame is its change.
static double fmGravityPotential(const fmBody* b, fmVec3 gravity)
{
	double sum = 0.0;
	for (int i = 0; i < b->mesh.vertexCount; ++i)
		sum += b->mesh.mass[i] * fmDot(gravity, fmLoad(b->state.x, i));
	return sum;
}

// Absolute tolerance, for a body that starts at rest with nothing pushing it: a thousandth of
// the work of lifting it by its own size, plus a millionth of its shear modulus times its
// volume (the elastic energy of a strain of about 1e-3).
static double fmLedgerFloor(const fmBody* b, fmVec3 gravity)
{
	double volume = 0.0;
	for (int t = 0; t < b->mesh.tetCount; ++t)
		volume += b->mesh.restVolume[t];
	return 1e-3 * b->mesh.totalMass * fmLength(gravity) * b->mesh.restSize +
	       1e-6 * b->mesh.material.mu * volume;
}

static void fmLedgerAddWork(fmEnergyLedger* ledger, double work)
{
	ledger->work += work;
	if (work > 0.0)
		ledger->workIn += work;
}

void fmLedger_BeginFrame(fmBody* b, fmVec3 gravity, double shadowStep, const fmEnergyPass* pass)
{
	fmEnergyLedger* ledger = &b->ledger;
	size_t bytes = sizeof(double) * 3 * (size_t)b->mesh.vertexCount;
	if (!ledger->started)
	{
		b->energyGood = fmBodyEnergy(b, gravity, shadowStep, &ledger->plainGood, NULL, pass);
		ledger->measureStep = shadowStep;
		ledger->started = true;
		ledger->initialEnergy = b->energyGood;
		ledger->floor = fmLedgerFloor(b, gravity);
	}
	else if (b->energyStale || memcmp(b->state.x, b->xGood, bytes) != 0 ||
	         memcmp(b->state.v, b->vGood, bytes) != 0)
	{
		// The caller changed the state (or the material) since the last good frame: the energy
		// difference is work the caller did.
		// A state set to NaN or Inf books nothing: the frame fails on it and restores.
		double plain;
		double energy = fmBodyEnergy(b, gravity, shadowStep, &plain, NULL, pass);
		if (isfinite(energy))
		{
			ledger->plainGood = plain;
			fmLedgerAddWork(ledger, energy - b->energyGood);
			b->energyGood = energy;
			ledger->measureStep = shadowStep;
		}
	}
	else if (shadowStep != ledger->measureStep)
	{
		// Same state, another step or integrator: only the shadow term changed. Its change is
		// neither work nor a runaway; re-measure without counting it as work done.
		double energy = fmBodyEnergy(b, gravity, shadowStep, NULL, NULL, pass);
		ledger->work += energy - b->energyGood;
		b->energyGood = energy;
		ledger->measureStep = shadowStep;
	}
	ledger->gravityStart = fmGravityPotential(b, gravity);
}

// What a frame can hold at most for a stable body: the plain energy it started with, the work
// contacts and loads put in so far, and gravity's most in a frame, M g (size + g T^2).
static double fmLedgerFrameReach(const fmBody* b, const fmFrameWork* work, fmVec3 gravity,
                                 double frameTime)
{
	double g = fmLength(gravity);
	return fmMax(b->ledger.plainGood, 0.0) + work->contact + work->loadIn +
	       b->mesh.totalMass * g * (b->mesh.restSize + g * frameTime * frameTime);
}

fmLedgerVerdict fmLedger_Check(fmBody* b, const fmFrameWork* work, fmVec3 gravity, double energy,
                               double plain, double frameTime)
{
	fmEnergyLedger* ledger = &b->ledger;
	ledger->frameGravityWork = fmGravityPotential(b, gravity) - ledger->gravityStart;
	ledger->framePlain = plain;
	double frameWork = ledger->frameGravityWork + work->contact + work->load + work->measure;
	double frameWorkIn = fmMax(ledger->frameGravityWork, 0.0) + work->contact + work->loadIn;
	double allowed =
	    ledger->initialEnergy + ledger->work + frameWork +
	    FM_LEDGER_RELATIVE * (fabs(ledger->initialEnergy) + ledger->workIn + frameWorkIn) +
	    ledger->floor;
	// The shadow energy is only meaningful for stable steps: an unstable one can make its
	// correction term as negative as the explosion is large. The plain energy gets the
	// per-frame backstop: gravity adds at most M g (size + g T^2) in a frame, and a stable body
	// does not multiply its energy by 1000 on top of that.
	double backstop = 1000.0 * fmLedgerFrameReach(b, work, gravity, frameTime) + ledger->floor;
	fmLedgerVerdict verdict = {true, false, energy, allowed};
	if (!(plain <= backstop))
		verdict = (fmLedgerVerdict){false, true, plain, backstop};
	else if (!(energy <= allowed))
		verdict.ok = false;
	return verdict;
}

void fmLedger_ChangeMeasure(fmBody* b, fmFrameWork* work, fmVec3 gravity, double frameTime,
                            double fromStep, double toStep, const fmEnergyPass* pass)
{
	double before = fmBodyEnergy(b, gravity, fromStep, NULL, NULL, pass);
	double change = fmBodyEnergy(b, gravity, toStep, NULL, NULL, pass) - before;
	double reach = fmLedgerFrameReach(b, work, gravity, frameTime) + b->ledger.floor;
	if (isfinite(change))
		work->measure += fmMin(fmMax(change, -reach), reach);
}

void fmLedger_Commit(fmBody* b, const fmFrameWork* work, double shadowStep)
{
	fmEnergyLedger* ledger = &b->ledger;
	ledger->measureStep = shadowStep;
	fmLedgerAddWork(ledger, ledger->frameGravityWork);
	fmLedgerAddWork(ledger, work->contact);
	ledger->work += work->load + work->measure;
	ledger->workIn += work->loadIn;
	ledger->frameGravityWork = 0.0;
	ledger->plainGood = ledger->framePlain;
}
