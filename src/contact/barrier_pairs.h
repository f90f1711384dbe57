// The barrier's pairs (barrier_pairs.c), for one body's barrier term (barrier_contact.h): the
// surface primitives of the other bodies within its reach, the candidate stencils that can come
// within dHat while the body stays in a box around a point or a segment, and the pairs within
// dHat at a point. Rules:
// - candidates are kept while they cover the point or segment asked about (every coordinate
//   within the box's radius of its centre) and gathered again around it when they do not;
// - a candidate is dropped at gathering when its distance at the centre exceeds dHat by more
//   than twice the furthest a vertex can move inside the box (sqrt(3) radius), and skipped by a
//   search when none of its vertices moved half its slack from the centre;
// - the pairs at a point are kept until asked for another point (a solve asks for each point up
//   to three times), in the candidates' order (deterministic for any worker count).
#pragma once

#include "contact/barrier_contact.h"

// The other bodies' primitives whose boxes (grown by dHat) meet [@p lo, @p hi], into the
// scratch, hashed; other bodies whose surfaces are not that close are skipped whole. False when
// memory is short.
bool fmBarrierPairs_GatherOthers(fmBarrierContact* bc, fmVec3 lo, fmVec3 hi);

// Stencil @p st's four points: the solved body's at @p x, any other body's where it stands.
void fmBarrierPairs_Points(const fmBarrierContact* bc, const fmBarrierStencil* st, const double* x,
                           fmVec3 p[4]);

// Whether the boxes of a stencil's two sides (its points @p p, swept by @p motion when not NULL)
// are more than dHat apart on some axis: then no point of the sweep brings the pair within dHat.
bool fmBarrierPairs_SidesApart(const fmBarrierContact* bc, const fmBarrierStencil* st,
                               const fmVec3 p[4], const fmVec3* motion);

// Whether candidate @p k surely stays beyond dHat at @p x (which the candidates cover).
bool fmBarrierPairs_SurelyFar(const fmBarrierContact* bc, int k, const double* x);

// Candidates covering the segment from @p x along @p dx (NULL: the point @p x). False when
// memory is short.
bool fmBarrierPairs_Cover(const fmBarrierContact* bc, const double* x, const double* dx);

// The pairs within dHat at @p x, into the scratch's pairs. False when memory is short.
bool fmBarrierPairs_Find(const fmBarrierContact* bc, const double* x);
