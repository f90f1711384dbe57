// The explicit stability limit (stability.h).
//
// Symplectic Euler is stable for h < 2 / omega_max, omega_max^2 the largest eigenvalue of
// M^-1 K. Gershgorin's theorem bounds it by the largest absolute row sum of K divided by the
// vertex mass. K is the tangent stiffness at the current deformation, element by element (the
// sum of the elements' absolute row sums bounds the assembled one's): at rest it is the linear
// elastic one for every model, under compression Neo-Hookean and StVK stiffen (NH's lambda
// (1 - ln J) / J^2 grows without bound as J -> 0), and the estimate follows. The 0.9 leaves
// room for the deformation to grow further within the frame.
#include "fem/stability.h"
#include "core/det_math.h"

#include "fem/elastic_mesh.h"
#include "fem/force_spring.h"
#include "fem/forces.h"
#include "fem/nodal_pressure.h"

#include <math.h>
#include <string.h>

// Add the absolute row sums of an element matrix K (size x size, rows node-major xyz) to the
// rows of its nodes.
static void fmAddRowSums(const double* K, int size, const int* nodes, double* rowSum)
{
	for (int r = 0; r < size; ++r)
	{
		double sum = 0.0;
		for (int c = 0; c < size; ++c)
			sum += fabs(K[size * r + c]);
		rowSum[3 * nodes[r / 3] + r % 3] += sum;
	}
}

double fmExplicitStepLimit(const fmElasticMesh* mesh, const fmBodyState* state, fmArena* arena)
{
	size_t mark = fmArena_Mark(arena);
	double* rowSum = fmArena_Doubles(arena, 3 * (size_t)mesh->vertexCount);
	if (rowSum == NULL)
		return 0.0;
	double K[144];
	if (mesh->forceModel == fm_massSpring)
		for (int e = 0; e < mesh->edgeCount; ++e)
		{
			fmSpringHessian(mesh, state->x, e, K, 0);
			fmAddRowSums(K, 6, mesh->edges + 2 * e, rowSum);
		}
	else
		for (int t = 0; t < mesh->tetCount; ++t)
		{
			fmTetHessian(mesh, state->x, t, K, 0);
			fmAddRowSums(K, 12, mesh->tets + 4 * t, rowSum);
		}
	if (fmNodalPressure_On(mesh))
		fmNodalPressure_AddRowSums(mesh, state->x, rowSum);
	double omega2 = 0.0;
	for (int k = 0; k < 3 * mesh->vertexCount; ++k)
		omega2 = fmMax(omega2, rowSum[k] * state->invMass[k / 3]);
	fmArena_Release(arena, mark);
	return omega2 > 0.0 && isfinite(omega2) ? 0.9 * 2.0 / sqrt(omega2)
	       : omega2 > 0.0                   ? 0.0
	                                        : INFINITY;
}

double fmStiffeningProxy(const fmElasticMesh* mesh, const double* x)
{
	return fmStiffeningProxyRange(mesh, x, 0, mesh->tetCount);
}

double fmStiffeningProxyRange(const fmElasticMesh* mesh, const double* x, int start, int end)
{
#if !defined(__EMSCRIPTEN__) // (no batched proxy in the browser's .wasm: forces.c)
	if (mesh->forceModel != fm_massSpring)
		return fmStiffeningProxyTets(mesh, x, start, end);
#endif
	double proxy = 1.0;
	for (int t = start; t < end; ++t)
	{
		fmMat3 F = fmTetDeformation(mesh, x, t);
		double J = fmDet(&F), I1 = 0.0;
		for (int k = 0; k < 9; ++k)
			I1 += F.m[k] * F.m[k];
		if (!(J > 0.0))
			return INFINITY;
		proxy = fmMax(proxy, fmMax(I1, I1 * I1 / (4.0 * J * J)));
	}
	return proxy;
}
