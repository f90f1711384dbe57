// The contact audit (audit.c): fmWorld_AuditContact, and the same tests for one body against the
// others, which body creation uses to refuse a body that would start inside another.
#pragma once

#include "world/world.h"

// The audit of the body in @p slot against every other live body whose filters meet its own
// (edge-triangle crossings both ways and surface vertices inside, no tets, no self-contact) into
// @p audit. fm_errOutOfMemory, fm_errNumerical for non-finite positions.
fmResult fmAudit_Body(fmWorld* world, int slot, fmContactAudit* audit);
