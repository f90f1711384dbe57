// The rows in motion of `femto bench` (motion.c): the frames a game has, not a body at rest.
// Scenes: a drop (the body falls 1 m onto the stick floor, lands and bounces), a swing (clamped
// at its -x end, no floor, swinging under gravity), a drag (grabbed on top and pulled around a
// circle, lifted) and, on the house, the seeds' jump every second; on the house and on bars of
// about 1k, 10k and 100k tets (4 m long, Neo-Hookean at E = 1 MPa) and TetGen's beams when the
// run has them. Each frame's time is its fastest over the run's repeats, which are interleaved
// (every case once, then every case again: a preempted frame in one repeat does not survive the
// others); the Newton and CG counts are the same in every repeat (determinism). Implicit rows
// at the game tolerance say how far the game path strays from the 1e-6 path.
#pragma once

#include "meshes.h"
#include "options.h"
#include "report.h"

/// Frames each scene runs unless --frames says (2 s of 1/60 s frames).
#define CLI_MOTION_FRAMES 120

/// The largest body timed in motion (tets): implicit frames beyond it take seconds.
#define CLI_MOTION_MAX_TETS 200000

/// The largest body a --quick run times in motion (the house; no bars).
#define CLI_MOTION_QUICK_MAX_TETS 1500

/// Time the scenes in motion on the run's house, bars and beams (@p meshes: the beams made for
/// the run; the house and bars are made here when their families are asked for, or when none
/// of house, box and beam is), print a row per scene and per body, integrator and worker count
/// with every scene pooled ("all"), and add them to @p report. Sets *code to cli_exitInput when
/// a row fails (a frame refused: the reason is printed).
void cliBenchMotionRows(const cliBenchOptions* o, const cliBenchMeshSet* meshes,
                        cliBenchReport* report, int* code);

/// The props of the many-small-bodies row (--quick: CLI_PROPS_QUICK).
#define CLI_PROPS 1000
#define CLI_PROPS_QUICK 100

/// Time CLI_PROPS props of 144 tets dropped onto the floor (implicit, the game tolerance, on 1
/// and on the run's workers) beside one prop alone times their count, print the rows with the
/// ratio and add them to @p report (scene "props"). Sets *code to cli_exitInput on a failure.
void cliBenchPropsRows(const cliBenchOptions* o, cliBenchReport* report, int* code);
