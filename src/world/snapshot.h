// Snapshots of a world's simulation state (snapshot.c); the functions are public (femto.h).
#pragma once

#include <femto/femto.h>
