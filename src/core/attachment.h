// Data a higher layer keeps on a lower layer's object (the draw stage's buffers on a body): the
// owner frees it through the release function the attacher gave, without knowing its type, so
// that the lower layer never includes the higher one.
#pragma once

typedef struct fmAttachment
{
	void* data;                 // NULL: nothing attached
	void (*release)(void* data); // frees data
} fmAttachment;

// Attach @p data (may be NULL) with its @p release, releasing what was attached before.
void fmAttachment_Set(fmAttachment* attachment, void* data, void (*release)(void* data));

// Release what is attached, leaving nothing.
void fmAttachment_Release(fmAttachment* attachment);
