// The logarithmic barrier and its derivatives (see barrier.h). With r = s / sHat:
//   b   = -(s - sHat)^2 ln r
//   b'  = (sHat - s)(2 ln r - sHat / s + 1)
//   b'' = (sHat / s + 2)(sHat / s) - 2 ln r - 3
#include "math/barrier.h"

#include "core/det_math.h"

#include <math.h>

double fmBarrier(double s, double sHat)
{
	if (s >= sHat)
		return 0.0;
	if (!(s > 0.0))
		return INFINITY;
	double d = s - sHat;
	return -d * d * fmMathLog(s / sHat);
}

double fmBarrier_First(double s, double sHat)
{
	if (s >= sHat)
		return 0.0;
	if (!(s > 0.0))
		return -INFINITY;
	return (sHat - s) * (2.0 * fmMathLog(s / sHat) - sHat / s + 1.0);
}

double fmBarrier_Second(double s, double sHat)
{
	if (s >= sHat)
		return 0.0;
	if (!(s > 0.0))
		return INFINITY;
	double q = sHat / s;
	return (q + 2.0) * q - 2.0 * fmMathLog(s / sHat) - 3.0;
}
