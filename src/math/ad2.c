// Second-order forward automatic differentiation (see ad2.h).
#include "math/ad2.h"

#include <string.h>

fmAd fmAd_Constant(double value)
{
	fmAd a;
	memset(&a, 0, sizeof a);
	a.v = value;
	return a;
}

fmAd fmAd_Variable(double value, int index)
{
	fmAd a = fmAd_Constant(value);
	a.g[index] = 1.0;
	return a;
}

fmAd fmAd_Add(const fmAd* a, const fmAd* b)
{
	fmAd r;
	r.v = a->v + b->v;
	for (int i = 0; i < FM_AD_MAX; ++i)
	{
		r.g[i] = a->g[i] + b->g[i];
		for (int j = 0; j < FM_AD_MAX; ++j)
			r.h[i][j] = a->h[i][j] + b->h[i][j];
	}
	return r;
}

fmAd fmAd_Sub(const fmAd* a, const fmAd* b)
{
	fmAd r;
	r.v = a->v - b->v;
	for (int i = 0; i < FM_AD_MAX; ++i)
	{
		r.g[i] = a->g[i] - b->g[i];
		for (int j = 0; j < FM_AD_MAX; ++j)
			r.h[i][j] = a->h[i][j] - b->h[i][j];
	}
	return r;
}

// (ab)'' = a b'' + b a'' + a' b'^T + b' a'^T
fmAd fmAd_Mul(const fmAd* a, const fmAd* b)
{
	fmAd r;
	r.v = a->v * b->v;
	for (int i = 0; i < FM_AD_MAX; ++i)
	{
		r.g[i] = a->v * b->g[i] + b->v * a->g[i];
		for (int j = 0; j < FM_AD_MAX; ++j)
			r.h[i][j] = a->v * b->h[i][j] + b->v * a->h[i][j] + a->g[i] * b->g[j] +
			            b->g[i] * a->g[j];
	}
	return r;
}

// f = a / b: a = f b gives f' = (a' - f b') / b and f'' = (a'' - f b'' - f' b'^T - b' f'^T) / b.
fmAd fmAd_Div(const fmAd* a, const fmAd* b)
{
	fmAd r;
	r.v = a->v / b->v;
	for (int i = 0; i < FM_AD_MAX; ++i)
		r.g[i] = (a->g[i] - r.v * b->g[i]) / b->v;
	for (int i = 0; i < FM_AD_MAX; ++i)
		for (int j = 0; j < FM_AD_MAX; ++j)
			r.h[i][j] = (a->h[i][j] - r.v * b->h[i][j] - r.g[i] * b->g[j] - b->g[i] * r.g[j]) /
			            b->v;
	return r;
}

fmAdVec3 fmAdVec3_Variables(fmVec3 p, int first)
{
	fmAdVec3 r = {fmAd_Variable(p.x, 3 * first), fmAd_Variable(p.y, 3 * first + 1),
	              fmAd_Variable(p.z, 3 * first + 2)};
	return r;
}

fmAdVec3 fmAdVec3_Sub(const fmAdVec3* a, const fmAdVec3* b)
{
	fmAdVec3 r = {fmAd_Sub(&a->x, &b->x), fmAd_Sub(&a->y, &b->y), fmAd_Sub(&a->z, &b->z)};
	return r;
}

static fmAd fmAdCrossTerm(const fmAd* a, const fmAd* b, const fmAd* c, const fmAd* d)
{
	fmAd ab = fmAd_Mul(a, b), cd = fmAd_Mul(c, d);
	return fmAd_Sub(&ab, &cd);
}

fmAdVec3 fmAdVec3_Cross(const fmAdVec3* a, const fmAdVec3* b)
{
	fmAdVec3 r = {fmAdCrossTerm(&a->y, &b->z, &a->z, &b->y),
	              fmAdCrossTerm(&a->z, &b->x, &a->x, &b->z),
	              fmAdCrossTerm(&a->x, &b->y, &a->y, &b->x)};
	return r;
}

fmAd fmAdVec3_Dot(const fmAdVec3* a, const fmAdVec3* b)
{
	fmAd xx = fmAd_Mul(&a->x, &b->x), yy = fmAd_Mul(&a->y, &b->y), zz = fmAd_Mul(&a->z, &b->z);
	fmAd s = fmAd_Add(&xx, &yy);
	return fmAd_Add(&s, &zz);
}

void fmAd_Export(const fmAd* a, int n, double* gradient, double* hessian)
{
	for (int i = 0; gradient != NULL && i < n; ++i)
		gradient[i] = a->g[i];
	for (int i = 0; hessian != NULL && i < n; ++i)
		for (int j = 0; j < n; ++j)
			hessian[n * i + j] = a->h[i][j];
}
