// A body's record in a snapshot (snapshot.c writes and checks the rest): its key, its state
// (positions, velocities, the last good state, pins, springs, material, ledger), its plastic
// state and the implicit solve's kept matrix, each moved by one function for saving and
// restoring (snapshot_stream.h).
#pragma once

#include "body/body.h"
#include "world/snapshot_stream.h"

#include <stddef.h>
#include <stdint.h>

struct fmWorld;

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

// A body's topology record (version 13), before the bodies' keys: a byte (0: whole, 1: torn),
// then for a torn body its vertex count (int32), its tets' corners (4 int32 a tet, the body's
// order) and its broken faces (4 bytes a tet). Restoring changes the body's topology first
// (fracture.h), so that its key and record then match.
void fmSnapshotBody_PutTopology(fmStream* s, const fmBody* b);

// Check the topology record at the stream's position against body @p b (stepping over it):
// 0 when it is the body's own, 1 when it is another the body can take, -1 when invalid, -2
// without memory to check it; @p vertexCount gets the record's vertex count.
int fmSnapshotBody_CheckTopology(fmStream* s, const fmBody* b, int* vertexCount);

// Give body @p b the (checked) topology record at the stream's position; false when out of
// memory.
bool fmSnapshotBody_ApplyTopology(fmStream* s, struct fmWorld* w, fmBody* b);
