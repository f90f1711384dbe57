// Plasticity's law (docs/materials.md, "Plasticity"): von Mises flow with linear isotropic
// hardening and optional creep on the logarithmic strain of a tet's elastic part, and the
// checks of its parameters. The bodies' per-tet state and its update: body/plasticity.h.
#pragma once

#include <femto/types.h>

#include <stddef.h>

// Whether material @p m flows (a yield stress > 0).
static inline bool fmPlasticity_Flows(const fmMaterial* m)
{
	return m->plasticity.yieldStress > 0.0;
}

// Check a material's plasticity: false with the reason in @p why.
bool fmPlasticity_Validate(const fmMaterial* m, char* why, size_t size);

// The share of the rate-independent flow material @p m takes over a step of @p seconds: 1
// without creep or for 0 or infinite seconds (statics), else Perzyna's c t / (1 + c t) (the
// overstress relaxing at the creep rate c, implicit in t).
double fmPlasticity_Share(const fmMaterial* m, double seconds);

// The return map of one tet of material @p m: the trial elastic part @p Fe, the share of the
// rate-independent flow to take @p share (fmPlasticity_Share), the tet's equivalent plastic
// strain @p alpha (updated). The returned elastic part into @p out, the same volume; false (nothing
// written) when it does not flow: inside the yield surface, at its cap, or det Fe <= 0.
// @p stress (may be NULL) gets the von Mises stresses (Pa, Kirchhoff) of the trial state
// (stress[0]) and of the returned one (stress[1]).
bool fmPlasticity_Return(const fmMaterial* m, const fmMat3* Fe, double share, double* alpha,
                         fmMat3* out, double stress[2]);
