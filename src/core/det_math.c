// Deterministic elementary functions (det_math.h). Both reduce the argument exactly (or with a
// split constant) to a small interval and sum a Taylor series there, whose coefficients are
// rationals (1/n! and 2/(2n+1)) written as the nearest doubles, to as many terms as make the
// truncation error below a tenth of an ulp. No tables, no fused multiply-add (the build has
// -ffp-contract=off), no library call but sqrt-free bit manipulation through memcpy.
#include "core/det_math.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

_Thread_local bool fmDetMathMode;

// ln 2 split in two: FM_LN2_HI has the low 32 bits of its significand zero, so k * FM_LN2_HI is
// exact for every exponent k a double has; FM_LN2_LO = ln 2 - FM_LN2_HI rounded to nearest.
#define FM_LN2_HI 0x1.62e42p-1
#define FM_LN2_LO 4.7493250390316726e-07
#define FM_INV_LN2 1.4426950408889634 // 1 / ln 2, rounded to nearest
#define FM_SQRT1_2 0.7071067811865476 // sqrt(1/2), rounded to nearest

static uint64_t fmBits(double x)
{
	uint64_t bits;
	memcpy(&bits, &x, sizeof bits);
	return bits;
}

static double fmFromBits(uint64_t bits)
{
	double x;
	memcpy(&x, &bits, sizeof x);
	return x;
}

// 2^n for n in [-1022, 1023], exactly.
static double fmPow2(int n)
{
	return fmFromBits((uint64_t)(n + 1023) << 52);
}

// ---- log ---------------------------------------------------------------------------------------

// log(1 + f) for 1 + f in [sqrt(1/2), sqrt(2)]: with s = f / (2 + f), log(1 + f) = 2 atanh(s)
// = 2 s + s R, R = sum over n >= 1 of 2 s^(2n) / (2n + 1) (c(2n+1) below, rounded to nearest).
// |s| <= 0.1716, s^2 <= 0.0295: eleven terms leave a truncation error below 1e-18 relative. Written
// (as in Cody and Waite's and Tang's methods) as f - (hfsq - s (hfsq + R)) with hfsq = f^2 / 2,
// since 2 s = f - s f and s f = hfsq - s hfsq: the large term f is exact and the correction small.
static double fmLog1pReduced(double f, double kLo)
{
	// R by Estrin's scheme (independent products in parallel: half the latency of Horner's).
	const double s = f / (2.0 + f), z = s * s, z2 = z * z, z4 = z2 * z2, z8 = z4 * z4;
	const double c3 = 0.6666666666666666, c5 = 0.4, c7 = 0.2857142857142857;
	const double c9 = 0.2222222222222222, c11 = 0.18181818181818182, c13 = 0.15384615384615385;
	const double c15 = 0.13333333333333333, c17 = 0.11764705882352941;
	const double c19 = 0.10526315789473684, c21 = 0.09523809523809523, c23 = 0.08695652173913043;
	const double low = (c3 + z * c5) + z2 * (c7 + z * c9);
	const double mid = (c11 + z * c13) + z2 * (c15 + z * c17);
	const double high = (c19 + z * c21) + z2 * c23;
	const double R = z * (low + z4 * mid + z8 * high);
	const double hfsq = 0.5 * f * f;
	return f - (hfsq - (s * (hfsq + R) + kLo));
}

double fmDetLog(double x)
{
	if (isnan(x))
		return x + x;
	if (x < 0.0)
		return NAN;
	if (x == 0.0)
		return -INFINITY;
	if (isinf(x))
		return x;
	// x = 2^k m, m in [sqrt(1/2), sqrt(2)): exact (denormals scaled up by 2^54 first).
	int k = 0;
	if (x < 0x1p-1022)
	{
		x *= 0x1p54;
		k = -54;
	}
	uint64_t bits = fmBits(x);
	k += (int)((bits >> 52) & 0x7FF) - 1023;
	double m = fmFromBits((bits & 0x000FFFFFFFFFFFFFull) | 0x3FF0000000000000ull);
	if (m > 2.0 * FM_SQRT1_2)
	{
		m *= 0.5;
		k += 1;
	}
	// log x = k ln 2 + log m; f = m - 1 is exact (Sterbenz), k FM_LN2_HI is exact.
	const double kd = (double)k;
	return kd * FM_LN2_HI + fmLog1pReduced(m - 1.0, kd * FM_LN2_LO);
}

// ---- exp ---------------------------------------------------------------------------------------

// e^r - 1 - r for |r| <= 0.35: r^2 (1/2! + r/3! + ... + r^11/13!); the first term left out,
// r^14 / 14!, is below 5e-18.
static double fmExpTail(double r)
{
	double p = 1.6059043836821613e-10;  // 1/13!
	p = 2.08767569878681e-09 + r * p;   // 1/12!
	p = 2.505210838544172e-08 + r * p;  // 1/11!
	p = 2.755731922398589e-07 + r * p;  // 1/10!
	p = 2.7557319223985893e-06 + r * p; // 1/9!
	p = 2.48015873015873e-05 + r * p;   // 1/8!
	p = 0.0001984126984126984 + r * p;  // 1/7!
	p = 0.001388888888888889 + r * p;   // 1/6!
	p = 0.008333333333333333 + r * p;   // 1/5!
	p = 0.041666666666666664 + r * p;   // 1/4!
	p = 0.16666666666666666 + r * p;    // 1/3!
	p = 0.5 + r * p;                    // 1/2!
	return r * r * p;
}

// y 2^k for y in [0.7, 1.5] and k in [-1080, 1030], rounded once (also to a denormal).
static double fmScale(double y, int k)
{
	if (k > 1023)
		return y * fmPow2(1023) * fmPow2(k - 1023);
	if (k < -1021)
		return y * fmPow2(k + 1000) * fmPow2(-1000); // the first product is exact
	return y * fmPow2(k);
}

double fmDetExp(double x)
{
	if (isnan(x))
		return x + x;
	if (x > 709.782712893384) // ln(DBL_MAX)
		return INFINITY;
	if (x < -745.1332191019412) // ln of half the smallest denormal
		return 0.0;
	if (fabs(x) < 0x1p-54)
		return 1.0 + x;
	// x = k ln 2 + r, |r| <= ln 2 / 2: k FM_LN2_HI is exact, and so is x - k FM_LN2_HI (x and
	// the product are within a factor of two of each other, or k is 0).
	const double k = floor(x * FM_INV_LN2 + 0.5);
	const double hi = x - k * FM_LN2_HI, lo = k * FM_LN2_LO;
	const double r = hi - lo;
	return fmScale(1.0 + (r + fmExpTail(r)), (int)k);
}

// ---- pow ---------------------------------------------------------------------------------------

double fmDetPow(double x, double y)
{
	if (y == 0.0 || x == 1.0)
		return 1.0;
	if (isnan(x) || isnan(y))
		return x + y;
	if (x < 0.0)
		return NAN;
	if (x == 0.0)
		return y > 0.0 ? 0.0 : INFINITY;
	return fmDetExp(y * fmDetLog(x));
}

// ---- sin and cos -------------------------------------------------------------------------------

// pi/2 in three parts (Cody and Waite): k * FM_PIO2_1 and k * FM_PIO2_2 are exact for
// |k| < 2^20, so x - k pi/2 keeps its accuracy over the range fmDetSinCos serves.
#define FM_PIO2_1 1.57079632673412561417e+00
#define FM_PIO2_2 6.07710050630396597660e-11
#define FM_PIO2_3 2.02226624879595063154e-21
#define FM_TWO_OVER_PI 6.36619772367581382433e-01

// sin r and cos r for |r| <= pi/4: their Taylor series to r^17 and r^18 (the next terms are
// below 2^-60 there).
static void fmSinCosKernel(double r, double* s, double* c)
{
	double z = r * r;
	*s = r + r * z *
	             (-1.0 / 6.0 +
	              z * (1.0 / 120.0 + z * (-1.0 / 5040.0 +
	                                      z * (1.0 / 362880.0 +
	                                           z * (-1.0 / 39916800.0 +
	                                                z * (1.0 / 6227020800.0 +
	                                                     z * (-1.0 / 1307674368000.0 +
	                                                          z * (1.0 / 355687428096000.0))))))));
	*c = 1.0 - 0.5 * z +
	     z * z *
	         (1.0 / 24.0 +
	          z * (-1.0 / 720.0 +
	               z * (1.0 / 40320.0 + z * (-1.0 / 3628800.0 +
	                                         z * (1.0 / 479001600.0 +
	                                              z * (-1.0 / 87178291200.0 +
	                                                   z * (1.0 / 20922789888000.0 +
	                                                        z * (-1.0 / 6402373705728000.0))))))));
}

void fmDetSinCos(double x, double* sine, double* cosine)
{
	if (!(fabs(x) <= 1e6))
	{
		*sine = *cosine = NAN;
		return;
	}
	double k = floor(x * FM_TWO_OVER_PI + 0.5);
	double r = ((x - k * FM_PIO2_1) - k * FM_PIO2_2) - k * FM_PIO2_3;
	double s, c;
	fmSinCosKernel(r, &s, &c);
	switch (((long)k) & 3)
	{
	case 0:
		*sine = s, *cosine = c;
		break;
	case 1:
		*sine = c, *cosine = -s;
		break;
	case 2:
		*sine = -s, *cosine = -c;
		break;
	default:
		*sine = -c, *cosine = s;
		break;
	}
}

// atan t for |t| <= tan(pi/16) = 0.199: its Taylor series to t^31 (the next term is below
// 2^-74 t).
static double fmAtanKernel(double t)
{
	double z = t * t, sum = 0.0;
	for (int k = 31; k >= 3; k -= 2)
		sum = (k / 2 % 2 ? -1.0 : 1.0) / k + z * sum;
	return t + t * z * sum;
}

// atan x for 0 <= x <= 1: atan x = c + atan((x - tan c) / (1 + x tan c)) with c = pi/8 or pi/4
// beyond tan(pi/16), which brings the argument below 0.2 either way.
static double fmAtanUnit(double x)
{
	if (x <= 0.19891236737965800691)
		return fmAtanKernel(x);
	const double t8 = 0.41421356237309504880; // tan(pi/8)
	if (x <= 0.66817863791929891999)          // tan(3 pi/16)
		return 0.39269908169872415481 + fmAtanKernel((x - t8) / (1.0 + x * t8));
	return 0.78539816339744830962 + fmAtanKernel((x - 1.0) / (1.0 + x)); // pi/4 + ...
}

double fmDetAtan2(double y, double x)
{
	if (isnan(x) || isnan(y))
		return NAN;
	double ax = fabs(x), ay = fabs(y);
	if (ax == 0.0 && ay == 0.0)
		return signbit(x) ? copysign(3.14159265358979311600, y) : copysign(0.0, y);
	bool swap = ay > ax;
	double angle = fmAtanUnit(swap ? ax / ay : ay / ax);
	if (swap)
		angle = 1.57079632679489655800 - angle + 6.123233995736766e-17;
	if (signbit(x))
		angle = 3.14159265358979311600 - angle + 1.2246467991473532e-16;
	return copysign(angle, y);
}
