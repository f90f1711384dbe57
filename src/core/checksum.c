// Four lanes of multiply-rotate rounds over 64-bit words (the round of xxHash64: Collet's
// design, written here from its description), each byte counted once, the length mixed in, and
// a final avalanche so that one changed bit reaches every bit of the result.
#include "core/checksum.h"

#define FM_PRIME1 0x9E3779B185EBCA87ull
#define FM_PRIME2 0xC2B2AE3D27D4EB4Full
#define FM_PRIME3 0x165667B19E3779F9ull

static uint64_t fmRotl(uint64_t x, int r)
{
	return (x << r) | (x >> (64 - r));
}

static uint64_t fmRound(uint64_t lane, uint64_t word)
{
	return fmRotl(lane + word * FM_PRIME2, 31) * FM_PRIME1;
}

// The little-endian 64-bit word at @p p, on any host.
static uint64_t fmWordAt(const unsigned char* p)
{
	uint64_t w = 0;
	for (int k = 7; k >= 0; --k)
		w = (w << 8) | p[k];
	return w;
}

uint64_t fmChecksum64(const void* data, size_t bytes, uint64_t seed)
{
	const unsigned char* p = data;
	uint64_t lane[4] = {seed + FM_PRIME1 + FM_PRIME2, seed + FM_PRIME2, seed, seed - FM_PRIME1};
	size_t at = 0;
	for (; at + 32 <= bytes; at += 32)
		for (int k = 0; k < 4; ++k)
			lane[k] = fmRound(lane[k], fmWordAt(p + at + 8 * k));
	uint64_t h =
	    fmRotl(lane[0], 1) + fmRotl(lane[1], 7) + fmRotl(lane[2], 12) + fmRotl(lane[3], 18);
	for (int k = 0; k < 4; ++k)
		h = (h ^ fmRound(0, lane[k])) * FM_PRIME1 + FM_PRIME3;
	h += (uint64_t)bytes;
	for (; at + 8 <= bytes; at += 8)
		h = fmRotl(h ^ fmRound(0, fmWordAt(p + at)), 27) * FM_PRIME1 + FM_PRIME3;
	for (; at < bytes; ++at)
		h = fmRotl(h ^ (p[at] * FM_PRIME3), 11) * FM_PRIME1;
	h ^= h >> 33;
	h *= FM_PRIME2;
	h ^= h >> 29;
	h *= FM_PRIME3;
	h ^= h >> 32;
	return h;
}
