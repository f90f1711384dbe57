// Second-order forward automatic differentiation over at most FM_AD_MAX variables: a value with
// its gradient and its (symmetric) Hessian, carried through +, -, * and /. For the small
// rational functions of contact geometry (squared distances of 4 points, 12 coordinates), where
// the exact derivatives are what matters and hand-written Hessians are where errors hide.
#pragma once

#include <femto/fm_math.h>

#define FM_AD_MAX 12

typedef struct fmAd
{
	double v;                         // value
	double g[FM_AD_MAX];              // gradient
	double h[FM_AD_MAX][FM_AD_MAX];   // Hessian
} fmAd;

typedef struct fmAdVec3
{
	fmAd x, y, z;
} fmAdVec3;

// A constant.
fmAd fmAd_Constant(double value);

// Variable @p index (0 to FM_AD_MAX - 1) at @p value.
fmAd fmAd_Variable(double value, int index);

fmAd fmAd_Add(const fmAd* a, const fmAd* b);
fmAd fmAd_Sub(const fmAd* a, const fmAd* b);
fmAd fmAd_Mul(const fmAd* a, const fmAd* b);
// a / b; b must not be 0.
fmAd fmAd_Div(const fmAd* a, const fmAd* b);

// Point @p p as the variables 3 @p first, 3 @p first + 1, 3 @p first + 2.
fmAdVec3 fmAdVec3_Variables(fmVec3 p, int first);
fmAdVec3 fmAdVec3_Sub(const fmAdVec3* a, const fmAdVec3* b);
fmAdVec3 fmAdVec3_Cross(const fmAdVec3* a, const fmAdVec3* b);
fmAd fmAdVec3_Dot(const fmAdVec3* a, const fmAdVec3* b);

// Copy the first @p n entries of the gradient to @p gradient and the n x n Hessian, row-major,
// to @p hessian (either may be NULL).
void fmAd_Export(const fmAd* a, int n, double* gradient, double* hessian);
