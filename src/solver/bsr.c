// Block sparse matrices (bsr.h): the pattern from the tets' vertex pairs, and the row kernels of
// the instruction set the CPU runs (bsr_kernel.h).
#include "solver/bsr.h"

#include "core/core.h"
#include "core/simd.h"
#include "solver/kernels/bsr_kernel.h"

#include <math.h>
#include <string.h>

void fmBsr_Free(fmBsrMatrix* m)
{
	FM_FREE_ARRAY(m->rowStart, int, (size_t)m->rows + 1);
	FM_FREE_ARRAY(m->columns, int, m->blocks);
	FM_FREE_ARRAY(m->diagonal, int, m->rows);
	memset(m, 0, sizeof *m);
}

int fmSortUnique(int* list, int count)
{
	for (int i = 1; i < count; ++i)
	{
		int value = list[i], j = i - 1;
		while (j >= 0 && list[j] > value)
		{
			list[j + 1] = list[j];
			--j;
		}
		list[j + 1] = value;
	}
	int unique = 0;
	for (int i = 0; i < count; ++i)
		if (unique == 0 || list[unique - 1] != list[i])
			list[unique++] = list[i];
	return unique;
}

// Vertex -> tets adjacency (CSR): start has n + 1 entries, list 4 * tetCount.
static bool fmVertexTets(int n, const int* tets, int tetCount, int** start, int** list)
{
	*start = FM_ALLOC_ZERO(int, (size_t)n + 1);
	*list = FM_ALLOC_ARRAY(int, 4 * (size_t)tetCount);
	if (*start == NULL || *list == NULL)
		return false;
	for (int k = 0; k < 4 * tetCount; ++k)
		(*start)[tets[k] + 1] += 1;
	for (int i = 0; i < n; ++i)
		(*start)[i + 1] += (*start)[i];
	int* fill = FM_ALLOC_ARRAY(int, n);
	if (fill == NULL)
		return false;
	memcpy(fill, *start, sizeof(int) * (size_t)n);
	for (int k = 0; k < 4 * tetCount; ++k)
		(*list)[fill[tets[k]]++] = k / 4;
	FM_FREE_ARRAY(fill, int, n);
	return true;
}

// Count (columns == NULL) or write the sorted neighbour lists of every vertex.
static int fmGatherRows(int n, const int* tets, const int* start, const int* list, int* scratch,
                        int* rowStart, int* columns)
{
	int total = 0;
	for (int i = 0; i < n; ++i)
	{
		int count = 0;
		scratch[count++] = i; // every vertex keeps its diagonal block, even a loose one
		for (int k = start[i]; k < start[i + 1]; ++k)
			for (int a = 0; a < 4; ++a)
				scratch[count++] = tets[4 * list[k] + a];
		count = fmSortUnique(scratch, count);
		if (columns)
			memcpy(columns + total, scratch, sizeof(int) * (size_t)count);
		if (rowStart)
			rowStart[i + 1] = total + count;
		total += count;
	}
	return total;
}

bool fmBsr_Build(fmBsrMatrix* m, int n, const int* tets, int tetCount)
{
	memset(m, 0, sizeof *m);
	int *start = NULL, *list = NULL;
	bool ok = fmVertexTets(n, tets, tetCount, &start, &list);
	int maxDegree = 0;
	for (int i = 0; ok && i < n; ++i)
		maxDegree = start[i + 1] - start[i] > maxDegree ? start[i + 1] - start[i] : maxDegree;
	size_t scratchCount = 4 * (size_t)maxDegree + 1;
	int* scratch = ok ? FM_ALLOC_ARRAY(int, scratchCount) : NULL;
	ok = ok && scratch != NULL;
	if (ok)
	{
		m->rows = n;
		m->blocks = fmGatherRows(n, tets, start, list, scratch, NULL, NULL);
		m->rowStart = FM_ALLOC_ZERO(int, (size_t)n + 1);
		m->columns = FM_ALLOC_ARRAY(int, m->blocks);
		m->diagonal = FM_ALLOC_ARRAY(int, n);
		ok = m->rowStart && m->columns && m->diagonal;
	}
	if (ok)
	{
		fmGatherRows(n, tets, start, list, scratch, m->rowStart, m->columns);
		for (int i = 0; i < n; ++i)
			m->diagonal[i] = fmBsr_Find(m, i, i);
	}
	FM_FREE_ARRAY(scratch, int, scratchCount);
	FM_FREE_ARRAY(start, int, (size_t)n + 1);
	FM_FREE_ARRAY(list, int, 4 * (size_t)tetCount);
	if (!ok)
		fmBsr_Free(m);
	return ok;
}

bool fmBsr_Square(fmBsrMatrix* m)
{
	// Row i of the square: the columns of the rows that row i reaches, sorted and unique.
	int widest = 0;
	for (int i = 0; i < m->rows; ++i)
		if (m->rowStart[i + 1] - m->rowStart[i] > widest)
			widest = m->rowStart[i + 1] - m->rowStart[i];
	size_t scratchCount = (size_t)widest * (size_t)widest;
	int* scratch = FM_ALLOC_ARRAY(int, scratchCount);
	int* rowStart = FM_ALLOC_ZERO(int, (size_t)m->rows + 1);
	bool ok = scratch != NULL && rowStart != NULL;
	int* columns = NULL;
	for (int pass = 0; ok && pass < 2; ++pass)
	{
		for (int i = 0; i < m->rows; ++i)
		{
			int count = 0;
			for (int k = m->rowStart[i]; k < m->rowStart[i + 1]; ++k)
			{
				int j = m->columns[k];
				for (int q = m->rowStart[j]; q < m->rowStart[j + 1]; ++q)
					scratch[count++] = m->columns[q];
			}
			count = fmSortUnique(scratch, count);
			if (columns)
				memcpy(columns + rowStart[i], scratch, sizeof(int) * (size_t)count);
			else
				rowStart[i + 1] = rowStart[i] + count;
		}
		if (pass == 0)
			ok = (columns = FM_ALLOC_ARRAY(int, rowStart[m->rows])) != NULL;
	}
	FM_FREE_ARRAY(scratch, int, scratchCount);
	if (!ok)
	{
		FM_FREE_ARRAY(rowStart, int, (size_t)m->rows + 1);
		return false;
	}
	FM_FREE_ARRAY(m->rowStart, int, (size_t)m->rows + 1);
	FM_FREE_ARRAY(m->columns, int, m->blocks);
	m->rowStart = rowStart;
	m->columns = columns;
	m->blocks = rowStart[m->rows];
	for (int i = 0; i < m->rows; ++i)
		m->diagonal[i] = fmBsr_Find(m, i, i);
	return true;
}

int fmBsr_Find(const fmBsrMatrix* m, int row, int column)
{
	int lo = m->rowStart[row], hi = m->rowStart[row + 1] - 1;
	while (lo <= hi)
	{
		int mid = lo + (hi - lo) / 2;
		if (m->columns[mid] == column)
			return mid;
		if (m->columns[mid] < column)
			lo = mid + 1;
		else
			hi = mid - 1;
	}
	return -1;
}

void fmBsr_Multiply(const fmBsrMatrix* m, const double* values, const double* x, double* y)
{
	fmBsr_MultiplyRows(m, values, x, y, 0, m->rows);
}

// The row kernels of the instruction set the CPU runs (bsr_kernel.h): every variant gives the
// same bits.
static fmBsrKernels fmBsrKernelsOfCpu(void)
{
	switch (fmSimd_Detect())
	{
#if defined(__x86_64__) || defined(_M_X64)
	case fm_simdAvx512:
		return (fmBsrKernels){fmBsrKernel_MultiplyRows_avx512, fmBsrKernel_ForwardSweep_avx512,
		                      fmBsrKernel_BackwardSweep_avx512};
	case fm_simdAvx2:
		return (fmBsrKernels){fmBsrKernel_MultiplyRows_avx2, fmBsrKernel_ForwardSweep_avx2,
		                      fmBsrKernel_BackwardSweep_avx2};
#endif
	case fm_simdScalar:
		return (fmBsrKernels){fmBsrKernel_MultiplyRows_scalar, fmBsrKernel_ForwardSweep_scalar,
		                      fmBsrKernel_BackwardSweep_scalar};
	default:
		return (fmBsrKernels){fmBsrKernel_MultiplyRows_baseline, fmBsrKernel_ForwardSweep_baseline,
		                      fmBsrKernel_BackwardSweep_baseline};
	}
}

void fmBsr_MultiplyRows(const fmBsrMatrix* m, const double* values, const double* x, double* y,
                        int first, int end)
{
	fmBsrKernelsOfCpu().multiplyRows(m, values, x, y, first, end);
}

void fmBsr_ForwardSweep(const fmBsrMatrix* m, const double* values, const double* blockInverse,
                        const uint8_t* fixed, const double* r, double* z, int first, int end)
{
	fmBsrKernelsOfCpu().forwardSweep(m, values, blockInverse, fixed, r, z, first, end);
}

void fmBsr_BackwardSweep(const fmBsrMatrix* m, const double* values, const double* blockInverse,
                         const uint8_t* fixed, double* z, int first, int end)
{
	fmBsrKernelsOfCpu().backwardSweep(m, values, blockInverse, fixed, z, first, end);
}

// Inverse of a symmetric 3x3 block if it is positive definite (Sylvester's criterion).
static bool fmInvertSpd3(const double* A, double* out)
{
	double d1 = A[0], d2 = A[0] * A[4] - A[1] * A[3];
	double det = A[0] * (A[4] * A[8] - A[5] * A[7]) - A[1] * (A[3] * A[8] - A[5] * A[6]) +
	             A[2] * (A[3] * A[7] - A[4] * A[6]);
	if (!(d1 > 0.0 && d2 > 0.0 && det > 0.0))
		return false;
	double inv = 1.0 / det;
	out[0] = (A[4] * A[8] - A[5] * A[7]) * inv;
	out[1] = (A[2] * A[7] - A[1] * A[8]) * inv;
	out[2] = (A[1] * A[5] - A[2] * A[4]) * inv;
	out[3] = (A[5] * A[6] - A[3] * A[8]) * inv;
	out[4] = (A[0] * A[8] - A[2] * A[6]) * inv;
	out[5] = (A[2] * A[3] - A[0] * A[5]) * inv;
	out[6] = (A[3] * A[7] - A[4] * A[6]) * inv;
	out[7] = (A[1] * A[6] - A[0] * A[7]) * inv;
	out[8] = (A[0] * A[4] - A[1] * A[3]) * inv;
	return isfinite(out[0]) && isfinite(out[4]) && isfinite(out[8]);
}

void fmBsr_InvertDiagonalBlocks(int rows, const double* diagBlocks, const uint8_t* fixed,
                                bool diagonalOnly, double* blockInverse)
{
	for (int i = 0; i < rows; ++i)
	{
		double A[9];
		memcpy(A, diagBlocks + 9 * (size_t)i, sizeof A);
		for (int r = 0; r < 3; ++r)
			for (int c = 0; c < 3; ++c)
			{
				bool cut = fixed[3 * i + r] || fixed[3 * i + c] || (diagonalOnly && r != c);
				if (cut)
					A[3 * r + c] = (r == c) ? 1.0 : 0.0;
			}
		double* B = blockInverse + 9 * (size_t)i;
		if (!diagonalOnly && fmInvertSpd3(A, B))
			continue;
		memset(B, 0, sizeof(double) * 9);
		for (int r = 0; r < 3; ++r)
			B[4 * r] = A[4 * r] > 0.0 ? 1.0 / A[4 * r] : 1.0;
	}
}
