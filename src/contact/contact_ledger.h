// The contact stage's entries in the energy ledger (contact_ledger.c): what the stage gave each
// body (kinetic, gravity's potential, the elastic energy of the tets around the vertices it
// changed, and for explicit frames the change of symplectic Euler's shadow term), exactly, after
// minus before, booked as contact work when it is a gain. Rules: it runs after the stage's
// responses, on one thread, from the log of changed vertices (contact_state.h), and leaves every vertex as
// the stage left it.
#pragma once

#include "contact/contact_state.h"

// Book the energy the stage gave body @p slot as contact work when it is positive: pushes
// and a kinematic collider's blows add energy, inelastic impacts take it away. The energy is
// the one the ledger measures: kinetic, elastic and gravity's potential, and for explicit
// frames symplectic Euler's shadow term h/2 v . f (energy_ledger.h; @p shadowWeight is h/2), into
// @p context.
bool fmContactLedger_AddStageWork(fmWorld* world, fmContactState* state, const fmStepContext* context,
                              double shadowWeight, int slot);
