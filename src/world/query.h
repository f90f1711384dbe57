// World queries (query.c): ray casts and sphere overlaps against the bodies' deformed surfaces
// and the colliders.
#pragma once

#include <femto/femto.h>
