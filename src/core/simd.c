// The instruction set the element kernels run with (simd.h).
#include "core/simd.h"

fmSimdLevel fmSimd_Detect(void)
{
#if (defined(__x86_64__) || defined(_M_X64)) && (defined(__GNUC__) || defined(__clang__))
	__builtin_cpu_init();
	if (__builtin_cpu_supports("avx512f"))
		return fm_simdAvx512;
	if (__builtin_cpu_supports("avx2"))
		return fm_simdAvx2;
	return fm_simdSse2;
#elif defined(__GNUC__) || defined(__clang__)
	return fm_simdSse2; // the target's baseline vectors (NEON, WebAssembly SIMD) or lowered
#else
	return fm_simdScalar;
#endif
}

fmSimdLevel fmSimd_Resolve(fmSimdLevel requested)
{
	if (requested == fm_simdOff || requested == fm_simdScalar)
		return requested;
	fmSimdLevel best = fmSimd_Detect();
	if (requested == fm_simdAuto || requested > best)
		return best;
	return requested;
}

static const char* const s_levelNames[fm_simdLevelCount] = {"auto", "off",  "scalar",
                                                            "sse2", "avx2", "avx512"};

const char* fmSimdLevelName(fmSimdLevel level)
{
	if ((int)level < 0 || level >= fm_simdLevelCount)
		return "unknown";
	return s_levelNames[level];
}

bool fmSimdLevelFromName(const char* name, fmSimdLevel* level)
{
	for (int i = 0; name != NULL && i < fm_simdLevelCount; ++i)
		if (strcmp(name, s_levelNames[i]) == 0)
		{
			*level = (fmSimdLevel)i;
			return true;
		}
	return false;
}
