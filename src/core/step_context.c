// The stages' bookings into the step context (see step_context.h).
#include "core/step_context.h"

void fmStepContext_AddContactWork(const fmStepContext* context, int slot, double work)
{
	if (work > 0.0)
		context->work[slot].contact += work;
}

void fmStepContext_AddLoadWork(const fmStepContext* context, int slot, double work)
{
	context->work[slot].load += work;
	if (work > 0.0)
		context->work[slot].loadIn += work;
}
