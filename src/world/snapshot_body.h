// A body's record in a snapshot (snapshot.c writes and checks the rest): its key, its state
// (positions, velocities, the last good state, pins, springs, material, ledger), its plastic
// state and the implicit solve's kept matrix, each moved by one function for saving and
// restoring (snapshot_stream.h).
#pragma once

#include "body/body.h"
#include "world/snapshot_stream.h"

#include <stddef.h>
#include <stdint.h>

// A body's identity in the snapshot: slot, generation and sizes.
typedef struct fmBodyKey
{
	int32_t slot;
	uint32_t generation;
	int32_t vertexCount;
	int32_t tetCount;
	int32_t edgeCount;
	int32_t forceModel;
} fmBodyKey;

// Body @p b's key at slot @p slot.
fmBodyKey fmSnapshotBody_Key(const fmBody* b, int slot);

// Save (@p save) or restore body @p b's record; false when a restore cannot take it (memory,
// another matrix size).
bool fmSnapshotBody_Move(fmStream* s, bool save, fmBody* b);

// Bytes of body @p b's record at @p offset of the buffer (after its key), or SIZE_MAX when the
// record does not fit @p b (another matrix size), the buffer, or holds an invalid material.
size_t fmSnapshotBody_RecordBytes(fmBody* b, const void* buffer, size_t size, size_t offset);
