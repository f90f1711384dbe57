// The SIMD layer: the only place that knows vector instructions exist (as Box2D v3 confines its
// SIMD to one file). The element kernels (tet_kernel.c) are written once on fmFloatV, a batch of
// FM_LANES floats, and compiled once per instruction set; simd.c picks the variant the CPU runs.
//
// Every variant does the same IEEE operations on every lane (no fused multiply-add: the build
// sets -ffp-contract=off; no reciprocal or square-root approximations; no reassociation), so the
// scalar, SSE2, AVX2 and AVX-512 variants give the same bits. tests/test_simd.c checks it.
#pragma once

#include <femto/types.h>

#include <stdint.h>
#include <string.h>

// Tets a kernel call takes at once: 16 floats fill one AVX-512 register, two AVX2 or four SSE2
// ones. The batch width is the same on every variant, so a batch's arithmetic is too.
#define FM_LANES 16

// The lanes of one vector of the kernel's translation unit: a batch is FM_LANES / FM_VLANES
// vectors, and the kernel runs them one after another, so that a 3x3 matrix of lanes fits the
// registers (AVX2 has 16 of 8 floats: a matrix of 16-float pairs would not). Each lane's
// arithmetic is its own, so the width changes no bit.
// A kernel's entry point with its variant's suffix: FM_KERNEL_NAME(fmTetKernel_Forces) is
// fmTetKernel_Forces_avx2 in the AVX2 compilation.
#define FM_PASTE2(a, b) a##_##b
#define FM_PASTE(a, b) FM_PASTE2(a, b)
#define FM_KERNEL_NAME(name) FM_PASTE(name, FM_KERNEL_VARIANT)

#if !defined(FM_KERNEL_VARIANT)
// (nothing: only the kernels' translation units have a width)
#elif defined(FM_SIMD_SCALAR) || !(defined(__GNUC__) || defined(__clang__))
#define FM_VLANES 1
#elif defined(__AVX512F__)
#define FM_VLANES 16
#elif defined(__AVX__)
#define FM_VLANES 8
#else
#define FM_VLANES 4
#endif

// The instruction set the running CPU supports best (never fm_simdAuto or fm_simdOff).
fmSimdLevel fmSimd_Detect(void);

// What a world asked for, resolved against the CPU: fm_simdAuto becomes fmSimd_Detect(), a
// level the CPU lacks falls back to the best one it has below it; fm_simdOff stays.
fmSimdLevel fmSimd_Resolve(fmSimdLevel requested);

// ---- the lane wrapper ---------------------------------------------------------------------------
// With GCC or Clang and without FM_SIMD_SCALAR: vector extensions, which the compiler maps to the
// instruction set of the translation unit (-msse2, -mavx2, -mavx512f). Otherwise: plain loops.
// Only the kernels' translation units (FM_KERNEL_VARIANT defined) see it.

#include <stdbool.h>

#if !defined(FM_KERNEL_VARIANT)
// (nothing: the lane types are the kernels' own)
#elif (defined(__GNUC__) || defined(__clang__)) && !defined(FM_SIMD_SCALAR)

typedef float fmFloatV __attribute__((vector_size(4 * FM_VLANES)));
typedef int32_t fmIntV __attribute__((vector_size(4 * FM_VLANES)));

static inline fmFloatV fmV_Set(float s)
{
	return (fmFloatV){0} + s;
}
static inline fmFloatV fmV_Add(fmFloatV a, fmFloatV b)
{
	return a + b;
}
static inline fmFloatV fmV_Sub(fmFloatV a, fmFloatV b)
{
	return a - b;
}
static inline fmFloatV fmV_Mul(fmFloatV a, fmFloatV b)
{
	return a * b;
}
static inline fmFloatV fmV_Div(fmFloatV a, fmFloatV b)
{
	return a / b;
}
// All bits set in the lanes where a < b.
static inline fmIntV fmV_Less(fmFloatV a, fmFloatV b)
{
	return (fmIntV)(a < b);
}
// a where the mask is set, b elsewhere.
static inline fmFloatV fmV_Select(fmIntV mask, fmFloatV a, fmFloatV b)
{
	return (fmFloatV)(((fmIntV)a & mask) | ((fmIntV)b & ~mask));
}
static inline fmIntV fmV_Bits(fmFloatV a)
{
	return (fmIntV)a;
}
static inline fmFloatV fmV_FromBits(fmIntV a)
{
	return (fmFloatV)a;
}
static inline fmIntV fmI_Set(int32_t s)
{
	return (fmIntV){0} + s;
}
static inline fmIntV fmI_Sub(fmIntV a, fmIntV b)
{
	return a - b;
}
static inline fmIntV fmI_Add(fmIntV a, fmIntV b)
{
	return a + b;
}
static inline fmIntV fmI_And(fmIntV a, fmIntV b)
{
	return a & b;
}
static inline fmIntV fmI_Or(fmIntV a, fmIntV b)
{
	return a | b;
}
// Shift right of lanes that are >= 0 (the only ones the kernels shift).
static inline fmIntV fmI_ShiftRight(fmIntV a, int n)
{
	return a >> n;
}
static inline fmFloatV fmI_ToFloat(fmIntV a)
{
	return __builtin_convertvector(a, fmFloatV);
}
// Whether any lane of the mask is set (on x86 one test of the whole vector).
#if defined(__AVX512F__)
#include <immintrin.h>
static inline bool fmI_Any(fmIntV mask)
{
	return _mm512_test_epi32_mask((__m512i)mask, (__m512i)mask) != 0;
}
#elif defined(__AVX__)
#include <immintrin.h>
static inline bool fmI_Any(fmIntV mask)
{
	return !_mm256_testz_si256((__m256i)mask, (__m256i)mask);
}
#elif defined(__SSE2__)
#include <emmintrin.h>
static inline bool fmI_Any(fmIntV mask)
{
	return _mm_movemask_epi8((__m128i)mask) != 0;
}
#else
static inline bool fmI_Any(fmIntV mask)
{
	int32_t any = 0;
	for (int l = 0; l < FM_VLANES; ++l)
		any |= mask[l];
	return any != 0;
}
#endif

#else

typedef struct fmFloatV
{
	float v[FM_VLANES];
} fmFloatV;
typedef struct fmIntV
{
	int32_t v[FM_VLANES];
} fmIntV;

#define FM_LANEWISE(T, expr)                                                                       \
	T r;                                                                                           \
	for (int l = 0; l < FM_VLANES; ++l)                                                            \
		r.v[l] = (expr);                                                                           \
	return r

static inline fmFloatV fmV_Set(float s)
{
	FM_LANEWISE(fmFloatV, s);
}
static inline fmFloatV fmV_Add(fmFloatV a, fmFloatV b)
{
	FM_LANEWISE(fmFloatV, a.v[l] + b.v[l]);
}
static inline fmFloatV fmV_Sub(fmFloatV a, fmFloatV b)
{
	FM_LANEWISE(fmFloatV, a.v[l] - b.v[l]);
}
static inline fmFloatV fmV_Mul(fmFloatV a, fmFloatV b)
{
	FM_LANEWISE(fmFloatV, a.v[l] * b.v[l]);
}
static inline fmFloatV fmV_Div(fmFloatV a, fmFloatV b)
{
	FM_LANEWISE(fmFloatV, a.v[l] / b.v[l]);
}
static inline fmIntV fmV_Less(fmFloatV a, fmFloatV b)
{
	FM_LANEWISE(fmIntV, a.v[l] < b.v[l] ? -1 : 0);
}
static inline fmIntV fmV_Bits(fmFloatV a)
{
	fmIntV r;
	memcpy(&r, &a, sizeof r);
	return r;
}
static inline fmFloatV fmV_FromBits(fmIntV a)
{
	fmFloatV r;
	memcpy(&r, &a, sizeof r);
	return r;
}
static inline fmFloatV fmV_Select(fmIntV mask, fmFloatV a, fmFloatV b)
{
	fmIntV x = fmV_Bits(a), y = fmV_Bits(b), r;
	for (int l = 0; l < FM_VLANES; ++l)
		r.v[l] = (x.v[l] & mask.v[l]) | (y.v[l] & ~mask.v[l]);
	return fmV_FromBits(r);
}
static inline fmIntV fmI_Set(int32_t s)
{
	FM_LANEWISE(fmIntV, s);
}
static inline fmIntV fmI_Sub(fmIntV a, fmIntV b)
{
	FM_LANEWISE(fmIntV, a.v[l] - b.v[l]);
}
static inline fmIntV fmI_Add(fmIntV a, fmIntV b)
{
	FM_LANEWISE(fmIntV, a.v[l] + b.v[l]);
}
static inline fmIntV fmI_And(fmIntV a, fmIntV b)
{
	FM_LANEWISE(fmIntV, a.v[l] & b.v[l]);
}
static inline fmIntV fmI_Or(fmIntV a, fmIntV b)
{
	FM_LANEWISE(fmIntV, a.v[l] | b.v[l]);
}
static inline fmIntV fmI_ShiftRight(fmIntV a, int n)
{
	FM_LANEWISE(fmIntV, a.v[l] >> n);
}
static inline fmFloatV fmI_ToFloat(fmIntV a)
{
	FM_LANEWISE(fmFloatV, (float)a.v[l]);
}
static inline bool fmI_Any(fmIntV mask)
{
	int32_t any = 0;
	for (int l = 0; l < FM_VLANES; ++l)
		any |= mask.v[l];
	return any != 0;
}

#undef FM_LANEWISE

#endif

#if defined(FM_KERNEL_VARIANT)
// Unaligned loads and stores of FM_VLANES floats (memcpy: the compiler emits vector moves).
static inline fmFloatV fmV_Load(const float* p)
{
	fmFloatV v;
	memcpy(&v, p, sizeof v);
	return v;
}
static inline void fmV_Store(float* p, fmFloatV v)
{
	memcpy(p, &v, sizeof v);
}

// ---- the edge gather ----------------------------------------------------------------------------
// fmV_GatherEdges: the edge matrices Du = [u1 - u0, u2 - u0, u3 - u0] of lanes [o, o + FM_VLANES)
// of a batch, du[3 i + k] = (float)(u[r_{k+1} + i] - u[r_0 + i]) with r_a = rows[a][lane] and u
// the displacements of the batch's vertices, 4 doubles each (the fourth unused). The
// difference is taken in double and rounded once to float on every variant, so every variant
// gives the same bits. On x86 each lane's edges are three vector subtractions of its vertices'
// 4-double rows and three conversions, and the lanes' rows are then transposed in registers;
// elsewhere a lane at a time.

#if !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__)) &&                       \
    (defined(__x86_64__) || defined(_M_X64))
#include <immintrin.h>
#endif

#if defined(__AVX__) && !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__))
// Edge k of lanes [o, o + 8) as rows x, y, z of 8 floats.
static inline void fmGatherEdge8(const double* u, const uint16_t (*rows)[FM_LANES], int o, int k,
                                 __m256 row[3])
{
	__m128 e[8];
	for (int l = 0; l < 8; ++l)
	{
		const double* u0 = u + (size_t)rows[0][o + l];
		__m256d d =
		    _mm256_sub_pd(_mm256_loadu_pd(u + (size_t)rows[k + 1][o + l]), _mm256_loadu_pd(u0));
		e[l] = _mm256_cvtpd_ps(d);
	}
	// Lanes l and l + 4 side by side, then a 4x4 transpose in each half.
	__m256 p[4];
	for (int l = 0; l < 4; ++l)
		p[l] = _mm256_insertf128_ps(_mm256_castps128_ps256(e[l]), e[l + 4], 1);
	__m256 t0 = _mm256_unpacklo_ps(p[0], p[1]), t1 = _mm256_unpackhi_ps(p[0], p[1]);
	__m256 t2 = _mm256_unpacklo_ps(p[2], p[3]), t3 = _mm256_unpackhi_ps(p[2], p[3]);
	row[0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
	row[1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
	row[2] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
}
#endif

#if defined(FM_SIMD_SCALAR) || !(defined(__GNUC__) || defined(__clang__)) ||                       \
    !(defined(__x86_64__) || defined(_M_X64))
static inline void fmV_GatherEdges(const double* u, const uint16_t (*rows)[FM_LANES], int o,
                                   fmFloatV du[9])
{
	float lanes[9][FM_VLANES];
	for (int l = 0; l < FM_VLANES; ++l)
	{
		const double* u0 = u + (size_t)rows[0][o + l];
		for (int k = 0; k < 3; ++k)
		{
			const double* uk = u + (size_t)rows[k + 1][o + l];
			for (int i = 0; i < 3; ++i)
				lanes[3 * i + k][l] = (float)(uk[i] - u0[i]);
		}
	}
	for (int k = 0; k < 9; ++k)
		du[k] = fmV_Load(lanes[k]);
}
#elif defined(__AVX512F__)
static inline void fmV_GatherEdges(const double* u, const uint16_t (*rows)[FM_LANES], int o,
                                   fmFloatV du[9])
{
	for (int k = 0; k < 3; ++k)
	{
		__m256 lo[3], hi[3];
		fmGatherEdge8(u, rows, o, k, lo);
		fmGatherEdge8(u, rows, o + 8, k, hi);
		for (int i = 0; i < 3; ++i)
			du[3 * i + k] = (fmFloatV)_mm512_insertf64x4(
			    _mm512_castpd256_pd512(_mm256_castps_pd(lo[i])), _mm256_castps_pd(hi[i]), 1);
	}
}
#elif defined(__AVX__)
static inline void fmV_GatherEdges(const double* u, const uint16_t (*rows)[FM_LANES], int o,
                                   fmFloatV du[9])
{
	for (int k = 0; k < 3; ++k)
	{
		__m256 row[3];
		fmGatherEdge8(u, rows, o, k, row);
		for (int i = 0; i < 3; ++i)
			du[3 * i + k] = (fmFloatV)row[i];
	}
}
#else
// Lane l's edge k as (x, y, z, unused) in float.
static inline __m128 fmEdge4(const double* u, const uint16_t (*rows)[FM_LANES], int k, int l)
{
	__m128d x0 = _mm_loadu_pd(u + (size_t)rows[0][l]),
	        z0 = _mm_loadu_pd(u + (size_t)rows[0][l] + 2);
	__m128d xk = _mm_loadu_pd(u + (size_t)rows[k + 1][l]);
	__m128d zk = _mm_loadu_pd(u + (size_t)rows[k + 1][l] + 2);
	return _mm_movelh_ps(_mm_cvtpd_ps(_mm_sub_pd(xk, x0)), _mm_cvtpd_ps(_mm_sub_pd(zk, z0)));
}

static inline void fmV_GatherEdges(const double* u, const uint16_t (*rows)[FM_LANES], int o,
                                   fmFloatV du[9])
{
	for (int k = 0; k < 3; ++k)
	{
		__m128 e0 = fmEdge4(u, rows, k, o), e1 = fmEdge4(u, rows, k, o + 1);
		__m128 e2 = fmEdge4(u, rows, k, o + 2), e3 = fmEdge4(u, rows, k, o + 3);
		_MM_TRANSPOSE4_PS(e0, e1, e2, e3);
		du[k] = (fmFloatV)e0, du[3 + k] = (fmFloatV)e1, du[6 + k] = (fmFloatV)e2;
	}
}
#endif

// ---- the node forces out, and a vertex's sum of them --------------------------------------------
// fmV_StoreNodes: out[l] = (x[l], y[l], z[l], 0) for the FM_VLANES lanes (one node's forces on
// the lanes of a vector), so that a vertex's sum loads each entry as one vector.
// fmSumEntries: sum[c] = the sum over e < count, in order, of (double)forces[offsets[e] + c],
// c = 0, 1, 2, each component in double in the same order on every variant; fmSumEntriesPair:
// the sums of two vertices whose entries follow each other (countA, then countB), side by side
// where the vectors allow (two dependency chains, each sum in its own order). fmWeightedSum and
// fmWeightedSumPair: the same of weights[e] * v[offsets[e] + c] (v: 3 doubles a vertex).

#if defined(__AVX__) && !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__))
// Lanes 0..7 of rows x, y, z transposed to 8 rows of 4 (a 4x4 transpose in each half).
static inline void fmStoreNodes8(float (*out)[4], __m256 x, __m256 y, __m256 z)
{
	__m256 zero = _mm256_setzero_ps();
	__m256 t0 = _mm256_unpacklo_ps(x, y), t1 = _mm256_unpackhi_ps(x, y);
	__m256 t2 = _mm256_unpacklo_ps(z, zero), t3 = _mm256_unpackhi_ps(z, zero);
	__m256 a[4] = {_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0)),
	               _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2)),
	               _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0)),
	               _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2))};
	for (int l = 0; l < 4; ++l)
	{
		_mm_storeu_ps(out[l], _mm256_castps256_ps128(a[l]));
		_mm_storeu_ps(out[l + 4], _mm256_extractf128_ps(a[l], 1));
	}
}

// sum[0..2] = lanes 0..2 of s.
static inline void fmStoreSum(double sum[3], __m256d s)
{
	_mm_storeu_pd(sum, _mm256_castpd256_pd128(s));
	_mm_store_sd(sum + 2, _mm256_extractf128_pd(s, 1));
}

static inline void fmWeightedSum(const double* v, const int* offsets, const double* weights,
                                 int count, double sum[3])
{
	// (The fourth lane is not loaded: the last vertex's row ends the array.)
	const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
	__m256d s = _mm256_setzero_pd();
	for (int e = 0; e < count; ++e)
		s = _mm256_add_pd(
		    s, _mm256_mul_pd(_mm256_set1_pd(weights[e]), _mm256_maskload_pd(v + offsets[e], xyz)));
	fmStoreSum(sum, s);
}

static inline void fmWeightedSumPair(const double* v, const int* offsets, const double* weights,
                                     int countA, int countB, double sumA[3], double sumB[3])
{
	const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
	const int* offsetsB = offsets + countA;
	const double* weightsB = weights + countA;
	__m256d a = _mm256_setzero_pd(), b = _mm256_setzero_pd();
	int both = countA < countB ? countA : countB, e = 0;
	for (; e + 1 < both; e += 2) // (two entries an iteration: half the loop's own instructions)
		for (int k = e; k < e + 2; ++k)
		{
			a = _mm256_add_pd(a, _mm256_mul_pd(_mm256_set1_pd(weights[k]),
			                                   _mm256_maskload_pd(v + offsets[k], xyz)));
			b = _mm256_add_pd(b, _mm256_mul_pd(_mm256_set1_pd(weightsB[k]),
			                                   _mm256_maskload_pd(v + offsetsB[k], xyz)));
		}
	for (; e < both; ++e)
	{
		a = _mm256_add_pd(
		    a, _mm256_mul_pd(_mm256_set1_pd(weights[e]), _mm256_maskload_pd(v + offsets[e], xyz)));
		b = _mm256_add_pd(b, _mm256_mul_pd(_mm256_set1_pd(weightsB[e]),
		                                   _mm256_maskload_pd(v + offsetsB[e], xyz)));
	}
	for (int k = e; k < countA; ++k)
		a = _mm256_add_pd(
		    a, _mm256_mul_pd(_mm256_set1_pd(weights[k]), _mm256_maskload_pd(v + offsets[k], xyz)));
	for (int k = e; k < countB; ++k)
		b = _mm256_add_pd(b, _mm256_mul_pd(_mm256_set1_pd(weightsB[k]),
		                                   _mm256_maskload_pd(v + offsetsB[k], xyz)));
	fmStoreSum(sumA, a);
	fmStoreSum(sumB, b);
}

static inline void fmSumEntries(const float* forces, const uint16_t* offsets, int count,
                                double sum[3])
{
	__m256d s = _mm256_setzero_pd();
	for (int e = 0; e < count; ++e)
		s = _mm256_add_pd(s, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsets[e])));
	fmStoreSum(sum, s);
}

static inline void fmSumEntriesPair(const float* forces, const uint16_t* offsets, int countA,
                                    int countB, double sumA[3], double sumB[3])
{
	const uint16_t* offsetsB = offsets + countA;
	__m256d a = _mm256_setzero_pd(), b = _mm256_setzero_pd();
	int both = countA < countB ? countA : countB, e = 0;
	for (; e + 1 < both; e += 2) // (two entries an iteration: half the loop's own instructions)
	{
		a = _mm256_add_pd(a, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsets[e])));
		b = _mm256_add_pd(b, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsetsB[e])));
		a = _mm256_add_pd(a, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsets[e + 1])));
		b = _mm256_add_pd(b, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsetsB[e + 1])));
	}
	for (; e < both; ++e)
	{
		a = _mm256_add_pd(a, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsets[e])));
		b = _mm256_add_pd(b, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsetsB[e])));
	}
	for (int k = e; k < countA; ++k)
		a = _mm256_add_pd(a, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsets[k])));
	for (int k = e; k < countB; ++k)
		b = _mm256_add_pd(b, _mm256_cvtps_pd(_mm_loadu_ps(forces + offsetsB[k])));
	fmStoreSum(sumA, a);
	fmStoreSum(sumB, b);
}
#else
static inline void fmWeightedSum(const double* v, const int* offsets, const double* weights,
                                 int count, double sum[3])
{
	double sx = 0.0, sy = 0.0, sz = 0.0;
	for (int e = 0; e < count; ++e)
	{
		const double* vj = v + offsets[e];
		double w = weights[e];
		sx += w * vj[0], sy += w * vj[1], sz += w * vj[2];
	}
	sum[0] = sx, sum[1] = sy, sum[2] = sz;
}

static inline void fmSumEntries(const float* forces, const uint16_t* offsets, int count,
                                double sum[3])
{
	double sx = 0.0, sy = 0.0, sz = 0.0;
	for (int e = 0; e < count; ++e)
	{
		const float* entry = forces + offsets[e];
		sx += (double)entry[0], sy += (double)entry[1], sz += (double)entry[2];
	}
	sum[0] = sx, sum[1] = sy, sum[2] = sz;
}

static inline void fmSumEntriesPair(const float* forces, const uint16_t* offsets, int countA,
                                    int countB, double sumA[3], double sumB[3])
{
	fmSumEntries(forces, offsets, countA, sumA);
	fmSumEntries(forces, offsets + countA, countB, sumB);
}

static inline void fmWeightedSumPair(const double* v, const int* offsets, const double* weights,
                                     int countA, int countB, double sumA[3], double sumB[3])
{
	fmWeightedSum(v, offsets, weights, countA, sumA);
	fmWeightedSum(v, offsets + countA, weights + countA, countB, sumB);
}
#endif

// ---- double rows of 4 tets ---------------------------------------------------------------------
// The force batch's inputs (tet_kernel.h), 4 lanes at a time, rows of @p stride doubles:
// fmV_EdgesOf4Tets: out[(3 i + k) stride + l] = x[3 n_{k+1} + i] - x[3 n_0 + i] for the tets
// l = 0..3 of @p nodes (4 vertex numbers a tet, x 3 doubles a vertex), in double;
// fmV_TransposeOf4: out[e stride + l] = m[9 l + e] for 4 matrices of 9 doubles. Copies and
// double subtractions: the same bits on every variant. On AVX each tet's vertices are one masked
// 4-double load and its edges one subtraction, transposed in registers.

#if defined(__AVX__) && !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__))
// (t0, t2) and (t1, t3): the unpacked rows of a 4x4 transpose; columns c = 0..3 to out rows.
static inline void fmStoreColumns4(__m256d r[4], double* out, size_t stride, int columns)
{
	__m256d t0 = _mm256_unpacklo_pd(r[0], r[1]), t1 = _mm256_unpackhi_pd(r[0], r[1]);
	__m256d t2 = _mm256_unpacklo_pd(r[2], r[3]), t3 = _mm256_unpackhi_pd(r[2], r[3]);
	_mm256_storeu_pd(out, _mm256_permute2f128_pd(t0, t2, 0x20));
	_mm256_storeu_pd(out + stride, _mm256_permute2f128_pd(t1, t3, 0x20));
	_mm256_storeu_pd(out + 2 * stride, _mm256_permute2f128_pd(t0, t2, 0x31));
	if (columns > 3)
		_mm256_storeu_pd(out + 3 * stride, _mm256_permute2f128_pd(t1, t3, 0x31));
}

static inline void fmV_EdgesOf4Tets(const double* x, const int* nodes, double* out, int stride)
{
	const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
	__m256d origin[4], edge[4];
	for (int l = 0; l < 4; ++l)
		origin[l] = _mm256_maskload_pd(x + 3 * (size_t)nodes[4 * l], xyz);
	for (int k = 0; k < 3; ++k)
	{
		for (int l = 0; l < 4; ++l)
			edge[l] = _mm256_sub_pd(_mm256_maskload_pd(x + 3 * (size_t)nodes[4 * l + k + 1], xyz),
			                        origin[l]);
		fmStoreColumns4(edge, out + k * (size_t)stride, 3 * (size_t)stride, 3);
	}
}

static inline void fmV_TransposeOf4(const double* m, double* out, int stride)
{
	for (int h = 0; h < 2; ++h)
	{
		__m256d r[4];
		for (int l = 0; l < 4; ++l)
			r[l] = _mm256_loadu_pd(m + 9 * l + 4 * h);
		fmStoreColumns4(r, out + 4 * h * (size_t)stride, (size_t)stride, 4);
	}
	for (int l = 0; l < 4; ++l)
		out[8 * (size_t)stride + l] = m[9 * l + 8];
}
#else
static inline void fmV_EdgesOf4Tets(const double* x, const int* nodes, double* out, int stride)
{
	for (int l = 0; l < 4; ++l)
		for (int i = 0; i < 3; ++i)
			for (int k = 0; k < 3; ++k)
				out[(3 * i + k) * (size_t)stride + l] =
				    x[3 * (size_t)nodes[4 * l + k + 1] + i] - x[3 * (size_t)nodes[4 * l] + i];
}

static inline void fmV_TransposeOf4(const double* m, double* out, int stride)
{
	for (int l = 0; l < 4; ++l)
		for (int e = 0; e < 9; ++e)
			out[e * (size_t)stride + l] = m[9 * l + e];
}
#endif

// ---- block rows
// ---------------------------------------------------------------------------------- fmBlockSums:
// the running sums of one row of a 3x3-block sparse matrix (bsr.h, blocks row-major), one lane per
// block entry: fmV_BlockAdd adds the products a[j] x[j % 3] of a block a and its column's x to
// lanes j = 0..8, fmV_BlockMerge adds one row's sums to another's lane by lane, and fmV_BlockResult
// gives the row's three sums t_r = (s_3r + s_3r+1) + s_3r+2. Each lane is a chain of double
// additions in block order on every variant: the same bits. AVX holds the lanes as (0..3) and
// (4..7) times (x0, x1, x2, x0) and (x1, x2, x0, x1); other vector units in pairs; the scalar
// variant in nine doubles.

#if defined(__AVX__) && !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__))
typedef struct fmBlockSums
{
	__m256d low, high; // lanes 0..3, 4..7
	double last;       // lane 8
} fmBlockSums;

static inline fmBlockSums fmV_BlockZero(void)
{
	return (fmBlockSums){_mm256_setzero_pd(), _mm256_setzero_pd(), 0.0};
}
static inline void fmV_BlockAdd(fmBlockSums* s, const double* a, const double* x)
{
	__m128d x01 = _mm_loadu_pd(x), x12 = _mm_loadu_pd(x + 1), x2 = _mm_load_sd(x + 2);
	__m256d low = _mm256_insertf128_pd(_mm256_castpd128_pd256(x01), _mm_loadh_pd(x2, x), 1);
	__m256d high = _mm256_insertf128_pd(_mm256_castpd128_pd256(x12), x01, 1);
	s->low = _mm256_add_pd(s->low, _mm256_mul_pd(_mm256_loadu_pd(a), low));
	s->high = _mm256_add_pd(s->high, _mm256_mul_pd(_mm256_loadu_pd(a + 4), high));
	s->last += a[8] * x[2];
}
static inline void fmV_BlockMerge(fmBlockSums* s, const fmBlockSums* t)
{
	s->low = _mm256_add_pd(s->low, t->low);
	s->high = _mm256_add_pd(s->high, t->high);
	s->last += t->last;
}
static inline void fmV_BlockResult(const fmBlockSums* s, double t[3])
{
	double lane[8];
	_mm256_storeu_pd(lane, s->low);
	_mm256_storeu_pd(lane + 4, s->high);
	t[0] = (lane[0] + lane[1]) + lane[2];
	t[1] = (lane[3] + lane[4]) + lane[5];
	t[2] = (lane[6] + lane[7]) + s->last;
}
#elif (defined(__GNUC__) || defined(__clang__)) && !defined(FM_SIMD_SCALAR)
typedef double fmDoublePair __attribute__((vector_size(16)));

typedef struct fmBlockSums
{
	fmDoublePair pair[4]; // lanes (0, 1), (2, 3), (4, 5), (6, 7)
	double last;          // lane 8
} fmBlockSums;

static inline fmDoublePair fmLoadPair(const double* p)
{
	fmDoublePair v;
	memcpy(&v, p, sizeof v);
	return v;
}
static inline fmBlockSums fmV_BlockZero(void)
{
	return (fmBlockSums){{{0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}, {0.0, 0.0}}, 0.0};
}
static inline void fmV_BlockAdd(fmBlockSums* s, const double* a, const double* x)
{
	fmDoublePair x01 = fmLoadPair(x), x12 = fmLoadPair(x + 1), x20 = {x[2], x[0]};
	s->pair[0] += fmLoadPair(a) * x01;
	s->pair[1] += fmLoadPair(a + 2) * x20;
	s->pair[2] += fmLoadPair(a + 4) * x12;
	s->pair[3] += fmLoadPair(a + 6) * x01;
	s->last += a[8] * x[2];
}
static inline void fmV_BlockMerge(fmBlockSums* s, const fmBlockSums* t)
{
	for (int p = 0; p < 4; ++p)
		s->pair[p] += t->pair[p];
	s->last += t->last;
}
static inline void fmV_BlockResult(const fmBlockSums* s, double t[3])
{
	t[0] = (s->pair[0][0] + s->pair[0][1]) + s->pair[1][0];
	t[1] = (s->pair[1][1] + s->pair[2][0]) + s->pair[2][1];
	t[2] = (s->pair[3][0] + s->pair[3][1]) + s->last;
}
#else
typedef struct fmBlockSums
{
	double lane[9];
} fmBlockSums;

static inline fmBlockSums fmV_BlockZero(void)
{
	return (fmBlockSums){{0.0}};
}
static inline void fmV_BlockAdd(fmBlockSums* s, const double* a, const double* x)
{
	for (int j = 0; j < 9; ++j)
		s->lane[j] += a[j] * x[j % 3];
}
static inline void fmV_BlockMerge(fmBlockSums* s, const fmBlockSums* t)
{
	for (int j = 0; j < 9; ++j)
		s->lane[j] += t->lane[j];
}
static inline void fmV_BlockResult(const fmBlockSums* s, double t[3])
{
	for (int r = 0; r < 3; ++r)
		t[r] = (s->lane[3 * r] + s->lane[3 * r + 1]) + s->lane[3 * r + 2];
}
#endif

#if defined(FM_SIMD_SCALAR) || !(defined(__GNUC__) || defined(__clang__)) ||                       \
    !(defined(__x86_64__) || defined(_M_X64))
static inline void fmV_StoreNodes(float (*out)[4], fmFloatV x, fmFloatV y, fmFloatV z)
{
	float rows[3][FM_VLANES];
	fmV_Store(rows[0], x), fmV_Store(rows[1], y), fmV_Store(rows[2], z);
	for (int l = 0; l < FM_VLANES; ++l)
		out[l][0] = rows[0][l], out[l][1] = rows[1][l], out[l][2] = rows[2][l], out[l][3] = 0.0f;
}
#elif defined(__AVX512F__)
// (The halves by literal immediates: the instructions take no variable.)
static inline void fmV_StoreNodes(float (*out)[4], fmFloatV x, fmFloatV y, fmFloatV z)
{
	__m512d dx = _mm512_castps_pd((__m512)x), dy = _mm512_castps_pd((__m512)y),
	        dz = _mm512_castps_pd((__m512)z);
	fmStoreNodes8(out, _mm256_castpd_ps(_mm512_castpd512_pd256(dx)),
	              _mm256_castpd_ps(_mm512_castpd512_pd256(dy)),
	              _mm256_castpd_ps(_mm512_castpd512_pd256(dz)));
	fmStoreNodes8(out + 8, _mm256_castpd_ps(_mm512_extractf64x4_pd(dx, 1)),
	              _mm256_castpd_ps(_mm512_extractf64x4_pd(dy, 1)),
	              _mm256_castpd_ps(_mm512_extractf64x4_pd(dz, 1)));
}
#elif defined(__AVX__)
static inline void fmV_StoreNodes(float (*out)[4], fmFloatV x, fmFloatV y, fmFloatV z)
{
	fmStoreNodes8(out, (__m256)x, (__m256)y, (__m256)z);
}
#else
static inline void fmV_StoreNodes(float (*out)[4], fmFloatV x, fmFloatV y, fmFloatV z)
{
	__m128 a = (__m128)x, b = (__m128)y, c = (__m128)z, d = _mm_setzero_ps();
	_MM_TRANSPOSE4_PS(a, b, c, d);
	_mm_storeu_ps(out[0], a), _mm_storeu_ps(out[1], b);
	_mm_storeu_ps(out[2], c), _mm_storeu_ps(out[3], d);
}
#endif
#endif
