// World queries (query.c): ray casts against the bodies' deformed surfaces and the colliders.
#pragma once

#include <femto/femto.h>
