// Snapshots of a world's simulation state (snapshot.c); the functions are public (femto.h).
#pragma once

#include <femto/femto.h>

#include <stddef.h>

// Write the length and checksum of the snapshot in the first @p length bytes of @p buffer into
// its header (every save does; the fuzzer re-seals a snapshot it changed, to reach the checks
// behind the checksum).
void fmSnapshot_Seal(void* buffer, size_t length);
