// Structured fuzz input: values taken from the front of the fuzzer's bytes, zero once they run
// out (so every input decodes to something, and short inputs decode to simple cases). Shared by
// fuzz_simulate.c and fuzz_api.c, with two user energies for the user-defined material models.
#pragma once

#include <femto/femto.h>

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct fmFuzzReader
{
	const uint8_t* data;
	size_t size;
	size_t at;
} fmFuzzReader;

static inline uint8_t fmFuzzByte(fmFuzzReader* r)
{
	return r->at < r->size ? r->data[r->at++] : 0;
}

// Raw bytes (zero-filled past the end).
static inline void fmFuzzBytes(fmFuzzReader* r, void* out, size_t count)
{
	uint8_t* p = out;
	for (size_t k = 0; k < count; ++k)
		p[k] = fmFuzzByte(r);
}

// An integer in [0, count).
static inline int fmFuzzPick(fmFuzzReader* r, int count)
{
	return count > 0 ? fmFuzzByte(r) % count : 0;
}

// A double near @p typical: mostly a scaled byte in [lo, hi], sometimes a value that breaks
// things (0, -0, negative, NaN, infinities, huge, tiny, raw bits).
static inline double fmFuzzDouble(fmFuzzReader* r, double lo, double hi)
{
	uint8_t kind = fmFuzzByte(r);
	if (kind < 224)
		return lo + (hi - lo) * fmFuzzByte(r) / 255.0;
	switch (kind % 8)
	{
	case 0:
		return 0.0;
	case 1:
		return -0.0;
	case 2:
		return -hi;
	case 3:
		return NAN;
	case 4:
		return (kind & 8) ? INFINITY : -INFINITY;
	case 5:
		return (kind & 8) ? 1e300 : -1e300;
	case 6:
		return 1e-310;
	default:
	{
		double value;
		fmFuzzBytes(r, &value, sizeof value);
		return value;
	}
	}
}

static inline fmVec3 fmFuzzVec3(fmFuzzReader* r, double lo, double hi)
{
	double x = fmFuzzDouble(r, lo, hi);
	double y = fmFuzzDouble(r, lo, hi);
	double z = fmFuzzDouble(r, lo, hi);
	return fmMakeVec3(x, y, z);
}

// psi = sum (s_i - 1)^2 + (s_0 s_1 s_2 - 1)^2: zero with zero gradient at s = (1, 1, 1).
static inline void fmFuzzStretchEnergy(const double s[3], const void* params, double* psi,
                                       double dpsi[3], double* d2psi)
{
	(void)params;
	double J = s[0] * s[1] * s[2];
	*psi = (J - 1.0) * (J - 1.0);
	for (int i = 0; i < 3; ++i)
	{
		double others = J == 0.0 ? s[(i + 1) % 3] * s[(i + 2) % 3] : J / s[i];
		*psi += (s[i] - 1.0) * (s[i] - 1.0);
		dpsi[i] = 2.0 * (s[i] - 1.0) + 2.0 * (J - 1.0) * others;
	}
	if (d2psi == NULL)
		return;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
		{
			double di = s[(i + 1) % 3] * s[(i + 2) % 3], dj = s[(j + 1) % 3] * s[(j + 2) % 3];
			double cross = i == j ? 0.0 : s[3 - i - j];
			d2psi[3 * i + j] = (i == j ? 2.0 : 0.0) + 2.0 * di * dj + 2.0 * (J - 1.0) * cross;
		}
}

// psi = (I1 - 3) - 2 log J + (J - 1)^2 (a Neo-Hookean), infinite for J <= 0.
static inline void fmFuzzInvariantEnergy(const double v[3], const void* params, double* psi,
                                         double dpsi[3], double* d2psi)
{
	(void)params;
	double J = v[2];
	*psi = J > 0.0 ? v[0] - 3.0 - 2.0 * log(J) + (J - 1.0) * (J - 1.0) : INFINITY;
	dpsi[0] = 1.0;
	dpsi[1] = 0.0;
	dpsi[2] = -2.0 / J + 2.0 * (J - 1.0);
	if (d2psi == NULL)
		return;
	memset(d2psi, 0, 9 * sizeof(double));
	d2psi[8] = 2.0 / (J * J) + 2.0;
}
