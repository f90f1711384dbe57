// The floating-point environment (fp_env.h). On x86 the state doubles are computed in is SSE's
// MXCSR (x86-64 never uses the x87 unit for double; 32-bit x86 must be built with
// -msse2 -mfpmath=sse); on AArch64 it is FPCR; elsewhere (WebAssembly has no modes, other
// targets) the C99 <fenv.h> rounding mode. Reading and writing the register costs a few cycles,
// so it is done on every public call, not only with fmWorldDef.crossPlatformDeterminism.
#include "core/fp_env.h"

#include "core/det_math.h"

#if defined(__SSE__) || defined(_M_X64) || (defined(_M_IX86_FP) && _M_IX86_FP >= 1)
#include <xmmintrin.h>
#define FM_FP_MXCSR 1
#elif defined(__aarch64__) && (defined(__GNUC__) || defined(__clang__))
#define FM_FP_FPCR 1
#else
#include <fenv.h>
#endif

#if FM_FP_MXCSR
// MXCSR: the six exception masks (bits 7-12) set, round to nearest (bits 13-14 zero), no
// flush-to-zero (bit 15) and no denormals-are-zero (bit 6), no exception flags. 0x1F80 is also
// the state a process starts in.
#define FM_MXCSR_FEMTO 0x1F80u

static uint64_t fmGetControl(void)
{
	return _mm_getcsr();
}

static void fmSetControl(uint64_t control)
{
	_mm_setcsr((unsigned)control);
}

static uint64_t fmFemtoControl(uint64_t host)
{
	(void)host;
	return FM_MXCSR_FEMTO;
}
#elif FM_FP_FPCR
// FPCR: round to nearest (RMode, bits 22-23, zero), no flush-to-zero (FZ, bit 24; FZ16, bit
// 19), no default-NaN mode (DN, bit 25), no exception traps (bits 8-12 and 15), and the
// alternate-handling bits of FEAT_AFP (AH, FIZ, NEP: bits 0-2) off. Other bits are kept.
#define FM_FPCR_CLEAR                                                                              \
	((3ull << 22) | (1ull << 24) | (1ull << 19) | (1ull << 25) | (0x1Full << 8) | (1ull << 15) |   \
	 0x7ull)

static uint64_t fmGetControl(void)
{
	uint64_t control;
	__asm__ __volatile__("mrs %0, fpcr" : "=r"(control));
	return control;
}

static void fmSetControl(uint64_t control)
{
	__asm__ __volatile__("msr fpcr, %0" : : "r"(control));
}

static uint64_t fmFemtoControl(uint64_t host)
{
	return host & ~FM_FPCR_CLEAR;
}
#else
static uint64_t fmGetControl(void)
{
	return (uint64_t)(unsigned)fegetround();
}

static void fmSetControl(uint64_t control)
{
	fesetround((int)control);
}

static uint64_t fmFemtoControl(uint64_t host)
{
	(void)host;
	return (uint64_t)(unsigned)FE_TONEAREST;
}
#endif

fmFpEnv fmFpEnv_Enter(bool deterministicMath)
{
	fmFpEnv saved;
	saved.control = fmGetControl();
	saved.deterministicMath = fmDetMath_Enabled();
	uint64_t femto = fmFemtoControl(saved.control);
	if (femto != saved.control)
		fmSetControl(femto);
	fmDetMath_Enable(deterministicMath);
	return saved;
}

void fmFpEnv_Leave(const fmFpEnv* saved)
{
	fmDetMath_Enable(saved->deterministicMath);
	if (fmGetControl() != saved->control)
		fmSetControl(saved->control);
}

bool fmFpEnv_IsFemtos(void)
{
	uint64_t control = fmGetControl();
#if FM_FP_MXCSR
	control &= ~0x3Fu; // the exception flags femto's own arithmetic raises
#endif
	return control == fmFemtoControl(control);
}
