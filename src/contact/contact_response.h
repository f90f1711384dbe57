// The rules every contact response of the stage shares (contact_response.c): the impact on a
// relative velocity (restitution and Coulomb's cone), the creep an implicit step's friction takes
// back from the positions, pins, the floor under a pushed vertex, inverse masses and the
// friction of a pair of bodies. Rules: pure functions of their arguments, or writes to the one
// vertex they are given; called on the stage's one thread.
#pragma once

#include "world/world.h"

// The largest slip (a share of the thickness) friction takes back from the positions as well as
// the velocities (fmVertexVsCollider, fmContactPair_Respond): a creep's.
#define FM_CREEP_FRACTION 0.1

// The same between two bodies in explicit substeps (vertex and triangle, edge and edge): the
// slips taken back from a pile's vertices, contact after contact within a substep, crushed the
// tets of the explicit three-house pile at 0.1 and 0.01 of the thickness (207 refused frames,
// three_houses_dropped_on_each_other); at 0.003 and 0.001 it holds, and so does the incline's
// block (a creep's slip is g h^2, well below either). A tenfold margin: 0.001.
#define FM_PAIR_CREEP_FRACTION 0.001

// The relative velocity @p relative after an impact along @p n with restitution @p e and
// friction @p mu; @p pushed (m/s) is the normal velocity a push during the step already gave
// (the implicit penalty's), which friction's cone counts too. Returns the normal velocity
// change (>= 0).
double fmContactResponse_Impact(fmVec3* relative, fmVec3 n, double e, double mu, double pushed);

// A step's positions follow its velocities (implicit x = x0 + h v, explicit symplectic Euler
// x = x0 + h v as well), so a velocity change @p dv that friction or the stick made along the
// surface (normal @p n) moves them by h dv too, where the slip it takes back is a creep (h |dv| at
// most @p limit, a share of the thickness): the slip is not kept in the positions (where it is,
// stacks and stick contacts creep: explicit substeps let a block at mu 0.7 on 30 degrees creep
// 32 mm/s). A faster slip is an impact's: moving the contact's vertices alone by it would crush
// their tets. Returns the move per unit of @p dv's scale (h, or 0). The callers say where it
// applies (explicit stick colliders keep their slip, as the seeds' stick floor does).
double fmContactResponse_CreepStep(const fmWorld* w, fmVec3 dv, fmVec3 n, double limit);

// The slip (m) friction may take back from the positions between two bodies in this substep
// (FM_CREEP_FRACTION of the thickness after an implicit step, FM_PAIR_CREEP_FRACTION in explicit
// substeps).
double fmContactResponse_PairCreep(const fmWorld* w, double thickness);

// How far the projections may separate two bodies' features (a vertex and a triangle, two
// edges) in a substep, from their distance along the contact normal at the substep's start
// @p start and how much they closed in it, @p closing: what the closing explains goes at once,
// back to the thickness; features that started within the thickness are only kept from coming
// closer (the margin is not restored: pushed back out at the depenetration speed, a stiff block
// made 2 mm from another, inside a 3.5 mm thickness, was thrown off it); ones that started behind
// each other come out at most @p depen (the depenetration speed times the substep) further.
double fmContactResponse_Reach(double start, double closing, double thickness, double depen);

// The most the depenetration speed moves a vertex out in this substep (m).
double fmContactResponse_DepenetrationStep(const fmWorld* w);

// Pinned axes keep their coordinate and have no velocity.
void fmContactResponse_KeepPins(fmBody* b, int i, fmVec3 x0);

// A push between bodies never moves a vertex below the floor (the floor holds it there).
void fmContactResponse_KeepAboveFloor(const fmWorld* w, fmBody* b, int i);

// Vertex i's inverse mass in a projection or response: 0 when it is pinned on every axis or
// its body sleeps.
double fmContactResponse_InverseMass(const fmBody* b, int i);

// The friction of two bodies in contact: sqrt(mu_a mu_b) of their friction (a negative one: the
// world's fmContactDef.friction).
double fmContactResponse_PairFriction(const fmWorld* w, const fmBody* a, const fmBody* b);
