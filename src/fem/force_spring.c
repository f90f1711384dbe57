// Mass-spring force model: a spring on every tet edge (the cheap baseline of 000_*.txt).
//
// Stiffness rule (docs/force-models.md): k_e = E * (sum of the rest volumes of the tets around
// edge e) / L_e^2. Under a uniform dilation by strain eps the springs then store
// 1/2 eps^2 E * 6 V, which equals the continuum's 9/2 K eps^2 V exactly when nu = 1/4
// (K = E / (3 (1 - 2 nu))): the only Poisson ratio a central-force network can represent
// (the Cauchy relation). For other nu the body is stiffer or softer in volume change; that
// is the price of the model, and why FEM is the default.
#include "fem/force_spring.h"


#include "core/core.h"

#include <stdlib.h>
#include <string.h>

typedef struct fmEdgeKey
{
	int a, b; // a < b
	int tet;  // one tet that owns it (for the volume sum we scan all)
} fmEdgeKey;

static int fmCompareEdges(const void* p, const void* q)
{
	const fmEdgeKey* e = p;
	const fmEdgeKey* f = q;
	if (e->a != f->a)
		return e->a < f->a ? -1 : 1;
	if (e->b != f->b)
		return e->b < f->b ? -1 : 1;
	return (e->tet > f->tet) - (e->tet < f->tet);
}

double fmYoungsModulus(const fmMaterial* m)
{
	return m->mu * (3.0 * m->lambda + 2.0 * m->mu) / (m->lambda + m->mu);
}

static void fmEmitSprings(fmElasticMesh* mesh, const fmEdgeKey* keys, size_t keyCount)
{
	int e = -1;
	for (size_t k = 0; k < keyCount; ++k)
	{
		if (k == 0 || keys[k].a != keys[k - 1].a || keys[k].b != keys[k - 1].b)
		{
			e += 1;
			mesh->edges[2 * e] = keys[k].a;
			mesh->edges[2 * e + 1] = keys[k].b;
			mesh->restLength[e] =
			    fmLength(fmSub(fmLoad(mesh->x0, keys[k].b), fmLoad(mesh->x0, keys[k].a)));
			mesh->springK[e] = 0.0;
		}
		// Each tet's share with its own material's Young's modulus (per-region materials).
		mesh->springK[e] +=
		    mesh->restVolume[keys[k].tet] * fmYoungsModulus(fmTetMaterial(mesh, keys[k].tet));
	}
	for (int i = 0; i < mesh->edgeCount; ++i)
		mesh->springK[i] *= 1.0 / (mesh->restLength[i] * mesh->restLength[i]);
}

int fmBuildSprings(fmElasticMesh* mesh)
{
	static const int s_pairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
	size_t keyCount = 6 * (size_t)mesh->tetCount;
	fmEdgeKey* keys = FM_ALLOC_ARRAY(fmEdgeKey, keyCount);
	if (keys == NULL)
		return 1;
	for (int t = 0; t < mesh->tetCount; ++t)
		for (int p = 0; p < 6; ++p)
		{
			int a = mesh->tets[4 * t + s_pairs[p][0]], b = mesh->tets[4 * t + s_pairs[p][1]];
			keys[6 * (size_t)t + p] = (fmEdgeKey){a < b ? a : b, a < b ? b : a, t};
		}
	qsort(keys, keyCount, sizeof *keys, fmCompareEdges);
	int count = 0;
	for (size_t k = 0; k < keyCount; ++k)
		count += k == 0 || keys[k].a != keys[k - 1].a || keys[k].b != keys[k - 1].b;
	mesh->edgeCount = count;
	mesh->edges = FM_ALLOC_ARRAY(int, 2 * (size_t)count);
	mesh->restLength = FM_ALLOC_ARRAY(double, count);
	mesh->springK = FM_ALLOC_ARRAY(double, count);
	int ok = mesh->edges && mesh->restLength && mesh->springK;
	if (ok)
		fmEmitSprings(mesh, keys, keyCount);
	FM_FREE_ARRAY(keys, fmEdgeKey, keyCount);
	return ok ? 0 : 1;
}

double fmSpringEnergy(const fmElasticMesh* mesh, const double* x)
{
	double energy = 0.0;
	for (int e = 0; e < mesh->edgeCount; ++e)
	{
		fmVec3 d = fmSub(fmLoad(x, mesh->edges[2 * e + 1]), fmLoad(x, mesh->edges[2 * e]));
		double stretch = fmLength(d) - mesh->restLength[e];
		energy += 0.5 * mesh->springK[e] * stretch * stretch;
	}
	return energy;
}

double fmAddSpringForces(const fmElasticMesh* mesh, const double* x, double* f)
{
	double energy = 0.0;
	for (int e = 0; e < mesh->edgeCount; ++e)
	{
		int a = mesh->edges[2 * e], b = mesh->edges[2 * e + 1];
		fmVec3 d = fmSub(fmLoad(x, b), fmLoad(x, a));
		double length = fmLength(d);
		double stretch = length - mesh->restLength[e];
		energy += 0.5 * mesh->springK[e] * stretch * stretch;
		if (length <= 0.0)
			continue; // coincident ends: no direction to push along
		fmVec3 fb = fmScale(-mesh->springK[e] * stretch / length, d);
		fmStore(f, b, fmAdd(fmLoad(f, b), fb));
		fmStore(f, a, fmSub(fmLoad(f, a), fb));
	}
	return energy;
}

// Critical damping of a spring between masses ma and mb is 2 sqrt(k m_eff), m_eff the reduced
// mass; springDamping is the fraction of it. Pinned ends have infinite mass.
double fmSpringDashpot(const fmElasticMesh* mesh, const double* invMass, const double* x, int e, fmVec3* direction)
{
	int a = mesh->edges[2 * e], b = mesh->edges[2 * e + 1];
	double invSum = invMass[a] + invMass[b];
	fmVec3 d = fmSub(fmLoad(x, b), fmLoad(x, a));
	double length = fmLength(d);
	if (invSum <= 0.0 || length <= 0.0)
		return 0.0;
	*direction = fmScale(1.0 / length, d);
	return 2.0 * mesh->springDamping * sqrt(mesh->springK[e] / invSum);
}

void fmAddSpringDamping(const fmElasticMesh* mesh, const double* invMass, const double* x, const double* v, double* f)
{
	if (mesh->springDamping <= 0.0)
		return;
	for (int e = 0; e < mesh->edgeCount; ++e)
	{
		int a = mesh->edges[2 * e], b = mesh->edges[2 * e + 1];
		fmVec3 n;
		double c = fmSpringDashpot(mesh, invMass, x, e, &n);
		if (c <= 0.0)
			continue;
		double rate = fmDot(fmSub(fmLoad(v, b), fmLoad(v, a)), n);
		fmVec3 fb = fmScale(-c * rate, n);
		fmStore(f, b, fmAdd(fmLoad(f, b), fb));
		fmStore(f, a, fmSub(fmLoad(f, a), fb));
	}
}

// d^2/dxb^2 of 1/2 k (|d| - L)^2 is H = k (n n^T + (1 - L/|d|)(I - n n^T)); the 6x6 is
// [H -H; -H H]. Its only possibly negative eigenvalue is k (1 - L/|d|) (a compressed spring);
// projection clamps that factor at zero.
void fmSpringHessian(const fmElasticMesh* mesh, const double* x, int e, double* K, int project)
{
	int a = mesh->edges[2 * e], b = mesh->edges[2 * e + 1];
	fmVec3 d = fmSub(fmLoad(x, b), fmLoad(x, a));
	double length = fmLength(d);
	double k = mesh->springK[e];
	double transverse = length > 0.0 ? 1.0 - mesh->restLength[e] / length : 0.0;
	if (project && transverse < 0.0)
		transverse = 0.0;
	fmVec3 n = length > 0.0 ? fmScale(1.0 / length, d) : fmMakeVec3(0, 0, 0);
	const double nv[3] = {n.x, n.y, n.z};
	double H[9];
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			H[3 * i + j] = k * (nv[i] * nv[j] + transverse * ((i == j) - nv[i] * nv[j]));
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
		{
			K[6 * i + j] = H[3 * i + j];
			K[6 * (i + 3) + (j + 3)] = H[3 * i + j];
			K[6 * i + (j + 3)] = -H[3 * i + j];
			K[6 * (i + 3) + j] = -H[3 * i + j];
		}
}
