// The contact audit (audit.c): fmWorld_AuditContact, and the same tests for one body against the
// others, which body creation uses to refuse a body that would start inside another.
#pragma once

#include "world/world.h"

// The audit of the body in @p slot against every other live body whose filters and boxes meet
// its own (edge-triangle crossings both ways and surface vertices inside, no inverted tets, no
// self-contact) into @p audit, and in @p tetsInside the tets of either body of such a pair whose
// centroid lies inside the other (bodies that lie on each other's surfaces, the first in
// @p firstTetInside). fm_errOutOfMemory, fm_errNumerical for non-finite positions.
fmResult fmAudit_Body(fmWorld* world, int slot, fmContactAudit* audit, int* tetsInside,
                      fmAuditFinding* firstTetInside);
