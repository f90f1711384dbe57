// The explicit step's per-vertex stages (vertex_kernel.h), compiled once per instruction set:
// FM_KERNEL_VARIANT names the variant and the build adds its -m flags, as for tet_kernel.c.
#ifndef FM_KERNEL_VARIANT
#define FM_KERNEL_VARIANT baseline
#endif
#include "fem/kernels/vertex_kernel.h"

#include "core/simd.h"
#include "fem/elastic_mesh.h"

#include <string.h>

#if defined(__GNUC__) || defined(__clang__)
#define FM_INLINE static inline __attribute__((always_inline))
#else
#define FM_INLINE static inline
#endif

// ---- a block's displacements
// ----------------------------------------------------------------------

#if defined(__AVX__) && !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__))
void FM_KERNEL_NAME(fmVertexKernel_Displacements)(const int* verts, int count, const double* x,
                                                  const double* X, double* u)
{
	// The masked loads read x, y and z only and give the fourth lane 0.
	const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);
	for (int i = 0; i < count; ++i)
	{
		const size_t v = 3 * (size_t)verts[i];
		_mm256_storeu_pd(u + 4 * (size_t)i, _mm256_sub_pd(_mm256_maskload_pd(x + v, xyz),
		                                                  _mm256_maskload_pd(X + v, xyz)));
	}
}
#else
void FM_KERNEL_NAME(fmVertexKernel_Displacements)(const int* verts, int count, const double* x,
                                                  const double* X, double* u)
{
	for (int i = 0; i < count; ++i)
	{
		for (int c = 0; c < 3; ++c)
			u[4 * i + c] = x[3 * verts[i] + c] - X[3 * verts[i] + c];
		u[4 * i + 3] = 0.0;
	}
}
#endif

// ---- each vertex's blocks' sums ---------------------------------------------------------------

#if defined(__AVX__) && !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__))
void FM_KERNEL_NAME(fmVertexKernel_GatherSums)(const fmBlockGather* p, int start, int end)
{
	const __m256d g = _mm256_setr_pd(p->g[0], p->g[1], p->g[2], 0.0);
	const double* restrict sums = p->sums;
	const int* restrict entries = p->entries;
	const int* restrict entryStart = p->entryStart;
	const double* restrict mass = p->mass;
	double* restrict forces = p->f;
	for (int i = start; i < end; ++i)
	{
		// (x, y, z, the next entry's x): the fourth lane is never stored.
		__m256d f = _mm256_mul_pd(_mm256_broadcast_sd(mass + i), g);
		for (int e = entryStart[i]; e < entryStart[i + 1]; ++e)
			f = _mm256_add_pd(f, _mm256_loadu_pd(sums + 3 * (size_t)entries[e]));
		double* out = forces + 3 * (size_t)i;
		_mm_storeu_pd(out, _mm256_castpd256_pd128(f));
		_mm_store_sd(out + 2, _mm256_extractf128_pd(f, 1));
	}
}
#else
FM_INLINE void fmGatherOne(const fmBlockGather* p, int i)
{
	const double m = p->mass[i];
	double fx = m * p->g[0], fy = m * p->g[1], fz = m * p->g[2];
	for (int e = p->entryStart[i]; e < p->entryStart[i + 1]; ++e)
	{
		const double* sum = p->sums + 3 * (size_t)p->entries[e];
		fx += sum[0], fy += sum[1], fz += sum[2];
	}
	double* f = p->f + 3 * (size_t)i;
	f[0] = fx, f[1] = fy, f[2] = fz;
}

void FM_KERNEL_NAME(fmVertexKernel_GatherSums)(const fmBlockGather* p, int start, int end)
{
	for (int i = start; i < end; ++i)
		fmGatherOne(p, i);
}
#endif

// ---- the explicit step's vertex updates
// -----------------------------------------------------------

// Vertex i's zeroed pinned axes (fmZeroPinnedAxes).
FM_INLINE void fmZeroAxes(unsigned pins, double* vi)
{
	for (int k = 0; k < 3; ++k)
		if ((pins >> k) & 1u)
			vi[k] = 0.0;
}

FM_INLINE void fmVelocityOne(const fmVertexUpdate* u, int i)
{
	double* vi = u->v + 3 * (size_t)i;
	const double* fi = u->f + 3 * (size_t)i;
	const unsigned pins = u->pinned[i];
	if (pins != FM_PIN_ALL)
	{
		const double s = u->dt * u->invMass[i];
		vi[0] = vi[0] + s * fi[0], vi[1] = vi[1] + s * fi[1], vi[2] = vi[2] + s * fi[2];
		fmZeroAxes(pins, vi);
	}
	vi[0] *= u->damping, vi[1] *= u->damping, vi[2] *= u->damping;
}

FM_INLINE void fmBlendOne(const fmVertexUpdate* u, int i)
{
	const unsigned pins = u->pinned[i];
	if (pins == FM_PIN_ALL)
		return;
	double* vi = u->v + 3 * (size_t)i;
	const double* si = u->sum + 3 * (size_t)i;
	const double w = u->weight[i];
	for (int k = 0; k < 3; ++k)
		vi[k] = u->keep * vi[k] + u->blend * (w * si[k]);
	fmZeroAxes(pins, vi);
}

FM_INLINE void fmPositionOne(const fmVertexUpdate* u, int i)
{
	if (u->pinned[i] == FM_PIN_ALL)
		return;
	double* xi = u->x + 3 * (size_t)i;
	const double* vi = u->v + 3 * (size_t)i;
	for (int k = 0; k < 3; ++k)
		xi[k] = xi[k] + u->dt * vi[k];
}

#if defined(__AVX2__) && !defined(FM_SIMD_SCALAR) && (defined(__GNUC__) || defined(__clang__))
// Four vertices' 12 doubles are three vectors; a per-vertex value s0..s3 spreads over them as
// (s0 s0 s0 s1), (s1 s1 s2 s2), (s2 s3 s3 s3).
FM_INLINE void fmSpread4(__m256d s, __m256d out[3])
{
	out[0] = _mm256_permute4x64_pd(s, _MM_SHUFFLE(1, 0, 0, 0));
	out[1] = _mm256_permute4x64_pd(s, _MM_SHUFFLE(2, 2, 1, 1));
	out[2] = _mm256_permute4x64_pd(s, _MM_SHUFFLE(3, 3, 3, 2));
}

// Whether vertices [i, i + 4) have no pins.
FM_INLINE bool fmFree4(const uint8_t* pinned, int i)
{
	uint32_t pins;
	memcpy(&pins, pinned + i, sizeof pins);
	return pins == 0u;
}

void FM_KERNEL_NAME(fmVertexKernel_Velocities)(const fmVertexUpdate* u, int start, int end)
{
	const __m256d dt = _mm256_set1_pd(u->dt), d = _mm256_set1_pd(u->damping);
	int i = start;
	for (; i + 4 <= end; i += 4)
	{
		if (!fmFree4(u->pinned, i))
		{
			for (int k = i; k < i + 4; ++k)
				fmVelocityOne(u, k);
			continue;
		}
		__m256d s[3];
		fmSpread4(_mm256_mul_pd(dt, _mm256_loadu_pd(u->invMass + i)), s);
		double* v = u->v + 3 * (size_t)i;
		const double* f = u->f + 3 * (size_t)i;
		for (int r = 0; r < 3; ++r)
		{
			__m256d vr = _mm256_add_pd(_mm256_loadu_pd(v + 4 * r),
			                           _mm256_mul_pd(s[r], _mm256_loadu_pd(f + 4 * r)));
			_mm256_storeu_pd(v + 4 * r, _mm256_mul_pd(vr, d));
		}
	}
	for (; i < end; ++i)
		fmVelocityOne(u, i);
}

void FM_KERNEL_NAME(fmVertexKernel_Blend)(const fmVertexUpdate* u, int start, int end)
{
	const __m256d keep = _mm256_set1_pd(u->keep), blend = _mm256_set1_pd(u->blend);
	int i = start;
	for (; i + 4 <= end; i += 4)
	{
		if (!fmFree4(u->pinned, i))
		{
			for (int k = i; k < i + 4; ++k)
				fmBlendOne(u, k);
			continue;
		}
		__m256d w[3];
		fmSpread4(_mm256_loadu_pd(u->weight + i), w);
		double* v = u->v + 3 * (size_t)i;
		const double* sum = u->sum + 3 * (size_t)i;
		for (int r = 0; r < 3; ++r)
		{
			__m256d smoothed =
			    _mm256_mul_pd(blend, _mm256_mul_pd(w[r], _mm256_loadu_pd(sum + 4 * r)));
			_mm256_storeu_pd(
			    v + 4 * r,
			    _mm256_add_pd(_mm256_mul_pd(keep, _mm256_loadu_pd(v + 4 * r)), smoothed));
		}
	}
	for (; i < end; ++i)
		fmBlendOne(u, i);
}

void FM_KERNEL_NAME(fmVertexKernel_Positions)(const fmVertexUpdate* u, int start, int end)
{
	const __m256d dt = _mm256_set1_pd(u->dt);
	int i = start;
	for (; i + 4 <= end; i += 4)
	{
		if (!fmFree4(u->pinned, i))
		{
			for (int k = i; k < i + 4; ++k)
				fmPositionOne(u, k);
			continue;
		}
		double* x = u->x + 3 * (size_t)i;
		const double* v = u->v + 3 * (size_t)i;
		for (int r = 0; r < 3; ++r)
			_mm256_storeu_pd(x + 4 * r,
			                 _mm256_add_pd(_mm256_loadu_pd(x + 4 * r),
			                               _mm256_mul_pd(dt, _mm256_loadu_pd(v + 4 * r))));
	}
	for (; i < end; ++i)
		fmPositionOne(u, i);
}
#else
void FM_KERNEL_NAME(fmVertexKernel_Velocities)(const fmVertexUpdate* u, int start, int end)
{
	for (int i = start; i < end; ++i)
		fmVelocityOne(u, i);
}

void FM_KERNEL_NAME(fmVertexKernel_Blend)(const fmVertexUpdate* u, int start, int end)
{
	for (int i = start; i < end; ++i)
		fmBlendOne(u, i);
}

void FM_KERNEL_NAME(fmVertexKernel_Positions)(const fmVertexUpdate* u, int start, int end)
{
	for (int i = start; i < end; ++i)
		fmPositionOne(u, i);
}
#endif
