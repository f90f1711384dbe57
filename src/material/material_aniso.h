// Anisotropic models (material_aniso.c, docs/materials.md "Anisotropy"): orthotropic linear and
// orthotropic St. Venant-Kirchhoff on nine engineering constants, and Neo-Hookean reinforced
// along a fibre. Each is written in the material's axes R = [fibre, sheet, fibre x sheet]
// (orthonormal columns in the body's rest frame): psi(F) = psi'(R^T F R), P = R P' R^T.
#pragma once

#include <femto/types.h>

// Whether @p model reads material axes (an anisotropic model).
static inline bool fmMaterialModel_IsAnisotropic(fmMaterialModel model)
{
	return model == fm_orthotropicLinear || model == fm_orthotropicStvk ||
	       model == fm_fibreNeoHookean;
}

// Whether @p model is one of the two orthotropic models (nine engineering constants).
static inline bool fmMaterialModel_IsOrthotropic(fmMaterialModel model)
{
	return model == fm_orthotropicLinear || model == fm_orthotropicStvk;
}

// The axes of @p material as the columns of a rotation: axis 1 along @p fibre (NULL: the
// material's own fibre; all zero: x), axis 2 the material's sheet made orthogonal to it (zero or
// parallel: y, or z when axis 1 is along y), axis 3 their cross product.
fmMat3 fmMaterial_Axes(const fmMaterial* material, const fmVec3* fibre);

// psi, P and dP/dF (material.h's layout; each output may be NULL) of an anisotropic model with
// axes @p R; @p project: dP/dF positive semi-definite for the Newton matrix. Returns psi.
double fmAniso_Evaluate(const fmMaterial* material, const fmMat3* R, const fmMat3* F, fmMat3* P,
                        double* dPdF, bool project);

// fmAniso_Evaluate with the material's own axes (fmMaterial_Axes(material, NULL)).
double fmAniso_EvaluateOwn(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF,
                           bool project);

// The orthotropic stiffness of @p o in the axes (Voigt order 11, 22, 33): the normal block
// @p normal (3x3, row-major, the inverse of the compliance's) and the shear moduli are o->G.
// False (normal untouched) when the constants are not a positive-definite material.
bool fmOrthotropy_NormalStiffness(const fmOrthotropy* o, double normal[9]);

// Check the constants an anisotropic model reads: false with the reason in @p why (a
// message for fmMaterial_Validate).
bool fmAniso_Validate(const fmMaterial* material, char* why, size_t size);

// The Voigt average of an orthotropic material's stiffness as Lame constants (the scale
// femto's tolerances and StVK's volume floor read from lambda and mu).
void fmOrthotropy_VoigtLame(const fmOrthotropy* o, double* lambda, double* mu);

// An orthotropic material's lambda and mu set to its Voigt average (a body's copy of a material
// always has them); other models are left as they are.
void fmMaterial_SetScale(fmMaterial* material);
