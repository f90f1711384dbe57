// Robust 3x3 SVD and symmetric eigen-decompositions by Jacobi rotations.
//
// fmSvd3 uses one-sided (Hestenes) Jacobi: plane rotations applied on the right orthogonalise
// the columns of F, B = F V. The column norms are the singular values and the normalised
// columns the left vectors. Unlike an eigen-decomposition of F^T F it never squares the
// condition number, so tiny singular values keep their relative accuracy. Then the
// conventions of Irving, Teran, Fedkiw 2004 ("Invertible finite elements") are applied:
// U, V proper rotations, the sign of det F on the smallest singular value.
#include "math/svd3.h"
#include "core/det_math.h"

#include <float.h>

// Rotation (c, s) zeroing the off-diagonal of the symmetric 2x2 [[a, g], [g, b]] when applied
// as J = [[c, s], [-s, c]] on both sides (Golub, Van Loan, "symmetric Schur"). The smaller
// of the two possible angles, so the iteration converges.
static void fmJacobiRotation(double a, double b, double g, double* c, double* s)
{
	double zeta = (b - a) / (2.0 * g);
	double t;
	if (fabs(zeta) > 1e150)
		t = 0.5 / zeta; // sqrt(1 + zeta^2) would overflow; t ~ 1 / (2 zeta)
	else
		t = (zeta >= 0.0 ? 1.0 : -1.0) / (fabs(zeta) + sqrt(1.0 + zeta * zeta));
	*c = 1.0 / sqrt(1.0 + t * t);
	*s = t * *c;
}

// The same rotation for the one-sided SVD, where a, b <= 3 after scaling: written without the
// quotient zeta, one division fewer on the critical path. Needs g^2 > 0 (the caller skips
// pairs whose g^2 underflows), so h >= 2 |g| > 0.
static void fmColumnRotation(double a, double b, double g, double* c, double* s)
{
	double d = b - a;
	double h = sqrt(d * d + 4.0 * g * g);
	double t = (d >= 0.0 ? 2.0 * g : -2.0 * g) / (fabs(d) + h);
	*c = 1.0 / sqrt(1.0 + t * t);
	*s = t * *c;
}

void fmSymEigenN(double* A, int n, double tolerance, double* w, double* Q)
{
	for (int i = 0; i < n * n; ++i)
		Q[i] = 0.0;
	for (int i = 0; i < n; ++i)
		Q[i * n + i] = 1.0;

	for (int sweep = 0; sweep < 50; ++sweep)
	{
		double off = 0.0, diag = 0.0;
		for (int i = 0; i < n; ++i)
		{
			diag += A[i * n + i] * A[i * n + i];
			for (int j = i + 1; j < n; ++j)
				off += A[i * n + j] * A[i * n + j];
		}
		if (off <= tolerance * tolerance * diag || off == 0.0)
			break;
		for (int p = 0; p < n - 1; ++p)
			for (int q = p + 1; q < n; ++q)
			{
				double g = A[p * n + q];
				// Skip entries already negligible against both diagonal entries (relative).
				if (fabs(g) <= 1e-18 * sqrt(fabs(A[p * n + p]) * fabs(A[q * n + q])) || g == 0.0)
					continue;
				double c, s;
				fmJacobiRotation(A[p * n + p], A[q * n + q], g, &c, &s);
				// A <- J^T A J with J the rotation in the (p, q) plane.
				for (int k = 0; k < n; ++k)
				{
					double akp = A[k * n + p], akq = A[k * n + q];
					A[k * n + p] = c * akp - s * akq;
					A[k * n + q] = s * akp + c * akq;
				}
				for (int k = 0; k < n; ++k)
				{
					double apk = A[p * n + k], aqk = A[q * n + k];
					A[p * n + k] = c * apk - s * aqk;
					A[q * n + k] = s * apk + c * aqk;
				}
				A[p * n + q] = 0.0;
				A[q * n + p] = 0.0;
				for (int k = 0; k < n; ++k)
				{
					double qkp = Q[k * n + p], qkq = Q[k * n + q];
					Q[k * n + p] = c * qkp - s * qkq;
					Q[k * n + q] = s * qkp + c * qkq;
				}
			}
	}
	for (int i = 0; i < n; ++i)
		w[i] = A[i * n + i];
}

void fmSymEigen3(const fmMat3* A, fmVec3* w, fmMat3* Q)
{
	double a[9], q[9], e[3];
	for (int k = 0; k < 9; ++k)
		a[k] = 0.5 * (A->m[k] + A->m[3 * (k % 3) + k / 3]); // symmetric part
	fmSymEigenN(a, 3, 1e-16, e, q);
	// Sort eigenvalues in decreasing order, columns of Q with them.
	int order[3] = {0, 1, 2};
	for (int i = 0; i < 2; ++i)
		for (int j = i + 1; j < 3; ++j)
			if (e[order[j]] > e[order[i]])
			{
				int t = order[i];
				order[i] = order[j];
				order[j] = t;
			}
	for (int i = 0; i < 3; ++i)
		for (int c = 0; c < 3; ++c)
			Q->m[3 * i + c] = q[3 * i + order[c]];
	*w = fmMakeVec3(e[order[0]], e[order[1]], e[order[2]]);
	if (fmDet(Q) < 0.0) // a proper rotation: flip the last eigenvector
		for (int i = 0; i < 3; ++i)
			Q->m[3 * i + 2] = -Q->m[3 * i + 2];
}

// A unit vector perpendicular to the unit vector a (stable: crosses with the axis a is least
// aligned with).
static fmVec3 fmAnyPerpendicular(fmVec3 a)
{
	fmVec3 axis;
	double ax = fabs(a.x), ay = fabs(a.y), az = fabs(a.z);
	if (ax <= ay && ax <= az)
		axis = fmMakeVec3(1, 0, 0);
	else if (ay <= az)
		axis = fmMakeVec3(0, 1, 0);
	else
		axis = fmMakeVec3(0, 0, 1);
	fmVec3 p = fmCross(a, axis);
	return fmScale(1.0 / fmLength(p), p);
}

static void fmSwapColumns(fmVec3* b, fmVec3* v, int i, int j)
{
	fmVec3 t = b[i];
	b[i] = b[j];
	b[j] = t;
	t = v[i];
	v[i] = v[j];
	v[j] = t;
}

// One-sided Jacobi sweeps on the columns @p b, accumulating the rotations in @p v: rotate column
// pairs until they are orthogonal to working precision relative to their own lengths. Norms are
// recomputed, not updated, so a column that is only rounding noise (rank-deficient F) is still
// judged against its own length.
static void fmJacobiSweeps(fmVec3 b[3], fmVec3 v[3])
{
	static const int pairs[3][2] = {{0, 1}, {0, 2}, {1, 2}};
	const double tol2 = (4.0 * DBL_EPSILON) * (4.0 * DBL_EPSILON);
	for (int sweep = 0; sweep < 20; ++sweep)
	{
		// Largest cos^2 between two columns and largest tan of a rotation in this sweep.
		double worstCos2 = 0.0, worstTan = 0.0;
		for (int k = 0; k < 3; ++k)
		{
			int p = pairs[k][0], q = pairs[k][1];
			double alpha = fmDot(b[p], b[p]), beta = fmDot(b[q], b[q]), gamma = fmDot(b[p], b[q]);
			double ab = alpha * beta;
			if (gamma * gamma <= tol2 * ab)
				continue;
			worstCos2 = fmMax(worstCos2, gamma * gamma / ab);
			double c, sn;
			fmColumnRotation(alpha, beta, gamma, &c, &sn);
			worstTan = fmMax(worstTan, fabs(sn / c));
			fmVec3 bp = b[p], vp = v[p];
			b[p] = fmSub(fmScale(c, bp), fmScale(sn, b[q]));
			b[q] = fmAdd(fmScale(sn, bp), fmScale(c, b[q]));
			v[p] = fmSub(fmScale(c, vp), fmScale(sn, v[q]));
			v[q] = fmAdd(fmScale(sn, vp), fmScale(c, v[q]));
		}
		// Small angles between nearly orthogonal columns: each rotation disturbs the other
		// pairs only to second order, so they are now orthogonal to rounding and the checking
		// sweep can be skipped. (Clustered columns rotate by large angles and keep iterating.)
		if (worstCos2 < 1e-20 && worstTan < 1e-8)
			break;
	}
}

// Sort the columns by decreasing norm (@p n gets the norms), keeping det V = +1: a swap of two
// columns flips it, fixed by negating the last column of V and of B.
static void fmSortColumns(fmVec3 b[3], fmVec3 v[3], double n[3])
{
	for (int k = 0; k < 3; ++k)
		n[k] = fmLength(b[k]);
	for (int i = 0; i < 2; ++i)
		for (int j = i + 1; j < 3; ++j)
			if (n[j] > n[i])
			{
				double t = n[i];
				n[i] = n[j];
				n[j] = t;
				fmSwapColumns(b, v, i, j);
			}
	if (fmDot(fmCross(v[0], v[1]), v[2]) < 0.0)
	{
		v[2] = fmScale(-1.0, v[2]);
		b[2] = fmScale(-1.0, b[2]);
	}
}

void fmSvd3(const fmMat3* F, fmMat3* U, fmVec3* s, fmMat3* V)
{
	// Scale to max |F_ij| = 1 so squared norms can neither overflow nor underflow.
	double scale = 0.0;
	int finite = 1;
	for (int k = 0; k < 9; ++k)
	{
		scale = fmMax(scale, fabs(F->m[k]));
		finite = finite && isfinite(F->m[k]);
	}
	if (!finite || scale == 0.0)
	{
		// F = 0: any rotations will do. Non-finite F: NaN singular values tell the caller.
		*U = fmIdentity3();
		*V = fmIdentity3();
		double value = finite ? 0.0 : NAN;
		*s = fmMakeVec3(value, value, value);
		return;
	}
	fmVec3 b[3], v[3];
	for (int j = 0; j < 3; ++j)
	{
		// Divide rather than multiply by 1 / scale, which overflows for subnormal scales.
		fmVec3 col = fmColumn(F, j);
		b[j] = fmMakeVec3(col.x / scale, col.y / scale, col.z / scale);
		v[j] = fmMakeVec3(j == 0, j == 1, j == 2);
	}

	fmJacobiSweeps(b, v);

	double n[3];
	fmSortColumns(b, v, n);

	// Left vectors: normalised columns; a zero column gets any direction completing the frame.
	// u2 = u0 x u1 makes U proper, and then s2 = u2 . b2 carries the sign of det F.
	const double tiny = 1e-150; // relative to max |F_ij| = 1; below it a column is zero
	fmVec3 u0 = n[0] > tiny ? fmScale(1.0 / n[0], b[0]) : fmMakeVec3(1, 0, 0);
	fmVec3 u1;
	if (n[1] > tiny)
	{
		// Columns are orthogonal to working precision; one more projection makes u1 exactly
		// orthogonal to u0 at the rounding level.
		u1 = fmScale(1.0 / n[1], b[1]);
		u1 = fmMulAdd(u1, -fmDot(u0, u1), u0);
		u1 = fmScale(1.0 / fmLength(u1), u1);
	}
	else
		u1 = fmAnyPerpendicular(u0);
	fmVec3 u2 = fmCross(u0, u1);
	double s2 = fmDot(u2, b[2]);
	// |s2| <= n[2] <= n[1] holds exactly in real arithmetic; keep the promised order when
	// rounding breaks a tie (F = diag(a, a, -a)).
	s2 = copysign(fmMin(fabs(s2), n[1]), s2);

	*U = fmMat3FromColumns(u0, u1, u2);
	*V = fmMat3FromColumns(v[0], v[1], v[2]);
	*s = fmMakeVec3(scale * n[0], scale * n[1], scale * s2);
}

// Polar factor by the scaled Newton iteration X <- (z X + X^-T / z) / 2 (Higham 1986, with the
// Frobenius-norm scaling z = sqrt(|X^-1| / |X|), dropped once X is near orthogonal so the last
// steps converge quadratically). X^-T = cof(X) / det(X). Refuses F that is inverted, nearly flat
// or non-finite (the SVD handles those by its sign convention).
bool fmPolarRotationFast(const fmMat3* F, fmMat3* R)
{
	double norm2 = fmDDot(F, F);
	double det = fmDet(F);
	// det / |F|^3 is 3^-1.5 = 0.19 for a rotation and falls with the condition number.
	if (!(det > FM_POLAR_MIN_SHAPE * norm2 * sqrt(norm2)) || !isfinite(norm2))
		return false;
	fmMat3 X = *F;
	// Near a rotation (|F|^2 = 3 + 2 tr E + |E|^2 and det F = 1 + tr E + ... for F = R (I + E))
	// the plain iteration converges quadratically from the first step, and the scaling's three
	// square roots would be wasted.
	bool scaled =
	    fabs(norm2 - 3.0) > FM_POLAR_NEAR_ROTATION || fabs(det - 1.0) > FM_POLAR_NEAR_ROTATION;
	for (int iteration = 0; iteration < FM_POLAR_MAX_ITERATIONS; ++iteration)
	{
		fmMat3 C = fmCofactor(&X);
		double d = X.m[0] * C.m[0] + X.m[1] * C.m[1] + X.m[2] * C.m[2]; // det by the first row
		double z = 1.0;
		if (scaled)
			z = sqrt(sqrt(fmDDot(&C, &C) / (d * d)) / sqrt(fmDDot(&X, &X)));
		double a = 0.5 * z, b = 0.5 / (z * d);
		double change = 0.0;
		for (int k = 0; k < 9; ++k)
		{
			double next = a * X.m[k] + b * C.m[k];
			change += (next - X.m[k]) * (next - X.m[k]);
			X.m[k] = next;
		}
		// Quadratic convergence: a change of e leaves an error of about e^2 / 2.
		if (change <= FM_POLAR_DONE * FM_POLAR_DONE)
		{
			*R = X;
			return true;
		}
		scaled = change > 1e-4;
	}
	return false;
}

fmMat3 fmPolarRotation(const fmMat3* F)
{
	fmMat3 U, V;
	fmVec3 s;
	fmSvd3(F, &U, &s, &V);
	return fmMatMulT(&U, &V);
}
