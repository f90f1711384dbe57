// Attachments (see attachment.h).
#include "core/attachment.h"

#include <stddef.h>

void fmAttachment_Set(fmAttachment* a, void* data, void (*release)(void* data))
{
	fmAttachment_Release(a);
	a->data = data;
	a->release = data != NULL ? release : NULL;
}

void fmAttachment_Release(fmAttachment* a)
{
	if (a->data != NULL && a->release != NULL)
		a->release(a->data);
	a->data = NULL;
	a->release = NULL;
}
