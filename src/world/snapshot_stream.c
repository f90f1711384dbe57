// The snapshot's byte stream (snapshot_stream.h).
#include "world/snapshot_stream.h"

#include <stdint.h>
#include <string.h>

void fmStream_Put(fmStream* s, const void* data, size_t bytes)
{
	if (bytes == 0) // an empty array may be a NULL pointer
		return;
	if (s->out != NULL && !s->overflow && bytes <= s->size - s->used)
		memcpy(s->out + s->used, data, bytes);
	else if (s->out != NULL)
		s->overflow = true;
	s->used += bytes;
}

void fmStream_Get(fmStream* s, void* data, size_t bytes)
{
	if (bytes == 0)
		return;
	if (s->overflow || bytes > s->size - s->used)
	{
		s->overflow = true;
		memset(data, 0, bytes);
		return;
	}
	memcpy(data, s->in + s->used, bytes);
	s->used += bytes;
}

void fmStream_Move(fmStream* s, bool save, void* data, size_t bytes)
{
	if (save)
		fmStream_Put(s, data, bytes);
	else
		fmStream_Get(s, data, bytes);
}

void fmStream_MoveBool(fmStream* s, bool save, bool* value)
{
	uint8_t byte = *value ? 1 : 0;
	fmStream_Move(s, save, &byte, 1);
	*value = byte != 0;
}

void fmStream_MoveDouble(fmStream* s, bool save, double* value)
{
	fmStream_Move(s, save, value, sizeof *value);
}

void fmStream_Skip(fmStream* s, size_t bytes)
{
	if (s->overflow || bytes > s->size - s->used)
		s->overflow = true;
	else
		s->used += bytes;
}
