// The peers of `femto bench` (peers.c): femto-bench-bullet (bench/peers/), Bullet's deformable
// world on the same mesh, material, masses and dt, built only where CMake found Bullet. Its
// rows go next to femto's implicit Neo-Hookean rows at the game tolerance, with the ratio.
#pragma once

#include "report.h"

/// Where femto-bench-bullet is: @p given (--bullet) when not NULL, else the one built with this
/// femto (its path compiled in), if any and still there. False, with the reason in @p why
/// (@p size bytes each), when there is none.
bool cliBenchPeer_Find(const char* given, char* program, char* why, size_t size);

/// Run @p program on the meshes of @p set with at most CLI_BENCH_PEER_MAX_TETS tets (written to
/// @p folder as 0-based .node with the vertex masses and .ele) for @p repeats timed frames after
/// one second, print a table against femto's "implicit game" Neo-Hookean rows of @p report and
/// add a "bullet implicit" row per mesh. False when a run failed (said so on stderr).
bool cliBenchPeer_Rows(const char* program, const cliBenchMeshSet* set, const char* folder,
                       int repeats, cliBenchReport* report);

/// The largest mesh the peer runs on: the house and the 1k and 10k boxes and beams.
#define CLI_BENCH_PEER_MAX_TETS 20000
