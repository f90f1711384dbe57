// IPC's logarithmic barrier (Li et al. 2020, "Incremental Potential Contact", eq. 6), applied as
// ipc-toolkit applies it, to squared distances: b(s) = -(s - sHat)^2 ln(s / sHat) for
// 0 < s < sHat, 0 from sHat on, and +infinity at s <= 0. It is C2 at sHat and grows without
// bound as the distance closes, so a minimiser of an energy with it never lets two primitives
// touch (barrier.c).
#pragma once

// b(s) for a squared distance @p s and the barrier's reach @p sHat (a squared distance, > 0).
double fmBarrier(double s, double sHat);

// db/ds; 0 from sHat on. At s <= 0 (inside: no derivative) it returns -infinity.
double fmBarrier_First(double s, double sHat);

// d2b/ds2; 0 from sHat on, +infinity at s <= 0.
double fmBarrier_Second(double s, double sHat);
