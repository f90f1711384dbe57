// The public headers must compile as C++ (engines embed femto from C++).
#include <femto/femto.h>

int femtoCxxHeaderCheck();
int femtoCxxHeaderCheck()
{
	fmWorldDef def = fmDefaultWorldDef();
	return def.maxBodies;
}
