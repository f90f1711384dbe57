// Robust 3x3 singular value decomposition for elasticity (Irving, Teran, Fedkiw 2004):
// F = U diag(s) V^T with U, V proper rotations (det = +1). When det F < 0 the smallest
// singular value carries the sign, so an inverted tet has s[2] < 0.
#pragma once

#include <femto/fm_math.h>

#include <stdbool.h>

// s sorted by decreasing magnitude, s[0] >= s[1] >= |s[2]|; s[2] < 0 iff det F < 0.
void fmSvd3(const fmMat3* F, fmMat3* U, fmVec3* s, fmMat3* V);

// Symmetric eigen-decomposition of a 3x3 matrix A = Q diag(w) Q^T (cyclic Jacobi).
void fmSymEigen3(const fmMat3* A, fmVec3* w, fmMat3* Q);

// Symmetric eigen-decomposition of an n x n row-major matrix by cyclic Jacobi: A is overwritten
// (it ends near diagonal), w gets the n eigenvalues (unsorted), Q (n x n, row-major) the
// eigenvectors as columns, A_in = Q diag(w) Q^T. Sweeps stop when the off-diagonal norm is below
// tolerance times the diagonal norm (1e-16: full precision).
void fmSymEigenN(double* A, int n, double tolerance, double* w, double* Q);

// fmPolarRotationFast: the smallest det F / |F|_F^3 it takes (a condition number of about
// 500), its most iterations, and the last change (Frobenius) after which X is orthogonal to
// round-off: a plain step of change c leaves an error of about c^2 / 2, here 5e-17. The batched
// kernel (tet_kernel.h) uses the same.
#define FM_POLAR_MIN_SHAPE 1e-3
#define FM_POLAR_MAX_ITERATIONS 12
#define FM_POLAR_DONE 1e-8
// How far |F|^2 from 3 and det F from 1 may be for the iteration to start unscaled (near a
// rotation the plain iteration converges quadratically from its first step, and the scaling's
// three square roots would be wasted: a 10k-tet corotated frame 15% faster).
#define FM_POLAR_NEAR_ROTATION 0.05

// The rotation of F = R S when det F > 0 and F is not nearly flat (then R = U V^T of fmSvd3, to
// round-off), by a few Newton steps: about 3x cheaper than fmSvd3 for the usual tet. Returns
// false, R untouched, for any other F (inverted, flat, non-finite, or not converged).
bool fmPolarRotationFast(const fmMat3* F, fmMat3* R);

// Polar decomposition F = R S with R a rotation (from the SVD; R = U V^T).
fmMat3 fmPolarRotation(const fmMat3* F);
