// 3x3 SVD (fmSvd3), polar rotation and symmetric eigen-decomposition: orthonormal proper
// factors, reconstruction, ordering and the inversion sign, on random, repeated, rank-deficient,
// reflected and extreme-scale matrices.
#include "support.h"
#include "math/svd3.h"
#include "test.h"

#include <string.h>

static fmMat3 diag3(double a, double b, double c)
{
	fmMat3 D = {{a, 0, 0, 0, b, 0, 0, 0, c}};
	return D;
}

// R1 diag(s) R2
static fmMat3 composeRandom(double a, double b, double c)
{
	fmMat3 R1 = fmTestRandomRotation(), R2 = fmTestRandomRotation(), D = diag3(a, b, c);
	fmMat3 T = fmMatMul(&R1, &D);
	return fmMatMul(&T, &R2);
}

static double frobenius(const fmMat3* A)
{
	return sqrt(fmDDot(A, A));
}

// Distance of Q^T Q from the identity.
static double orthoError(const fmMat3* Q)
{
	fmMat3 QtQ = fmMatTMul(Q, Q);
	fmMat3 I = fmIdentity3();
	fmMat3 E = fmMatMulAdd(&QtQ, -1.0, &I);
	return frobenius(&E);
}

// Checks every promise of fmSvd3 on F; returns the relative reconstruction error.
static double checkSvd(const fmMat3* F, double tol, int* failures_)
{
	fmMat3 U, V;
	fmVec3 s;
	fmSvd3(F, &U, &s, &V);
	CHECK_NEAR(orthoError(&U), 0.0, 1e-14 * 10);
	CHECK_NEAR(orthoError(&V), 0.0, 1e-14 * 10);
	CHECK_NEAR(fmDet(&U), 1.0, 1e-13);
	CHECK_NEAR(fmDet(&V), 1.0, 1e-13);
	CHECK(s.x >= s.y);
	CHECK(s.y >= fabs(s.z));
	CHECK(s.y >= 0.0);
	double norm = frobenius(F);
	// The sign of s2 follows det F wherever det F is resolvable at this precision.
	double detF = fmDet(F);
	if (fabs(detF) > 1e-10 * norm * norm * norm)
		CHECK((s.z < 0.0) == (detF < 0.0));
	fmMat3 D = diag3(s.x, s.y, s.z);
	fmMat3 UD = fmMatMul(&U, &D);
	fmMat3 back = fmMatMulT(&UD, &V);
	fmMat3 E = fmMatMulAdd(&back, -1.0, F);
	double rel = norm > 0.0 ? frobenius(&E) / norm : frobenius(&E);
	CHECK_NEAR(rel, 0.0, tol);
	return rel;
}

TEST(random_matrices_reconstruct_to_1e13)
{
	double worst = 0.0;
	for (int n = 0; n < 2000; ++n)
	{
		fmMat3 F;
		for (int k = 0; k < 9; ++k)
			F.m[k] = fmTestRandom(-2, 2);
		worst = fmax(worst, checkSvd(&F, 1e-13, failures_));
	}
	CHECK(worst < 1e-13);
}

TEST(singular_values_match_construction)
{
	// Known singular values, random rotations: well separated, graded, clustered, inverted.
	const double cases[][3] = {{3, 2, 1},       {1, 1e-4, 1e-8}, {5 + 1e-9, 5, 5 - 1e-9},
	                           {2, 1, -0.5},    {1, 1, -1},      {1e3, 1, 1e-3},
	                           {1.5, 1.5, 1.5}, {2, 2, 1},       {1, 0.5, -1e-6}};
	for (int c = 0; c < (int)(sizeof cases / sizeof cases[0]); ++c)
		for (int trial = 0; trial < 50; ++trial)
		{
			const double* e = cases[c];
			fmMat3 F = composeRandom(e[0], e[1], e[2]);
			checkSvd(&F, 1e-14 * 20, failures_);
			fmMat3 U, V;
			fmVec3 s;
			fmSvd3(&F, &U, &s, &V);
			// Entries of F carry rounding of about eps |F|, so the values are exact to that.
			double tol = 1e-14 * 20 * e[0];
			CHECK_NEAR(s.x, e[0], tol);
			CHECK_NEAR(s.y, e[1], tol);
			CHECK_NEAR(s.z, e[2], tol);
		}
}

TEST(special_matrices)
{
	fmMat3 R = fmTestRandomRotation();
	fmMat3 cases[] = {
	    fmIdentity3(),
	    R,
	    diag3(2, 2, 1),
	    diag3(1, 1, -1),   // reflection
	    diag3(-1, -1, -1), // point inversion: s = (1, 1, -1)
	    diag3(-2, 3, 1),
	    diag3(2, 1, 0), // rank 2
	    diag3(0, 3, 0), // rank 1
	    fmZero3(),
	    {{1, 2, 3, 2, 4, 6, -1, -2, -3}},      // rank 1, non-diagonal
	    {{1, 0, 0, 0, 1, 0, 0, 0, 1e-300}},    // nearly flat
	    {{0, 1, 0, 1, 0, 0, 0, 0, 1}},         // swap: det -1
	    {{1, 1e-12, 0, 0, 1, 1e-12, 0, 0, 1}}, // nearly identity, tiny shear
	};
	for (int c = 0; c < (int)(sizeof cases / sizeof cases[0]); ++c)
		checkSvd(&cases[c], 1e-15 * 10, failures_);

	fmMat3 U, V;
	fmVec3 s;
	fmSvd3(&cases[4], &U, &s, &V);
	CHECK_NEAR(s.x, 1.0, 1e-15);
	CHECK_NEAR(s.z, -1.0, 1e-15);
	fmSvd3(&cases[8], &U, &s, &V);
	CHECK(s.x == 0.0 && s.y == 0.0 && s.z == 0.0);
	fmSvd3(&cases[9], &U, &s, &V);
	CHECK_NEAR(s.x, sqrt(14.0) * sqrt(6.0), 1e-13);
	CHECK_NEAR(s.y, 0.0, 1e-14);
	fmSvd3(&cases[0], &U, &s, &V);
	CHECK(s.x == 1.0 && s.y == 1.0 && s.z == 1.0);
}

TEST(rank_deficient_random)
{
	for (int n = 0; n < 300; ++n)
	{
		fmMat3 F2 = composeRandom(fmTestRandom(0.5, 2), fmTestRandom(0.1, 0.5), 0.0);
		checkSvd(&F2, 1e-14 * 10, failures_);
		fmMat3 F1 = composeRandom(fmTestRandom(0.5, 2), 0.0, 0.0);
		checkSvd(&F1, 1e-14 * 10, failures_);
		// Two equal and one opposite: an inverted, otherwise uniform scaling.
		fmMat3 Fi = composeRandom(1.3, 1.3, -1.3);
		checkSvd(&Fi, 1e-14 * 10, failures_);
	}
}

TEST(extreme_scales)
{
	const double scales[] = {1e-320, 1e-300, 1e-150, 1e-20, 1e20, 1e150, 1e300};
	for (int c = 0; c < 7; ++c)
		for (int n = 0; n < 50; ++n)
		{
			fmMat3 F;
			for (int k = 0; k < 9; ++k)
				F.m[k] = scales[c] * fmTestRandom(-1, 1);
			fmMat3 U, V;
			fmVec3 s;
			fmSvd3(&F, &U, &s, &V);
			CHECK(isfinite(s.x) && isfinite(s.y) && isfinite(s.z));
			CHECK_NEAR(orthoError(&U), 0.0, 1e-13);
			CHECK_NEAR(orthoError(&V), 0.0, 1e-13);
			// Reconstruct in scaled units so the check itself cannot overflow.
			fmMat3 D = diag3(s.x / scales[c], s.y / scales[c], s.z / scales[c]);
			fmMat3 UD = fmMatMul(&U, &D);
			fmMat3 back = fmMatMulT(&UD, &V);
			fmMat3 Fs;
			for (int k = 0; k < 9; ++k)
				Fs.m[k] = F.m[k] / scales[c];
			fmMat3 E = fmMatMulAdd(&back, -1.0, &Fs);
			// Subnormal singular values keep only a few digits; normal ones all of them.
			double tol = scales[c] < 1e-307 ? 1e-2 : 1e-13;
			CHECK_NEAR(frobenius(&E) / frobenius(&Fs), 0.0, tol);
		}
}

TEST(non_finite_input_gives_nan_not_a_hang)
{
	fmMat3 F = fmIdentity3();
	F.m[4] = NAN;
	fmMat3 U, V;
	fmVec3 s;
	fmSvd3(&F, &U, &s, &V);
	CHECK(isnan(s.x));
	F.m[4] = INFINITY;
	fmSvd3(&F, &U, &s, &V);
	CHECK(isnan(s.z));
}

TEST(polar_rotation)
{
	for (int n = 0; n < 500; ++n)
	{
		fmMat3 R0 = fmTestRandomRotation();
		fmMat3 S = {
		    {fmTestRandom(0.5, 2), 0, 0, 0, fmTestRandom(0.5, 2), 0, 0, 0, fmTestRandom(0.5, 2)}};
		fmMat3 Q = fmTestRandomRotation();
		// F = R0 (Q S Q^T): its polar rotation is R0.
		fmMat3 QS = fmMatMul(&Q, &S);
		fmMat3 Sym = fmMatMulT(&QS, &Q);
		fmMat3 F = fmMatMul(&R0, &Sym);
		fmMat3 R = fmPolarRotation(&F);
		fmMat3 E = fmMatMulAdd(&R, -1.0, &R0);
		CHECK_NEAR(frobenius(&E), 0.0, 1e-13);
		CHECK_NEAR(fmDet(&R), 1.0, 1e-13);
	}
	// Inverted F: R stays a rotation and R^T F is symmetric (with a negative eigenvalue).
	for (int n = 0; n < 200; ++n)
	{
		fmMat3 F = composeRandom(2, 1, -0.3);
		fmMat3 R = fmPolarRotation(&F);
		CHECK_NEAR(fmDet(&R), 1.0, 1e-13);
		fmMat3 S = fmMatTMul(&R, &F);
		CHECK_NEAR(S.m[1], S.m[3], 1e-13);
		CHECK_NEAR(S.m[2], S.m[6], 1e-13);
		CHECK_NEAR(S.m[5], S.m[7], 1e-13);
		CHECK(fmDet(&S) < 0.0);
	}
}

// The Newton polar rotation used by the corotated energy: the SVD's R = U V^T to round-off on
// every F it takes (small strains, large stretches, near-rotations), and it declines inverted,
// flat and non-finite F so that those take the SVD's sign convention.
TEST(fast_polar_rotation_matches_the_svd)
{
	const double stretches[4][2] = {{0.999, 1.001}, {0.5, 2.0}, {0.1, 3.0}, {1.0, 1.0}};
	int taken = 0;
	for (int kind = 0; kind < 4; ++kind)
		for (int n = 0; n < 300; ++n)
		{
			double lo = stretches[kind][0], hi = stretches[kind][1];
			fmMat3 F =
			    composeRandom(fmTestRandom(lo, hi), fmTestRandom(lo, hi), fmTestRandom(lo, hi));
			fmMat3 R, Rsvd = fmPolarRotation(&F);
			if (!fmPolarRotationFast(&F, &R))
				continue;
			taken += 1;
			fmMat3 E = fmMatMulAdd(&R, -1.0, &Rsvd);
			CHECK_NEAR(frobenius(&E), 0.0, 1e-14);
			CHECK_NEAR(orthoError(&R), 0.0, 1e-15);
		}
	printf("  fast polar took %d of 1200 matrices\n", taken);
	CHECK(taken == 1200); // condition numbers up to 30: far from the limit of about 500
	fmMat3 R = fmIdentity3(), keep = R;
	fmMat3 inverted = composeRandom(1.0, 1.0, -1.0), flat = composeRandom(1.0, 1.0, 1e-5);
	fmMat3 nan = diag3(NAN, 1.0, 1.0);
	CHECK(!fmPolarRotationFast(&inverted, &R));
	CHECK(!fmPolarRotationFast(&flat, &R));
	CHECK(!fmPolarRotationFast(&nan, &R));
	CHECK(memcmp(&R, &keep, sizeof R) == 0);
}

TEST(symmetric_eigen3)
{
	for (int n = 0; n < 500; ++n)
	{
		fmMat3 A;
		for (int i = 0; i < 3; ++i)
			for (int j = i; j < 3; ++j)
				A.m[3 * i + j] = A.m[3 * j + i] = fmTestRandom(-3, 3);
		if (n % 5 == 0) // a repeated eigenvalue: Q diag(2, 2, -1) Q^T
		{
			fmMat3 Q = fmTestRandomRotation(), D = diag3(2, 2, -1);
			fmMat3 QD = fmMatMul(&Q, &D);
			A = fmMatMulT(&QD, &Q);
		}
		fmVec3 w;
		fmMat3 Q;
		fmSymEigen3(&A, &w, &Q);
		CHECK(w.x >= w.y && w.y >= w.z);
		CHECK_NEAR(orthoError(&Q), 0.0, 1e-13);
		CHECK_NEAR(fmDet(&Q), 1.0, 1e-13);
		fmMat3 D = diag3(w.x, w.y, w.z);
		fmMat3 QD = fmMatMul(&Q, &D);
		fmMat3 back = fmMatMulT(&QD, &Q);
		fmMat3 E = fmMatMulAdd(&back, -1.0, &A);
		CHECK_NEAR(frobenius(&E), 0.0, 1e-13 * frobenius(&A));
		if (n % 5 == 0)
		{
			CHECK_NEAR(w.x, 2.0, 1e-13);
			CHECK_NEAR(w.y, 2.0, 1e-13);
			CHECK_NEAR(w.z, -1.0, 1e-13);
		}
	}
}
