// Batched element kernels (tet_kernel.h), written once on the lane wrapper of simd.h and compiled
// once per instruction set: FM_KERNEL_VARIANT names the variant (scalar, baseline, avx2,
// avx512) and the build adds its -m flags. Everything here is static except the entry points, so
// no function compiled for a wider instruction set can be picked by the linker for a narrower one.
//
// Per tet, with H = F - I = Du Dm^-1 (a small strain keeps its relative accuracy in float):
//   linear:      eps = (H + H^T)/2,                   P = 2 mu eps + lambda tr(eps) I
//   StVK:        G = (H + H^T + H^T H)/2,             P = (I + H)(2 mu G + lambda tr(G) I)
//   Neo-Hookean: J = 1 + j, j = tr H + c2(H) + det H, c2 = ((tr H)^2 - tr(H^2))/2,
//                cof F = (1 + tr H + c2) I - (1 + tr H) H^T + (H^T)^2,
//                F J - cof F = det H I + (1 + j) H + (1 + tr H) H^T - (H^T)^2, and for J above the
//                clamp P = (mu (F J - cof F) + lambda ln J cof F) / J (no cancellation at small
//                strain); below it P = mu F + (lambda l - mu) l' cof F with the clamped l(J) of
//                material_invariant.c.
//   Mooney-Rivlin: with a = mu + 2 C01, b = lambda - 4 C01 and G Green's strain, Neo-Hookean's
//                P with mu -> a and lambda -> b, plus 4 C01 F (tr G I - G) (the I2 term; the
//                derivation is at fmNeoHookeanStress).
//   isochoric Neo-Hookean: P = 2 mu J^(-5/3) cof(F) dev(G) + kappa (J - 1) cof F above the clamp
//                (fmIsochoricStress), J^(-1/3) by Newton's iteration.
//   corotated:   P = 2 mu (F - R) + lambda (J - 1) cof F, R the rotation of F's polar
//                decomposition by Newton's iteration X <- (X + X^-T)/2 from X = F, kept as
//                Y = X - I: X^-T - I = (-det Y I - (1 + tr Y) Y^T + (Y^T)^2) / det X, so F - R =
//                H - Y without cancellation. Tets with J < 0.1 (near flat, inverted: the
//                iteration would find a reflection) or not converged in 12 iterations are left
//                to the double-precision reference (fmTetBatchForces.fallback).
// The force on node a = 1..3 is -V0 P g_a, g_a the rows of Dm^-1; node 0 takes minus the sum.
#ifndef FM_KERNEL_VARIANT
#define FM_KERNEL_VARIANT baseline
#endif
#include "fem/kernels/tet_kernel.h"

#include "core/det_math.h"

#include "material/material.h"
#include "material/material_invariant.h"
#include "math/svd3.h"

#include <math.h>

// The helpers are inlined into the entry point: 64-byte vectors stay in registers. The
// Neo-Hookean energy (the ledger's, once a frame) is not, for the sanitizer and fuzzer builds'
// compile time (docs/decisions.md, "Kernel inlining").
#if defined(__GNUC__) || defined(__clang__)
#define FM_INLINE static inline __attribute__((always_inline))
#define FM_NOINLINE static __attribute__((noinline))
#else
#define FM_INLINE static inline
#define FM_NOINLINE static
#endif

// A 3x3 matrix of lanes, row-major.
typedef struct fmMat3V
{
	fmFloatV m[9];
} fmMat3V;

// Rows of FM_LANES floats each: entry k of lane l at rows[FM_LANES * k + l].
FM_INLINE fmMat3V fmMat3V_Load(const float* rows)
{
	fmMat3V a;
	for (int k = 0; k < 9; ++k)
		a.m[k] = fmV_Load(rows + FM_LANES * k);
	return a;
}

FM_INLINE fmMat3V fmMat3V_Mul(const fmMat3V* a, const fmMat3V* b)
{
	fmMat3V c;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			c.m[3 * i + j] = fmV_Add(
			    fmV_Add(fmV_Mul(a->m[3 * i], b->m[j]), fmV_Mul(a->m[3 * i + 1], b->m[3 + j])),
			    fmV_Mul(a->m[3 * i + 2], b->m[6 + j]));
	return c;
}

FM_INLINE fmMat3V fmMat3V_Transpose(const fmMat3V* a)
{
	fmMat3V t;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			t.m[3 * i + j] = a->m[3 * j + i];
	return t;
}

FM_INLINE fmFloatV fmMat3V_Trace(const fmMat3V* a)
{
	return fmV_Add(fmV_Add(a->m[0], a->m[4]), a->m[8]);
}

FM_INLINE fmFloatV fmMat3V_Det(const fmMat3V* a)
{
	const fmFloatV* m = a->m;
	fmFloatV c0 = fmV_Sub(fmV_Mul(m[4], m[8]), fmV_Mul(m[5], m[7]));
	fmFloatV c1 = fmV_Sub(fmV_Mul(m[5], m[6]), fmV_Mul(m[3], m[8]));
	fmFloatV c2 = fmV_Sub(fmV_Mul(m[3], m[7]), fmV_Mul(m[4], m[6]));
	return fmV_Add(fmV_Add(fmV_Mul(m[0], c0), fmV_Mul(m[1], c1)), fmV_Mul(m[2], c2));
}

// ln(1 + j) for 1 + j >= 2^-126, to a few ulp, from +, -, *, / only (no libm: the same bits on
// every target). 1 + j = 2^k m with m in [sqrt(1/2), sqrt(2)); ln m = 2 atanh(s), s = f / (2 + f),
// f = m - 1, as a series to s^9 (|s| < 0.172: the next term is below 2e-9 of ln m); the rounding
// of 1 + j comes back as c / (1 + j).
FM_INLINE fmFloatV fmV_Log1p(fmFloatV j)
{
	const fmFloatV one = fmV_Set(1.0f);
	fmFloatV u = fmV_Add(one, j);
	fmIntV bits = fmI_Add(fmV_Bits(u), fmI_Set(0x3f800000 - 0x3f3504f3));
	fmIntV k = fmI_Sub(fmI_ShiftRight(bits, 23), fmI_Set(0x7f));
	fmFloatV m = fmV_FromBits(fmI_Add(fmI_And(bits, fmI_Set(0x007fffff)), fmI_Set(0x3f3504f3)));
	fmFloatV kf = fmI_ToFloat(k);
	// The part of j that 1 + j rounded off (exact where it matters: k = 0 or 1).
	fmFloatV c = fmV_Select(fmV_Less(fmV_Set(0.5f), kf), fmV_Sub(one, fmV_Sub(u, j)),
	                        fmV_Sub(j, fmV_Sub(u, one)));
	c = fmV_Select(fmV_Less(kf, fmV_Set(24.5f)), fmV_Div(c, u), fmV_Set(0.0f));
	fmFloatV f = fmV_Sub(m, one);
	fmFloatV s = fmV_Div(f, fmV_Add(fmV_Set(2.0f), f));
	fmFloatV z = fmV_Mul(s, s);
	fmFloatV series = fmV_Add(fmV_Set(2.0f / 7.0f), fmV_Mul(z, fmV_Set(2.0f / 9.0f)));
	series = fmV_Add(fmV_Set(2.0f / 5.0f), fmV_Mul(z, series));
	series = fmV_Add(fmV_Set(2.0f / 3.0f), fmV_Mul(z, series));
	fmFloatV lnm = fmV_Add(fmV_Add(s, s), fmV_Mul(fmV_Mul(s, z), series));
	const fmFloatV ln2Hi = fmV_Set(6.9314575195e-01f), ln2Lo = fmV_Set(1.4286067653e-06f);
	return fmV_Add(fmV_Mul(kf, ln2Hi), fmV_Add(fmV_Add(lnm, c), fmV_Mul(kf, ln2Lo)));
}

// psi = P : eps / 2 for the quadratic energies (linear: mu eps:eps + lambda/2 tr(eps)^2; StVK
// the same in G), the double contraction of a matrix of lanes with another.
FM_INLINE fmFloatV fmMat3V_Contract(const fmMat3V* a, const fmMat3V* b)
{
	fmFloatV sum = fmV_Mul(a->m[0], b->m[0]);
	for (int k = 1; k < 9; ++k)
		sum = fmV_Add(sum, fmV_Mul(a->m[k], b->m[k]));
	return sum;
}

FM_INLINE fmFloatV fmV_Abs(fmFloatV a)
{
	return fmV_FromBits(fmI_And(fmV_Bits(a), fmI_Set(0x7fffffff)));
}

// j - ln(1 + j) given ln(1 + j): its series j^2/2 - j^3/3 + ... to j^10 for |j| < 1/4 (the
// difference would lose the digits the two share), the difference above.
FM_INLINE fmFloatV fmV_JMinusLog1p(fmFloatV j, fmFloatV lnJ)
{
	fmFloatV series = fmV_Set(1.0f / 10.0f);
	for (int n = 9; n >= 2; --n)
		series = fmV_Sub(fmV_Set(1.0f / (float)n), fmV_Mul(j, series));
	series = fmV_Mul(fmV_Mul(j, j), series);
	fmIntV small = fmV_Less(fmV_Abs(j), fmV_Set(0.25f));
	return fmV_Select(small, series, fmV_Sub(j, lnJ));
}

FM_INLINE void fmLinearStress(const fmMat3V* H, fmFloatV mu, fmFloatV lambda, fmMat3V* P,
                              fmFloatV* psi)
{
	fmFloatV twoMu = fmV_Add(mu, mu), half = fmV_Set(0.5f);
	fmFloatV lt = fmV_Mul(lambda, fmMat3V_Trace(H));
	fmMat3V eps;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
		{
			eps.m[3 * i + j] = fmV_Mul(half, fmV_Add(H->m[3 * i + j], H->m[3 * j + i]));
			P->m[3 * i + j] = fmV_Mul(twoMu, eps.m[3 * i + j]);
		}
	for (int i = 0; i < 3; ++i)
		P->m[4 * i] = fmV_Add(P->m[4 * i], lt);
	if (psi)
		*psi = fmV_Mul(half, fmMat3V_Contract(P, &eps));
}

// Green's strain G = (H + H^T + H^T H) / 2, symmetric.
FM_INLINE fmMat3V fmGreenStrain(const fmMat3V* H)
{
	fmMat3V G;
	const fmFloatV half = fmV_Set(0.5f);
	for (int i = 0; i < 3; ++i)
		for (int j = i; j < 3; ++j)
		{
			fmFloatV hth =
			    fmV_Add(fmV_Add(fmV_Mul(H->m[i], H->m[j]), fmV_Mul(H->m[3 + i], H->m[3 + j])),
			            fmV_Mul(H->m[6 + i], H->m[6 + j]));
			G.m[3 * i + j] = G.m[3 * j + i] =
			    fmV_Mul(half, fmV_Add(fmV_Add(H->m[3 * i + j], H->m[3 * j + i]), hth));
		}
	return G;
}

FM_INLINE void fmStvkStress(const fmMat3V* H, fmFloatV mu, fmFloatV lambda, fmMat3V* P,
                            fmFloatV* psi)
{
	// S = 2 mu G + lambda tr(G) I; P = S + H S; psi = S : G / 2.
	const fmFloatV half = fmV_Set(0.5f), twoMu = fmV_Add(mu, mu);
	const fmMat3V G = fmGreenStrain(H);
	fmMat3V S;
	fmFloatV lt = fmV_Mul(lambda, fmMat3V_Trace(&G));
	for (int k = 0; k < 9; ++k)
		S.m[k] = fmV_Mul(twoMu, G.m[k]);
	for (int i = 0; i < 3; ++i)
		S.m[4 * i] = fmV_Add(S.m[4 * i], lt);
	if (psi)
		*psi = fmV_Mul(half, fmMat3V_Contract(&S, &G));
	fmMat3V HS = fmMat3V_Mul(H, &S);
	for (int k = 0; k < 9; ++k)
		P->m[k] = fmV_Add(S.m[k], HS.m[k]);
}

// The lanes whose det(I + H) is below StVK's volume floor (material.h, with a float's margin): the
// reference path evaluates them in double, floor and all.
FM_INLINE fmIntV fmStvkBelowFloor(const fmMat3V* H)
{
	fmMat3V F = *H;
	const fmFloatV one = fmV_Set(1.0f);
	for (int i = 0; i < 3; ++i)
		F.m[4 * i] = fmV_Add(one, H->m[4 * i]);
	return fmV_Less(fmMat3V_Det(&F), fmV_Set((float)(FM_STVK_FLOOR_J * 1.001)));
}

// cof(I + A) = (1 + t + c2) I - (1 + t) A^T + (A^T)^2 and det(I + A) - 1 = t + c2 + det A, with
// t = tr A, c2 = (t^2 - tr(A^2)) / 2 (the Cayley-Hamilton form used throughout).
typedef struct fmNearIdentity
{
	fmMat3V AT, AT2;     // A^T, (A^T)^2
	fmFloatV t, c2, det; // tr A, c2, det A
	fmFloatV j;          // det(I + A) - 1
} fmNearIdentity;

FM_INLINE void fmNearIdentity_Make(const fmMat3V* A, fmNearIdentity* n)
{
	n->AT = fmMat3V_Transpose(A);
	n->AT2 = fmMat3V_Mul(&n->AT, &n->AT);
	n->t = fmMat3V_Trace(A);
	n->c2 = fmV_Mul(fmV_Set(0.5f), fmV_Sub(fmV_Mul(n->t, n->t), fmMat3V_Trace(&n->AT2)));
	n->det = fmMat3V_Det(A);
	n->j = fmV_Add(fmV_Add(n->t, n->c2), n->det);
}

// Entry @p k (row-major) of cof(I + A) = (1 + t + c2) I - (1 + t) A^T + (A^T)^2.
FM_INLINE fmFloatV fmNearIdentity_Cofactor(const fmNearIdentity* n, int k)
{
	const fmFloatV onePlusT = fmV_Add(fmV_Set(1.0f), n->t);
	fmFloatV diag = (k % 4 == 0) ? fmV_Add(onePlusT, n->c2) : fmV_Set(0.0f);
	return fmV_Add(fmV_Sub(diag, fmV_Mul(onePlusT, n->AT.m[k])), n->AT2.m[k]);
}

// Corotated; @p fallback gets the lanes left to the reference.
FM_INLINE void fmCorotatedStress(const fmMat3V* H, fmFloatV mu, fmFloatV lambda, fmMat3V* P,
                                 fmIntV* fallback, fmFloatV* psi)
{
	const fmFloatV one = fmV_Set(1.0f), zero = fmV_Set(0.0f), half = fmV_Set(0.5f);
	fmNearIdentity h;
	fmNearIdentity_Make(H, &h);
	fmIntV flat = fmV_Less(fmV_Add(one, h.j), fmV_Set(0.1f));
	fmMat3V Y = *H;
	fmIntV moving = fmI_Set(-1);
	for (int iteration = 0; iteration < 12 && fmI_Any(moving); ++iteration)
	{
		fmNearIdentity y;
		fmNearIdentity_Make(&Y, &y);
		// Flat lanes divide by 1 instead: their result is discarded.
		fmFloatV detX = fmV_Select(flat, one, fmV_Add(one, y.j));
		fmFloatV onePlusT = fmV_Add(one, y.t);
		fmFloatV change = zero;
		for (int k = 0; k < 9; ++k)
		{
			fmFloatV diag = (k % 4 == 0) ? y.det : zero;
			fmFloatV z =
			    fmV_Div(fmV_Sub(y.AT2.m[k], fmV_Add(diag, fmV_Mul(onePlusT, y.AT.m[k]))), detX);
			fmFloatV next = fmV_Mul(half, fmV_Add(Y.m[k], z));
			fmFloatV delta = fmV_Abs(fmV_Sub(next, Y.m[k]));
			change = fmV_Select(fmV_Less(change, delta), delta, change);
			Y.m[k] = fmV_Select(moving, next, Y.m[k]);
		}
		// A lane stops at its own convergence, whatever its neighbours in the vector do: the
		// same bits at any vector width.
		moving = fmI_And(moving, fmV_Less(fmV_Set(1e-6f), change));
	}
	*fallback = fmI_Or(flat, moving);
	// psi = mu |F - R|^2 + lambda/2 (J - 1)^2, F - R = H - Y.
	fmFloatV twoMu = fmV_Add(mu, mu), lj = fmV_Mul(lambda, h.j);
	fmFloatV stretch = zero;
	for (int k = 0; k < 9; ++k)
	{
		fmFloatV cof = fmNearIdentity_Cofactor(&h, k);
		fmFloatV d = fmV_Sub(H->m[k], Y.m[k]);
		stretch = fmV_Add(stretch, fmV_Mul(d, d));
		P->m[k] = fmV_Add(fmV_Mul(twoMu, d), fmV_Mul(lj, cof));
	}
	if (psi)
		*psi = fmV_Add(fmV_Mul(mu, stretch), fmV_Mul(fmV_Mul(half, lj), h.j));
}

// Neo-Hookean: P = alpha (F J - cof F) + beta cof F + gamma F, alpha, beta, gamma per lane.
// Neo-Hookean psi = mu (tr G - ln J) + lambda/2 (ln J)^2 above the clamp (I1 - 3 = 2 tr G), from
// Green's strain, which a rotation does not disturb beyond float's 1e-7 of its entries (H's are
// of order 1 under a rotation and would cancel): with k = J^2 - 1 = det(I + 2G) - 1 =
// 2 tr G + 4 c2(G) + 8 det G, ln J = ln(1 + k) / 2 and tr G - ln J = (k - ln(1 + k)) / 2 -
// 2 c2(G) - 4 det G, every term of second order at small strain.
// Green's strain G's invariants: t = tr G, c2 = (t^2 - tr(G^2)) / 2, det G, and
// k = J^2 - 1 = det(I + 2 G) - 1 = 2 t + 4 c2 + 8 det G, each free of cancellation at small
// strain.
typedef struct fmGreenInvariants
{
	fmFloatV t, c2, det, k;
} fmGreenInvariants;

FM_INLINE fmGreenInvariants fmGreenInvariants_Make(const fmMat3V* H)
{
	const fmFloatV half = fmV_Set(0.5f), two = fmV_Set(2.0f), four = fmV_Set(4.0f);
	fmMat3V G = fmGreenStrain(H);
	fmMat3V G2 = fmMat3V_Mul(&G, &G);
	fmGreenInvariants g;
	g.t = fmMat3V_Trace(&G);
	g.det = fmMat3V_Det(&G);
	g.c2 = fmV_Mul(half, fmV_Sub(fmV_Mul(g.t, g.t), fmMat3V_Trace(&G2)));
	g.k = fmV_Add(fmV_Mul(two, g.t), fmV_Add(fmV_Mul(four, g.c2), fmV_Mul(fmV_Set(8.0f), g.det)));
	return g;
}

// Mooney-Rivlin's (@p c01 > 0, with mu -> a and lambda -> b, fmNeoHookeanStress) adds 4 C01 c2(G).
FM_NOINLINE fmFloatV fmNeoHookeanEnergy(const fmMat3V* H, fmFloatV mu, fmFloatV lambda, float c01)
{
	const fmFloatV half = fmV_Set(0.5f), two = fmV_Set(2.0f), four = fmV_Set(4.0f);
	fmGreenInvariants g = fmGreenInvariants_Make(H);
	fmFloatV c2 = g.c2, det = g.det, k = g.k;
	fmFloatV log1pK = fmV_Log1p(k), lnJ = fmV_Mul(half, log1pK);
	fmFloatV trMinusLn = fmV_Sub(fmV_Mul(half, fmV_JMinusLog1p(k, log1pK)),
	                             fmV_Add(fmV_Mul(two, c2), fmV_Mul(four, det)));
	fmFloatV psi =
	    fmV_Add(fmV_Mul(mu, trMinusLn), fmV_Mul(fmV_Mul(half, lambda), fmV_Mul(lnJ, lnJ)));
	if (c01 != 0.0f)
		psi = fmV_Add(psi, fmV_Mul(fmV_Set(4.0f * c01), c2));
	return psi;
}

// Below the clamp (a collapsed or inverted tet, far from small strain): the plain formula
// mu/2 (2 tr H + |H|^2) - mu l + lambda/2 l^2 with the clamped l.
FM_INLINE fmFloatV fmNeoHookeanPlainEnergy(const fmMat3V* H, fmFloatV t, fmFloatV l, fmFloatV mu,
                                           fmFloatV lambda)
{
	const fmFloatV half = fmV_Set(0.5f);
	fmFloatV i1 = fmV_Add(fmV_Add(t, t), fmMat3V_Contract(H, H));
	return fmV_Add(fmV_Sub(fmV_Mul(fmV_Mul(half, mu), i1), fmV_Mul(mu, l)),
	               fmV_Mul(fmV_Mul(half, lambda), fmV_Mul(l, l)));
}

// Mooney-Rivlin below the clamp: C10 (I1 - 3) + C01 (I2 - 3) - a l + b/2 l^2, with I1 - 3 =
// 2 tr H + |H|^2 and I2 - 3 = 4 tr G + 4 c2(G).
FM_INLINE fmFloatV fmMooneyRivlinPlainEnergy(const fmMat3V* H, fmFloatV t, fmFloatV l, fmFloatV a,
                                             fmFloatV b, float c01, float c10)
{
	const fmFloatV half = fmV_Set(0.5f), four = fmV_Set(4.0f);
	fmFloatV i1 = fmV_Add(fmV_Add(t, t), fmMat3V_Contract(H, H));
	fmGreenInvariants g = fmGreenInvariants_Make(H);
	fmFloatV i2 = fmV_Mul(four, fmV_Add(g.t, g.c2));
	fmFloatV invariants = fmV_Add(fmV_Mul(fmV_Set(c10), i1), fmV_Mul(fmV_Set(c01), i2));
	return fmV_Add(fmV_Sub(invariants, fmV_Mul(a, l)), fmV_Mul(fmV_Mul(half, b), fmV_Mul(l, l)));
}

// Neo-Hookean, and Mooney-Rivlin when @p mooney (C01 from @p material). Its P = 2 C10 F +
// 2 C01 (I1 F - F C) + (b l - a) l' cof F (material_invariant.c) with C10 = mu/2 - C01,
// a = mu + 2 C01, b = lambda - 4 C01; C = I + 2 G and I1 = 3 + 2 tr G give 2 C01 (I1 F - F C) =
// 2 C01 F + 4 C01 F (tr G I - G), so P = a F + 4 C01 F (tr G I - G) + (b l - a) l' cof F:
// Neo-Hookean's with mu -> a and lambda -> b, plus a term that G keeps free of cancellation.
FM_INLINE void fmNeoHookeanStress(const fmMat3V* H, const fmKernelMaterial* material, bool mooney,
                                  fmMat3V* P, fmFloatV* psi)
{
	const fmFloatV one = fmV_Set(1.0f), zero = fmV_Set(0.0f);
	const float c01 = mooney ? material->c01 : 0.0f;
	const fmFloatV mu = fmV_Set(material->mu + 2.0f * c01);
	const fmFloatV lambda = fmV_Set(material->lambda - 4.0f * c01);
	fmNearIdentity h;
	fmNearIdentity_Make(H, &h);
	const fmMat3V HT = h.AT, HT2 = h.AT2;
	fmFloatV t = h.t, c2 = h.c2, d = h.det, j = h.j, J = fmV_Add(one, j);
	fmFloatV onePlusT = fmV_Add(one, t), onePlusJ = J;

	// Above the clamp: l = ln J, alpha = mu / J, beta = lambda l / J, gamma = 0. Below it:
	// l = ln c + e / c - e^2 / (2 c^2), l' = 1/c - e / c^2 (e = J - c), alpha = 0,
	// beta = (lambda l - mu) l', gamma = mu.
	const float clamp = 0.2f, lnClamp = -1.6094379124341003f;
	fmIntV below = fmV_Less(J, fmV_Set(clamp));
	fmFloatV lnJ = fmV_Log1p(fmV_Select(below, zero, j));
	fmFloatV e = fmV_Sub(J, fmV_Set(clamp)), invC = fmV_Set(1.0f / clamp);
	fmFloatV lBelow = fmV_Sub(fmV_Add(fmV_Set(lnClamp), fmV_Mul(e, invC)),
	                          fmV_Mul(fmV_Mul(fmV_Set(0.5f), fmV_Mul(e, e)), fmV_Mul(invC, invC)));
	fmFloatV dlBelow = fmV_Sub(invC, fmV_Mul(e, fmV_Mul(invC, invC)));
	fmFloatV safeJ = fmV_Select(below, one, J);
	fmFloatV alpha = fmV_Select(below, zero, fmV_Div(mu, safeJ));
	fmFloatV beta = fmV_Select(below, fmV_Mul(fmV_Sub(fmV_Mul(lambda, lBelow), mu), dlBelow),
	                           fmV_Div(fmV_Mul(lambda, lnJ), safeJ));
	fmFloatV gamma = fmV_Select(below, mu, zero);
	if (psi && mooney)
		*psi = fmV_Select(
		    below,
		    fmMooneyRivlinPlainEnergy(H, t, lBelow, mu, lambda, c01, 0.5f * material->mu - c01),
		    fmNeoHookeanEnergy(H, mu, lambda, c01));
	else if (psi)
		*psi = fmV_Select(below, fmNeoHookeanPlainEnergy(H, t, lBelow, mu, lambda),
		                  fmNeoHookeanEnergy(H, mu, lambda, 0.0f));

	for (int k = 0; k < 9; ++k)
	{
		fmFloatV diag = (k % 4 == 0) ? one : zero;
		fmFloatV cof = fmV_Add(
		    fmV_Sub(fmV_Mul(fmV_Add(onePlusT, c2), diag), fmV_Mul(onePlusT, HT.m[k])), HT2.m[k]);
		fmFloatV fjMinusCof = fmV_Sub(fmV_Add(fmV_Add(fmV_Mul(d, diag), fmV_Mul(onePlusJ, H->m[k])),
		                                      fmV_Mul(onePlusT, HT.m[k])),
		                              HT2.m[k]);
		fmFloatV F = fmV_Add(diag, H->m[k]);
		P->m[k] =
		    fmV_Add(fmV_Add(fmV_Mul(alpha, fjMinusCof), fmV_Mul(beta, cof)), fmV_Mul(gamma, F));
	}
	if (!mooney)
		return;
	// Mooney-Rivlin's 4 C01 F (tr G I - G) = 4 C01 (tr G F - F G).
	fmMat3V G = fmGreenStrain(H), F = *H;
	for (int k = 0; k < 9; k += 4)
		F.m[k] = fmV_Add(one, F.m[k]);
	fmMat3V FG = fmMat3V_Mul(&F, &G);
	fmFloatV trG = fmMat3V_Trace(&G), fourC01 = fmV_Set(4.0f * c01);
	for (int k = 0; k < 9; ++k)
		P->m[k] = fmV_Add(P->m[k], fmV_Mul(fourC01, fmV_Sub(fmV_Mul(trG, F.m[k]), FG.m[k])));
}

// ---- isochoric Neo-Hookean (CalculiX's, material_invariant.c) ----------------------------------
// psi = C10 (g I1 - 3) + kappa/2 (J - 1)^2, C10 = mu/2, kappa = lambda + 2/3 mu, g = J^(-2/3)
// (continued below the clamp c by its Taylor polynomial, as the reference). P = 2 C10 g F +
// (C10 g' I1 + kappa (J - 1)) cof F; above the clamp g' = -2/3 g / J and F - I1/3 F^-T =
// F^-T dev(C) = 2 F^-T dev(G), so P = 2 mu (g / J) cof(F) dev(G) + kappa (J - 1) cof F: no term
// of order one cancels at small strain.

// J^(-1/3) for finite J > 0, from +, -, *, / and bit operations (the same bits on every target):
// a first guess from the bits (their third by shifts, within 1% of the exponent's third) and
// four Newton steps y <- y (4 - J y^3) / 3 (the error e goes to about 2 e^2).
FM_INLINE fmFloatV fmV_InvCbrt(fmFloatV J)
{
	fmIntV i = fmV_Bits(J), third = fmI_Set(0);
	for (int shift = 2; shift <= 16; shift += 2)
		third = fmI_Add(third, fmI_ShiftRight(i, shift));
	fmFloatV y = fmV_FromBits(fmI_Sub(fmI_Set(0x54a2fa8c), third));
	const fmFloatV four = fmV_Set(4.0f), oneThird = fmV_Set(1.0f / 3.0f);
	for (int k = 0; k < 4; ++k)
		y = fmV_Mul(fmV_Mul(y, oneThird), fmV_Sub(four, fmV_Mul(J, fmV_Mul(y, fmV_Mul(y, y)))));
	return y;
}

// r = 3 ((1 + k)^(-1/3) - 1) + k, of second order in k: its series to k^9 for |k| < 0.15 (the next
// term below 1e-7 of r), else directly from @p g = (1 + k)^(-1/3).
FM_INLINE fmFloatV fmIsochoricRemainder(fmFloatV k, fmFloatV g)
{
	static const float c[] = {-135850.0f / 531441.0f, 5434.0f / 19683.0f, -1976.0f / 6561.0f,
	                          728.0f / 2187.0f,       -91.0f / 243.0f,    35.0f / 81.0f,
	                          -14.0f / 27.0f,         2.0f / 3.0f};
	fmFloatV series = fmV_Set(c[0]);
	for (int n = 1; n < 8; ++n)
		series = fmV_Add(fmV_Set(c[n]), fmV_Mul(k, series));
	series = fmV_Mul(fmV_Mul(k, k), series);
	fmFloatV direct = fmV_Add(fmV_Mul(fmV_Set(3.0f), fmV_Sub(g, fmV_Set(1.0f))), k);
	return fmV_Select(fmV_Less(fmV_Abs(k), fmV_Set(0.15f)), series, direct);
}

// Above the clamp: C10 (g I1 - 3) with I1 = 3 + 2 tr G, g = 1 + q: 3 q + 2 tr G + 2 q tr G, and
// 3 q + 2 tr G = r - 4 c2(G) - 8 det G (k = J^2 - 1 = 2 tr G + 4 c2 + 8 det G, as Neo-Hookean's).
// @p y = J^(-1/3), @p j = J - 1.
FM_NOINLINE fmFloatV fmIsochoricEnergy(const fmMat3V* H, fmFloatV y, fmFloatV j, fmFloatV mu,
                                       fmFloatV kappa)
{
	const fmFloatV half = fmV_Set(0.5f), two = fmV_Set(2.0f), four = fmV_Set(4.0f);
	fmGreenInvariants g = fmGreenInvariants_Make(H);
	fmFloatV t = g.t, c2 = g.c2, det = g.det, k = g.k;
	fmFloatV r = fmIsochoricRemainder(k, fmV_Mul(y, y));
	fmFloatV q = fmV_Mul(fmV_Sub(r, k), fmV_Set(1.0f / 3.0f));
	fmFloatV iso = fmV_Add(fmV_Sub(r, fmV_Add(fmV_Mul(four, c2), fmV_Mul(fmV_Set(8.0f), det))),
	                       fmV_Mul(two, fmV_Mul(q, t)));
	return fmV_Add(fmV_Mul(fmV_Mul(half, mu), iso), fmV_Mul(fmV_Mul(half, kappa), fmV_Mul(j, j)));
}

FM_INLINE void fmIsochoricStress(const fmMat3V* H, fmFloatV mu, fmFloatV lambda, fmMat3V* P,
                                 fmFloatV* psi)
{
	const fmFloatV one = fmV_Set(1.0f), zero = fmV_Set(0.0f), half = fmV_Set(0.5f);
	const fmFloatV kappa = fmV_Add(lambda, fmV_Mul(fmV_Set(2.0f / 3.0f), mu));
	fmNearIdentity h;
	fmNearIdentity_Make(H, &h);
	fmFloatV J = fmV_Add(one, h.j);
	// Below the clamp c = 0.2: g = gc + g1 d + g2 d^2 / 2, g' = g1 + g2 d, d = J - c.
	const float clamp = 0.2f, gc = 2.9240177382128656f, g1 = -9.746725794042884f,
	            g2 = 81.22271495035737f;
	fmIntV below = fmV_Less(J, fmV_Set(clamp));
	fmFloatV d = fmV_Sub(J, fmV_Set(clamp));
	fmFloatV gBelow =
	    fmV_Add(fmV_Set(gc), fmV_Mul(d, fmV_Add(fmV_Set(g1), fmV_Mul(fmV_Set(0.5f * g2), d))));
	fmFloatV dgBelow = fmV_Add(fmV_Set(g1), fmV_Mul(fmV_Set(g2), d));
	fmFloatV i1 = fmV_Add(fmV_Set(3.0f), fmV_Add(fmV_Add(h.t, h.t), fmMat3V_Contract(H, H)));
	// Above it (J >= c > 0): 2 mu g / J, with g = (J^(-1/3))^2.
	fmFloatV safeJ = fmV_Select(below, one, J), y = fmV_InvCbrt(safeJ);
	fmFloatV alpha = fmV_Div(fmV_Mul(fmV_Add(mu, mu), fmV_Mul(y, y)), safeJ);
	fmFloatV gammaBelow = fmV_Mul(mu, gBelow);
	fmFloatV beta =
	    fmV_Add(fmV_Select(below, fmV_Mul(fmV_Mul(half, mu), fmV_Mul(dgBelow, i1)), zero),
	            fmV_Mul(kappa, h.j));
	fmMat3V cof, G = fmGreenStrain(H);
	for (int k = 0; k < 9; ++k)
		cof.m[k] = fmNearIdentity_Cofactor(&h, k);
	fmFloatV trG3 = fmV_Mul(fmMat3V_Trace(&G), fmV_Set(1.0f / 3.0f));
	for (int k = 0; k < 9; k += 4)
		G.m[k] = fmV_Sub(G.m[k], trG3); // dev(G)
	fmMat3V M = fmMat3V_Mul(&cof, &G);
	for (int k = 0; k < 9; ++k)
	{
		fmFloatV F = (k % 4 == 0) ? fmV_Add(one, H->m[k]) : H->m[k];
		fmFloatV first = fmV_Select(below, fmV_Mul(gammaBelow, F), fmV_Mul(alpha, M.m[k]));
		P->m[k] = fmV_Add(first, fmV_Mul(beta, cof.m[k]));
	}
	if (psi)
	{
		fmFloatV plain =
		    fmV_Add(fmV_Mul(fmV_Mul(half, mu), fmV_Sub(fmV_Mul(gBelow, i1), fmV_Set(3.0f))),
		            fmV_Mul(fmV_Mul(half, kappa), fmV_Mul(h.j, h.j)));
		*psi = fmV_Select(below, plain, fmIsochoricEnergy(H, y, h.j, mu, kappa));
	}
}

FM_INLINE fmFloatV fmV_Max(fmFloatV a, fmFloatV b)
{
	return fmV_Select(fmV_Less(a, b), b, a);
}

// The lanes whose det F is surely positive, from float: J = det(I + H) above a bound on its
// error. With a = max |Du|, d = max |Dm^-1|, m = 1 + max |H| (at least every |F_ij|), each
// entry of H is off by at most 15 u a d (u = 2^-24: the roundings of Du and Dm^-1 to float, the
// products and sums of H = Du Dm^-1), and det F by 18 m^2 times that plus about 12 u m^3 of its
// own roundings: 1.6e-5 m^2 a d + 7e-7 m^3. The bound takes 60 and 14 times those. Non-finite
// values fail the comparison; the double-precision recheck decides them.
FM_INLINE fmIntV fmV_SurelyUpright(const fmMat3V* Du, const fmMat3V* DmInv, const fmMat3V* H)
{
	const fmFloatV one = fmV_Set(1.0f), zero = fmV_Set(0.0f);
	fmFloatV a = zero, d = zero, h = zero;
	fmMat3V F;
	for (int k = 0; k < 9; ++k)
	{
		a = fmV_Max(a, fmV_Abs(Du->m[k]));
		d = fmV_Max(d, fmV_Abs(DmInv->m[k]));
		h = fmV_Max(h, fmV_Abs(H->m[k]));
		F.m[k] = k % 4 == 0 ? fmV_Add(one, H->m[k]) : H->m[k];
	}
	fmFloatV m = fmV_Add(one, h), m2 = fmV_Mul(m, m);
	fmFloatV bound = fmV_Add(fmV_Mul(fmV_Set(1e-3f), fmV_Mul(m2, fmV_Mul(a, d))),
	                         fmV_Mul(fmV_Set(1e-5f), fmV_Mul(m2, m)));
	return fmV_Less(bound, fmMat3V_Det(&F));
}

// Lanes [o, o + FM_VLANES) of the batch, from the displacements @p u of its block (4 doubles a
// vertex); with @p laneEnergy NULL the energy's terms are skipped (a step's pass does not pay for
// them).
FM_INLINE bool fmKernelVector(const fmTetBatch* batch, const double* u, int o,
                              fmMaterialModel model, const fmKernelMaterial* material,
                              fmTetBatchForces* out, float* laneEnergy)
{
	fmMat3V Du;
	fmV_GatherEdges(u, batch->row, o, Du.m);
	fmMat3V DmInv = fmMat3V_Load(&batch->dmInv[0][o]);
	fmMat3V H = fmMat3V_Mul(&Du, &DmInv);
	fmFloatV mu = fmV_Set(material->mu), lambda = fmV_Set(material->lambda);
	fmMat3V P;
	fmFloatV psi = fmV_Set(0.0f);
	fmFloatV* energy = laneEnergy ? &psi : NULL;
	fmIntV fallback = fmI_Set(0);
	if (model == fm_stvk)
	{
		fmStvkStress(&H, mu, lambda, &P, energy);
		fallback = fmStvkBelowFloor(&H);
	}
	else if (model == fm_corotated)
		fmCorotatedStress(&H, mu, lambda, &P, &fallback, energy);
	else if (model == fm_neoHookean)
		fmNeoHookeanStress(&H, material, false, &P, energy);
	else if (model == fm_mooneyRivlin)
		fmNeoHookeanStress(&H, material, true, &P, energy);
	else if (model == fm_neoHookeanIsochoric)
		fmIsochoricStress(&H, mu, lambda, &P, energy);
	else
		fmLinearStress(&H, mu, lambda, &P, energy);
	// force on node k + 1 = -V0 P (row k of Dm^-1): M = P Dm^-T, column k.
	fmMat3V DmInvT = fmMat3V_Transpose(&DmInv);
	fmMat3V M = fmMat3V_Mul(&P, &DmInvT);
	fmFloatV volume = fmV_Load(batch->volume + o);
	if (energy)
	{
		fmV_Store(laneEnergy + o, fmV_Mul(volume, psi));
		fmIntV upright = fmV_SurelyUpright(&Du, &DmInv, &H);
		memcpy(out->upright + o, &upright, sizeof upright);
	}
	fmFloatV minusV = fmV_Sub(fmV_Set(0.0f), volume), zero = fmV_Set(0.0f);
	fmFloatV node0[3];
	for (int i = 0; i < 3; ++i)
	{
		fmFloatV sum = zero;
		for (int k = 0; k < 3; ++k)
			sum = fmV_Add(sum, fmV_Mul(minusV, M.m[3 * i + k]));
		node0[i] = fmV_Sub(zero, sum);
	}
	fmV_StoreNodes(out->force[0] + o, node0[0], node0[1], node0[2]);
	for (int k = 0; k < 3; ++k)
		fmV_StoreNodes(out->force[k + 1] + o, fmV_Mul(minusV, M.m[k]), fmV_Mul(minusV, M.m[3 + k]),
		               fmV_Mul(minusV, M.m[6 + k]));
	memcpy(out->fallback + o, &fallback, sizeof fallback);
	return fmI_Any(fallback);
}

// The kernel of one material model: the batch's vectors one after another. A function of its
// own per model (the model a constant in it): one body for all four left the compiler spilling
// StVK's matrices.
#define FM_MODEL_KERNEL(name, model)                                                               \
	FM_NOINLINE bool name(const fmTetBatch* batch, const double* u,                                \
	                      const fmKernelMaterial* material, fmTetBatchForces* out,                 \
	                      float* laneEnergy)                                                       \
	{                                                                                              \
		bool fallback = false;                                                                     \
		for (int o = 0; o < FM_LANES; o += FM_VLANES)                                              \
			fallback |= fmKernelVector(batch, u, o, model, material, out, laneEnergy);             \
		return fallback;                                                                           \
	}
FM_MODEL_KERNEL(fmKernelLinear, fm_linear)
FM_MODEL_KERNEL(fmKernelStvk, fm_stvk)
FM_MODEL_KERNEL(fmKernelNeoHookean, fm_neoHookean)
FM_MODEL_KERNEL(fmKernelCorotated, fm_corotated)
FM_MODEL_KERNEL(fmKernelMooneyRivlin, fm_mooneyRivlin)
FM_MODEL_KERNEL(fmKernelIsochoric, fm_neoHookeanIsochoric)

bool FM_KERNEL_NAME(fmTetKernel_Forces)(const fmTetBatch* batch, const double* u,
                                        const fmKernelMaterial* material, fmTetBatchForces* out,
                                        float* laneEnergy)
{
	switch (material->model)
	{
	case fm_stvk:
		return fmKernelStvk(batch, u, material, out, laneEnergy);
	case fm_neoHookean:
		return fmKernelNeoHookean(batch, u, material, out, laneEnergy);
	case fm_corotated:
		return fmKernelCorotated(batch, u, material, out, laneEnergy);
	case fm_mooneyRivlin:
		return fmKernelMooneyRivlin(batch, u, material, out, laneEnergy);
	case fm_neoHookeanIsochoric:
		return fmKernelIsochoric(batch, u, material, out, laneEnergy);
	default:
		return fmKernelLinear(batch, u, material, out, laneEnergy);
	}
}

void FM_KERNEL_NAME(fmTetKernel_SumForces)(const float* forces, const uint16_t* offsets,
                                           const int* start, int count, double* sums)
{
	// Two vertices at a time: two dependency chains (each vertex's own sum in its order).
	int i = 0;
	for (; i + 1 < count; i += 2)
		fmSumEntriesPair(forces, offsets + start[i], start[i + 1] - start[i],
		                 start[i + 2] - start[i + 1], sums + 3 * i, sums + 3 * i + 3);
	if (i < count)
		fmSumEntries(forces, offsets + start[i], start[i + 1] - start[i], sums + 3 * i);
}

void FM_KERNEL_NAME(fmTetKernel_WeightedSums)(const double* v, const int* offsets,
                                              const double* weights, const int* start, int first,
                                              int end, double* sums)
{
	int i = first;
	for (; i + 1 < end; i += 2)
		fmWeightedSumPair(v, offsets + start[i], weights + start[i], start[i + 1] - start[i],
		                  start[i + 2] - start[i + 1], sums + 3 * i, sums + 3 * i + 3);
	if (i < end)
		fmWeightedSum(v, offsets + start[i], weights + start[i], start[i + 1] - start[i],
		              sums + 3 * i);
}

// ---- batched polar rotations --------------------------------------------------------------------
// Plain loops over the lanes, which the compiler vectorises at the variant's width; every
// expression is fmPolarRotationFast's (fmDDot, fmDet and fmCofactor of fm_math.h written out in
// their order), and square roots, taken lane by lane, are rare (only for scaled steps).

#define FM_PL FM_POLAR_LANES

// C = cof(X) and d = det X by its first row, lane by lane.
FM_INLINE void fmPolarCofactor(const double X[9][FM_PL], double C[9][FM_PL], double d[FM_PL])
{
	for (int l = 0; l < FM_PL; ++l)
	{
		C[0][l] = X[4][l] * X[8][l] - X[5][l] * X[7][l];
		C[1][l] = X[5][l] * X[6][l] - X[3][l] * X[8][l];
		C[2][l] = X[3][l] * X[7][l] - X[4][l] * X[6][l];
		C[3][l] = X[2][l] * X[7][l] - X[1][l] * X[8][l];
		C[4][l] = X[0][l] * X[8][l] - X[2][l] * X[6][l];
		C[5][l] = X[1][l] * X[6][l] - X[0][l] * X[7][l];
		C[6][l] = X[1][l] * X[5][l] - X[2][l] * X[4][l];
		C[7][l] = X[2][l] * X[3][l] - X[0][l] * X[5][l];
		C[8][l] = X[0][l] * X[4][l] - X[1][l] * X[3][l];
		d[l] = X[0][l] * C[0][l] + X[1][l] * C[1][l] + X[2][l] * C[2][l];
	}
}

// The sum over k of A[k] B[k] of every lane, each in k order (fmDDot).
FM_INLINE void fmPolarDots(const double A[9][FM_PL], const double B[9][FM_PL], double s[FM_PL])
{
	for (int l = 0; l < FM_PL; ++l)
		s[l] = 0.0;
	for (int k = 0; k < 9; ++k)
		for (int l = 0; l < FM_PL; ++l)
			s[l] += A[k][l] * B[k][l];
}

// Which lanes start: fmPolarRotationFast's shape test, and whether their first step is scaled
// (masks of all bits set, as wide as a double, which the compiler blends with).
FM_INLINE void fmPolarStart(const fmPolarBatch* batch, int64_t active[FM_PL], int64_t scaled[FM_PL])
{
	double norms2[FM_PL];
	fmPolarDots(batch->F, batch->F, norms2);
	for (int l = 0; l < FM_PL; ++l)
	{
		const double* m[9];
		for (int k = 0; k < 9; ++k)
			m[k] = &batch->F[k][l];
		double norm2 = norms2[l];
		double det = *m[0] * (*m[4] * *m[8] - *m[5] * *m[7]) -
		             *m[1] * (*m[3] * *m[8] - *m[5] * *m[6]) +
		             *m[2] * (*m[3] * *m[7] - *m[4] * *m[6]);
		active[l] = det > FM_POLAR_MIN_SHAPE * norm2 * sqrt(norm2) && isfinite(norm2) ? -1 : 0;
		scaled[l] =
		    fabs(norm2 - 3.0) > FM_POLAR_NEAR_ROTATION || fabs(det - 1.0) > FM_POLAR_NEAR_ROTATION
		        ? -1
		        : 0;
	}
}

// One step X <- a X + b C of every lane (a lane done or refused keeps its X), with each lane's
// change |step|^2.
FM_INLINE void fmPolarStep(double X[9][FM_PL], const double C[9][FM_PL], const double d[FM_PL],
                           const int64_t active[FM_PL], const int64_t scaled[FM_PL],
                           double change[FM_PL])
{
	double z[FM_PL], a[FM_PL], b[FM_PL];
	int64_t anyScaled = 0;
	for (int l = 0; l < FM_PL; ++l)
		z[l] = 1.0, anyScaled |= scaled[l] & active[l];
	if (anyScaled)
	{
		// Every lane at once; lanes not scaled take ones instead, whose root is exactly 1 (and
		// raises no floating-point exception).
		double cc[FM_PL], xx[FM_PL];
		fmPolarDots(C, C, cc);
		fmPolarDots(X, X, xx);
		for (int l = 0; l < FM_PL; ++l)
		{
			// (Selects of values computed in every lane, masks as wide as a double: the loop
			// vectorises.)
			int64_t scale = scaled[l] & active[l];
			double dd = d[l] * d[l];
			double num = scale ? cc[l] : 1.0, den = scale ? dd : 1.0, xs = scale ? xx[l] : 1.0;
			z[l] = sqrt(sqrt(num / den) / sqrt(xs));
		}
	}
	for (int l = 0; l < FM_PL; ++l)
	{
		// Lanes done or refused divide by 1 instead (their steps are discarded).
		a[l] = 0.5 * z[l], b[l] = 0.5 / (z[l] * (active[l] ? d[l] : 1.0));
		change[l] = 0.0;
	}
	for (int k = 0; k < 9; ++k)
		for (int l = 0; l < FM_PL; ++l)
		{
			double next = a[l] * X[k][l] + b[l] * C[k][l];
			change[l] += (next - X[k][l]) * (next - X[k][l]);
			X[k][l] = active[l] ? next : X[k][l];
		}
}

// fmPolarRotationFast of every lane (one function for both entry points: not inlined twice).
FM_NOINLINE void fmPolarRun(fmPolarBatch* batch)
{
	double X[9][FM_PL], C[9][FM_PL], d[FM_PL], change[FM_PL];
	int64_t active[FM_PL], scaled[FM_PL], ok[FM_PL], any = 0; // masks: all bits set or none
	memcpy(X, batch->F, sizeof X);
	fmPolarStart(batch, active, scaled);
	for (int l = 0; l < FM_PL; ++l)
		ok[l] = 0, any |= active[l];
	for (int iteration = 0; iteration < FM_POLAR_MAX_ITERATIONS && any; ++iteration)
	{
		fmPolarCofactor(X, C, d);
		fmPolarStep(X, C, d, active, scaled, change);
		any = 0;
		for (int l = 0; l < FM_PL; ++l)
		{
			// A lane done keeps its X (fmPolarStep leaves lanes that are not active).
			int64_t done = active[l] & -(int64_t)(change[l] <= FM_POLAR_DONE * FM_POLAR_DONE);
			ok[l] |= done;
			active[l] &= ~done;
			scaled[l] = -(int64_t)(change[l] > 1e-4);
			any |= active[l];
		}
	}
	for (int l = 0; l < FM_PL; ++l)
		batch->ok[l] = ok[l] != 0;
	memcpy(batch->R, X, sizeof X);
}

void FM_KERNEL_NAME(fmTetKernel_Polar)(fmPolarBatch* batch)
{
	fmPolarRun(batch);
}

// ---- batched forces of one material: the fill, Neo-Hookean, corotated, inverted tets -----------
// Plain loops over the lanes, which the compiler vectorises at the variant's width; every
// expression is the scalar path's (fm_math.h's products and fmNeoHookean_Evaluate written out in
// their order; fmPolarCofactor and fmPolarDots above are fmCofactor with det F along the first row
// and the double contraction from 0.0).

void FM_KERNEL_NAME(fmTetKernel_FillForceBatch)(const double* x, const int* tets,
                                                const fmMat3* dmInv, const double* volume,
                                                int first, fmForceBatch* b)
{
	// (The 4 lanes' matrices are consecutive: 36 doubles from the first one's.)
	for (int o = 0; o < FM_FORCE_LANES; o += 4)
	{
		fmV_EdgesOf4Tets(x, tets + 4 * (size_t)(first + o), &b->Ds[0][o], FM_FORCE_LANES);
		fmV_TransposeOf4(dmInv[first + o].m, &b->dmInv[0][o], FM_FORCE_LANES);
	}
	for (int l = 0; l < FM_FORCE_LANES; ++l)
		b->volume[l] = volume[first + l];
}

// F = Ds Dm^-1 of every lane (fmTetDeformation's products).
FM_INLINE void fmLaneDeformation(const fmForceBatch* b, double F[9][FM_PL])
{
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			for (int l = 0; l < FM_PL; ++l)
				F[3 * i + j][l] = b->Ds[3 * i][l] * b->dmInv[j][l] +
				                  b->Ds[3 * i + 1][l] * b->dmInv[3 + j][l] +
				                  b->Ds[3 * i + 2][l] * b->dmInv[6 + j][l];
}

// The nodal forces of P (fmAddTetForces): H = P Dm^-T; node a's force is -V0 times H's column
// a - 1; node 0's entry their sum from 0.0 in node order.
FM_INLINE void fmLaneNodalForces(fmForceBatch* b, const double P[9][FM_PL])
{
	for (int i = 0; i < 3; ++i)
	{
		for (int l = 0; l < FM_PL; ++l)
			b->force[0][i][l] = 0.0;
		for (int a = 1; a < 4; ++a)
			for (int l = 0; l < FM_PL; ++l)
			{
				double h = P[3 * i][l] * b->dmInv[3 * (a - 1)][l] +
				           P[3 * i + 1][l] * b->dmInv[3 * (a - 1) + 1][l] +
				           P[3 * i + 2][l] * b->dmInv[3 * (a - 1) + 2][l];
				b->force[a][i][l] = -b->volume[l] * h;
				b->force[0][i][l] = b->force[0][i][l] + b->force[a][i][l];
			}
	}
}

void FM_KERNEL_NAME(fmTetKernel_NeoHookean)(fmForceBatch* b)
{
	double F[9][FM_PL], C[9][FM_PL], J[FM_PL], k[FM_PL], P[9][FM_PL];
	fmLaneDeformation(b, F);
	fmPolarCofactor(F, C, J);
	for (int l = 0; l < FM_PL; ++l)
	{
		// (I1 lane by lane: with fmPolarDots before this loop, Emscripten's clang 14 at -O3 with
		// -msimd128 got k wrong in every other lane; simd.batched_neo_hookean_forces_... caught
		// it in a WebAssembly build of the tests.)
		double I1 = 0.0, ln[3];
		for (int q = 0; q < 9; ++q)
			I1 += F[q][l] * F[q][l];
		fmClampedLogJ(J[l], ln);
		k[l] = (b->lambda * ln[0] - b->mu) * ln[1];
		b->psi[l] = 0.5 * b->mu * (I1 - 3.0) - b->mu * ln[0] + 0.5 * b->lambda * ln[0] * ln[0];
		b->ok[l] = true;
	}
	for (int e = 0; e < 9; ++e)
		for (int l = 0; l < FM_PL; ++l)
			P[e][l] = b->mu * F[e][l] + k[l] * C[e][l];
	fmLaneNodalForces(b, P);
}

#if !defined(__EMSCRIPTEN__) // (the .wasm line: the browser takes StVK one tet at a time)
// fmStvk_Evaluate (material.c) lane by lane: G = (F^T F - I) / 2 (fmGreenStrain's six sums),
// S = 2 mu G + lambda tr(G) I, P = F S, psi = mu G : G + lambda tr(G)^2 / 2. A lane below the
// volume floor's J (fmMaterial_StvkFloor) is not ok: the scalar path adds the floor there.
void FM_KERNEL_NAME(fmTetKernel_Stvk)(fmForceBatch* b)
{
	double F[9][FM_PL], C[9][FM_PL], J[FM_PL], G[9][FM_PL], S[9][FM_PL], P[9][FM_PL], GG[FM_PL];
	fmLaneDeformation(b, F);
	fmPolarCofactor(F, C, J);
	for (int i = 0; i < 3; ++i)
		for (int j = i; j < 3; ++j)
			for (int l = 0; l < FM_PL; ++l)
			{
				double sum =
				    F[i][l] * F[j][l] + F[3 + i][l] * F[3 + j][l] + F[6 + i][l] * F[6 + j][l];
				G[3 * i + j][l] = G[3 * j + i][l] = 0.5 * (i == j ? sum - 1.0 : sum);
			}
	fmPolarDots(G, G, GG);
	for (int l = 0; l < FM_PL; ++l)
	{
		double tr = G[0][l] + G[4][l] + G[8][l];
		for (int e = 0; e < 9; ++e)
			S[e][l] = 2.0 * b->mu * G[e][l];
		for (int i = 0; i < 3; ++i)
			S[4 * i][l] = S[4 * i][l] + b->lambda * tr;
		b->psi[l] = b->mu * GG[l] + 0.5 * b->lambda * tr * tr;
		b->ok[l] = !(J[l] < FM_STVK_FLOOR_J);
	}
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			for (int l = 0; l < FM_PL; ++l)
				P[3 * i + j][l] = F[3 * i][l] * S[j][l] + F[3 * i + 1][l] * S[3 + j][l] +
				                  F[3 * i + 2][l] * S[6 + j][l];
	fmLaneNodalForces(b, P);
}
#endif

void FM_KERNEL_NAME(fmTetKernel_Inverted)(const fmForceBatch* b, int count, unsigned char* inverted)
{
	double F[9][FM_PL], C[9][FM_PL], J[FM_PL];
	fmLaneDeformation(b, F);
	fmPolarCofactor(F, C, J);
	for (int l = 0; l < count; ++l)
		inverted[l] = !(J[l] > 0.0);
}

#if !defined(__EMSCRIPTEN__) // (the .wasm line: the browser takes the proxy one tet at a time)
void FM_KERNEL_NAME(fmTetKernel_Proxy)(const fmForceBatch* b, int count, double* largest)
{
	double F[9][FM_PL], C[9][FM_PL], J[FM_PL];
	fmLaneDeformation(b, F);
	fmPolarCofactor(F, C, J);
	for (int l = 0; l < count; ++l)
	{
		double I1 = 0.0;
		for (int q = 0; q < 9; ++q)
			I1 += F[q][l] * F[q][l];
		double p = !(J[l] > 0.0) ? INFINITY : fmMax(I1, I1 * I1 / (4.0 * J[l] * J[l]));
		*largest = fmMax(*largest, p);
	}
}
#endif

// fmCorotated_Stress (material_stretch.c) lane by lane: D = F - R, J = det F (by the first row of
// cof F, the same bits as fmDet), P = 2 mu D + lambda (J - 1) cof F, psi = mu D : D +
// lambda (J - 1)^2 / 2. A lane the polar iteration declines takes D = F - F instead (its results
// are discarded; no exception from a rotation it did not find).
void FM_KERNEL_NAME(fmTetKernel_Corotated)(fmForceBatch* b)
{
	fmPolarBatch polar;
	double C[9][FM_PL], J[FM_PL], D[9][FM_PL], P[9][FM_PL], DD[FM_PL];
	fmLaneDeformation(b, polar.F);
	fmPolarRun(&polar);
	fmPolarCofactor(polar.F, C, J);
	for (int e = 0; e < 9; ++e)
		for (int l = 0; l < FM_PL; ++l)
			D[e][l] = polar.F[e][l] + -1.0 * (polar.ok[l] ? polar.R[e][l] : polar.F[e][l]);
	fmPolarDots(D, D, DD);
	for (int l = 0; l < FM_PL; ++l)
	{
		b->psi[l] = b->mu * DD[l] + 0.5 * b->lambda * (J[l] - 1.0) * (J[l] - 1.0);
		b->ok[l] = polar.ok[l];
	}
	for (int e = 0; e < 9; ++e)
		for (int l = 0; l < FM_PL; ++l)
			P[e][l] = 2.0 * b->mu * D[e][l] + b->lambda * (J[l] - 1.0) * C[e][l];
	fmLaneNodalForces(b, P);
}
