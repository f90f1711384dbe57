/// @file fm_math.h
/// Small inline value math: 3-vectors and 3x3 matrices in double precision.
/// Matrices are row-major: m[3 * row + col]. Named fm_math.h so it never shadows <math.h>.
#pragma once

#include <math.h>

/// A 3-vector (metres, metres per second, newtons, ...).
typedef struct fmVec3
{
	double x, y, z;
} fmVec3;

/// A 3x3 matrix, row-major: m[3 * row + col].
typedef struct fmMat3
{
	double m[9];
} fmMat3;

/// Make a vector.
static inline fmVec3 fmMakeVec3(double x, double y, double z)
{
	fmVec3 v = {x, y, z};
	return v;
}
/// a + b
static inline fmVec3 fmAdd(fmVec3 a, fmVec3 b) { return fmMakeVec3(a.x + b.x, a.y + b.y, a.z + b.z); }
/// a - b
static inline fmVec3 fmSub(fmVec3 a, fmVec3 b) { return fmMakeVec3(a.x - b.x, a.y - b.y, a.z - b.z); }
/// s * a
static inline fmVec3 fmScale(double s, fmVec3 a) { return fmMakeVec3(s * a.x, s * a.y, s * a.z); }
/// a + s * b
static inline fmVec3 fmMulAdd(fmVec3 a, double s, fmVec3 b)
{
	return fmMakeVec3(a.x + s * b.x, a.y + s * b.y, a.z + s * b.z);
}
/// Dot product.
static inline double fmDot(fmVec3 a, fmVec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
/// Cross product.
static inline fmVec3 fmCross(fmVec3 a, fmVec3 b)
{
	return fmMakeVec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
/// Euclidean length.
static inline double fmLength(fmVec3 a) { return sqrt(fmDot(a, a)); }

/// Load vertex @p i from a packed xyz array.
static inline fmVec3 fmLoad(const double* xyz, int i)
{
	return fmMakeVec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]);
}
/// Store vertex @p i into a packed xyz array.
static inline void fmStore(double* xyz, int i, fmVec3 v)
{
	xyz[3 * i] = v.x;
	xyz[3 * i + 1] = v.y;
	xyz[3 * i + 2] = v.z;
}

/// Identity matrix.
static inline fmMat3 fmIdentity3(void)
{
	fmMat3 r = {{1, 0, 0, 0, 1, 0, 0, 0, 1}};
	return r;
}
/// Zero matrix.
static inline fmMat3 fmZero3(void)
{
	fmMat3 r = {{0, 0, 0, 0, 0, 0, 0, 0, 0}};
	return r;
}
/// Matrix with columns a, b, c.
static inline fmMat3 fmMat3FromColumns(fmVec3 a, fmVec3 b, fmVec3 c)
{
	fmMat3 r = {{a.x, b.x, c.x, a.y, b.y, c.y, a.z, b.z, c.z}};
	return r;
}
/// Column j.
static inline fmVec3 fmColumn(const fmMat3* a, int j)
{
	return fmMakeVec3(a->m[j], a->m[3 + j], a->m[6 + j]);
}
// (The 3x3 products below are written out: GCC at -O2 keeps such loops, three times the
// instructions.)
/// A * B
static inline fmMat3 fmMatMul(const fmMat3* a, const fmMat3* b)
{
	const double* x = a->m;
	const double* y = b->m;
	fmMat3 r = {{x[0] * y[0] + x[1] * y[3] + x[2] * y[6], x[0] * y[1] + x[1] * y[4] + x[2] * y[7],
	             x[0] * y[2] + x[1] * y[5] + x[2] * y[8], x[3] * y[0] + x[4] * y[3] + x[5] * y[6],
	             x[3] * y[1] + x[4] * y[4] + x[5] * y[7], x[3] * y[2] + x[4] * y[5] + x[5] * y[8],
	             x[6] * y[0] + x[7] * y[3] + x[8] * y[6], x[6] * y[1] + x[7] * y[4] + x[8] * y[7],
	             x[6] * y[2] + x[7] * y[5] + x[8] * y[8]}};
	return r;
}
/// A^T * B
static inline fmMat3 fmMatTMul(const fmMat3* a, const fmMat3* b)
{
	const double* x = a->m;
	const double* y = b->m;
	fmMat3 r = {{x[0] * y[0] + x[3] * y[3] + x[6] * y[6], x[0] * y[1] + x[3] * y[4] + x[6] * y[7],
	             x[0] * y[2] + x[3] * y[5] + x[6] * y[8], x[1] * y[0] + x[4] * y[3] + x[7] * y[6],
	             x[1] * y[1] + x[4] * y[4] + x[7] * y[7], x[1] * y[2] + x[4] * y[5] + x[7] * y[8],
	             x[2] * y[0] + x[5] * y[3] + x[8] * y[6], x[2] * y[1] + x[5] * y[4] + x[8] * y[7],
	             x[2] * y[2] + x[5] * y[5] + x[8] * y[8]}};
	return r;
}
/// A * B^T
static inline fmMat3 fmMatMulT(const fmMat3* a, const fmMat3* b)
{
	const double* x = a->m;
	const double* y = b->m;
	fmMat3 r = {{x[0] * y[0] + x[1] * y[1] + x[2] * y[2], x[0] * y[3] + x[1] * y[4] + x[2] * y[5],
	             x[0] * y[6] + x[1] * y[7] + x[2] * y[8], x[3] * y[0] + x[4] * y[1] + x[5] * y[2],
	             x[3] * y[3] + x[4] * y[4] + x[5] * y[5], x[3] * y[6] + x[4] * y[7] + x[5] * y[8],
	             x[6] * y[0] + x[7] * y[1] + x[8] * y[2], x[6] * y[3] + x[7] * y[4] + x[8] * y[5],
	             x[6] * y[6] + x[7] * y[7] + x[8] * y[8]}};
	return r;
}
/// A * v
static inline fmVec3 fmMatVec(const fmMat3* a, fmVec3 v)
{
	return fmMakeVec3(a->m[0] * v.x + a->m[1] * v.y + a->m[2] * v.z,
					  a->m[3] * v.x + a->m[4] * v.y + a->m[5] * v.z,
					  a->m[6] * v.x + a->m[7] * v.y + a->m[8] * v.z);
}
/// A^T
static inline fmMat3 fmTranspose(const fmMat3* a)
{
	fmMat3 r = {{a->m[0], a->m[3], a->m[6], a->m[1], a->m[4], a->m[7], a->m[2], a->m[5], a->m[8]}};
	return r;
}
/// A + s * B
static inline fmMat3 fmMatMulAdd(const fmMat3* a, double s, const fmMat3* b)
{
	const double* x = a->m;
	const double* y = b->m;
	fmMat3 r = {{x[0] + s * y[0], x[1] + s * y[1], x[2] + s * y[2], x[3] + s * y[3],
	             x[4] + s * y[4], x[5] + s * y[5], x[6] + s * y[6], x[7] + s * y[7],
	             x[8] + s * y[8]}};
	return r;
}
/// s * A
static inline fmMat3 fmMatScale(double s, const fmMat3* a)
{
	const double* x = a->m;
	fmMat3 r = {
	    {s * x[0], s * x[1], s * x[2], s * x[3], s * x[4], s * x[5], s * x[6], s * x[7], s * x[8]}};
	return r;
}
/// Trace.
static inline double fmTrace(const fmMat3* a) { return a->m[0] + a->m[4] + a->m[8]; }
/// Frobenius inner product A : B.
static inline double fmDDot(const fmMat3* a, const fmMat3* b)
{
	const double* x = a->m;
	const double* y = b->m;
	return 0.0 + x[0] * y[0] + x[1] * y[1] + x[2] * y[2] + x[3] * y[3] + x[4] * y[4] + x[5] * y[5] +
	       x[6] * y[6] + x[7] * y[7] + x[8] * y[8];
}
/// Determinant.
static inline double fmDet(const fmMat3* a)
{
	const double* m = a->m;
	return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) +
		   m[2] * (m[3] * m[7] - m[4] * m[6]);
}
/// Cofactor matrix: d det(A) / dA. Equals det(A) A^-T when A is invertible.
static inline fmMat3 fmCofactor(const fmMat3* a)
{
	const double* m = a->m;
	fmMat3 r = {{m[4] * m[8] - m[5] * m[7], m[5] * m[6] - m[3] * m[8], m[3] * m[7] - m[4] * m[6],
				 m[2] * m[7] - m[1] * m[8], m[0] * m[8] - m[2] * m[6], m[1] * m[6] - m[0] * m[7],
				 m[1] * m[5] - m[2] * m[4], m[2] * m[3] - m[0] * m[5], m[0] * m[4] - m[1] * m[3]}};
	return r;
}
/// Inverse; returns 0 and leaves @p out untouched when |det| <= tiny * scale^3 (never divides by 0).
static inline int fmInverse(const fmMat3* a, fmMat3* out)
{
	double det = fmDet(a);
	double scale = 0.0;
	for (int k = 0; k < 9; ++k)
		scale = fmax(scale, fabs(a->m[k]));
	if (!(fabs(det) > 1e-14 * scale * scale * scale))
		return 0;
	fmMat3 c = fmCofactor(a);
	fmMat3 ct = fmTranspose(&c);
	*out = fmMatScale(1.0 / det, &ct);
	return 1;
}
