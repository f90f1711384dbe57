// A 64-bit checksum of a byte range (checksum.c): detects changed bytes in a snapshot. Not
// cryptographic: it finds accidents (a flipped byte, a cut buffer), not forgeries.
#pragma once

#include <stddef.h>
#include <stdint.h>

// The checksum of @p bytes bytes at @p data, continuing from @p seed (0 to start). The same
// value on every platform: the bytes are read as little-endian 64-bit words.
uint64_t fmChecksum64(const void* data, size_t bytes, uint64_t seed);
