// Anisotropic models (material_aniso.h, docs/materials.md "Anisotropy").
//
// Orthotropic stiffness: the compliance of the engineering constants in the axes (Voigt order
// 11, 22, 33, then the shears) has the normal block
//   [ 1/E1      -nu12/E1  -nu13/E1 ]
//   [ -nu12/E1  1/E2      -nu23/E2 ]
//   [ -nu13/E1  -nu23/E2  1/E3     ]
// and 1/G12, 1/G13, 1/G23 on the shears (Jones, "Mechanics of Composite Materials", ch. 2; the
// same constants as CalculiX's *ELASTIC, TYPE=ENGINEERING CONSTANTS). Its inverse is the
// normal stiffness N, so sigma_ii = sum_j N_ij e_jj and sigma_ij = 2 G_ij e_ij (i != j), and the
// energy is psi = e : sigma / 2, with e the small strain sym(F') - I (linear) or Green's strain
// (F'^T F' - I) / 2 (StVK, S = sigma(e), P' = F' S), F' = R^T F R.
// Fibre-reinforced Neo-Hookean: psi = psi_NH(F) + k / 8 (I4 - 1)^2, I4 = |F a|^2, a = R e1, so
// P = P_NH + k / 2 (I4 - 1) (F a) a^T; at small strain the fibre adds k to C_1111 and so,
// exactly, k to the modulus along the fibre (a Schur complement is linear in its corner).
#include "material/material_aniso.h"

#include "material/material.h"
#include "material/material_invariant.h"
#include "material/material_neohookean.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

// @p v made unit length; false (v unchanged) when it has no direction.
static bool fmUnit(double v[3])
{
	double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	if (!(n > 0.0 && isfinite(n)))
		return false;
	for (int k = 0; k < 3; ++k)
		v[k] /= n;
	return true;
}

// @p v less its part along the unit vector @p a, made unit length; false when nothing is left.
static bool fmOrthogonalUnit(double v[3], const double a[3])
{
	double scale = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	double along = v[0] * a[0] + v[1] * a[1] + v[2] * a[2];
	for (int k = 0; k < 3; ++k)
		v[k] -= along * a[k];
	double n = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
	return n > 1e-9 * scale && fmUnit(v);
}

fmMat3 fmMaterial_Axes(const fmMaterial* material, const fmVec3* fibre)
{
	const fmVec3* f = fibre != NULL ? fibre : &material->fibre;
	double a[3] = {f->x, f->y, f->z},
	       b[3] = {material->sheet.x, material->sheet.y, material->sheet.z};
	if (!fmUnit(a))
		a[0] = 1.0, a[1] = a[2] = 0.0;
	if (!fmOrthogonalUnit(b, a))
	{
		bool alongY = fabs(a[1]) > 0.9;
		b[0] = 0.0, b[1] = alongY ? 0.0 : 1.0, b[2] = alongY ? 1.0 : 0.0;
		fmOrthogonalUnit(b, a);
	}
	fmMat3 R;
	for (int i = 0; i < 3; ++i)
	{
		int j = (i + 1) % 3, k = (i + 2) % 3;
		R.m[3 * i] = a[i];
		R.m[3 * i + 1] = b[i];
		R.m[3 * i + 2] = a[j] * b[k] - a[k] * b[j];
	}
	return R;
}

// The compliance's normal block of @p o (the file's comment).
static void fmOrthotropyCompliance(const fmOrthotropy* o, double s[9])
{
	s[0] = 1.0 / o->E[0];
	s[4] = 1.0 / o->E[1];
	s[8] = 1.0 / o->E[2];
	s[1] = s[3] = -o->nu[0] / o->E[0];
	s[2] = s[6] = -o->nu[1] / o->E[0];
	s[5] = s[7] = -o->nu[2] / o->E[1];
}

bool fmOrthotropy_NormalStiffness(const fmOrthotropy* o, double normal[9])
{
	double s[9];
	fmOrthotropyCompliance(o, s);
	double minor2 = s[0] * s[4] - s[1] * s[3];
	fmMat3 S, C;
	memcpy(S.m, s, sizeof s);
	C = fmCofactor(&S); // symmetric, so also the adjugate
	double det = s[0] * C.m[0] + s[1] * C.m[1] + s[2] * C.m[2];
	if (!(s[0] > 0.0 && minor2 > 0.0 && det > 0.0 && isfinite(det)))
		return false;
	for (int k = 0; k < 9; ++k)
		normal[k] = C.m[k] / det;
	return true;
}

void fmOrthotropy_VoigtLame(const fmOrthotropy* o, double* lambda, double* mu)
{
	double n[9];
	if (!fmOrthotropy_NormalStiffness(o, n))
	{
		*lambda = *mu = NAN;
		return;
	}
	double diagonal = n[0] + n[4] + n[8], off = n[1] + n[2] + n[5];
	double shear = o->G[0] + o->G[1] + o->G[2];
	*mu = (diagonal - off + 3.0 * shear) / 15.0;
	*lambda = (diagonal + 2.0 * off) / 9.0 - 2.0 / 3.0 * *mu;
}

bool fmAniso_Validate(const fmMaterial* m, char* why, size_t size)
{
	const fmVec3* axes[2] = {&m->fibre, &m->sheet};
	for (int k = 0; k < 2; ++k)
		if (!isfinite(axes[k]->x) || !isfinite(axes[k]->y) || !isfinite(axes[k]->z))
		{
			snprintf(why, size, "the material's %s direction must be finite",
			         k == 0 ? "fibre" : "sheet");
			return false;
		}
	if (m->model == fm_fibreNeoHookean &&
	    !(m->fibreStiffness >= 0.0 && isfinite(m->fibreStiffness)))
	{
		snprintf(why, size,
		         "fibreStiffness = %g Pa must be finite and >= 0 (it adds to Young's modulus "
		         "along the fibre; 0 is plain Neo-Hookean)",
		         m->fibreStiffness);
		return false;
	}
	if (!fmMaterialModel_IsOrthotropic(m->model))
		return true;
	const fmOrthotropy* o = &m->orthotropy;
	static const char* const names[9] = {"E1",   "E2",  "E3",  "nu12", "nu13",
	                                     "nu23", "G12", "G13", "G23"};
	const double* constants[3] = {o->E, o->nu, o->G};
	for (int k = 0; k < 9; ++k)
	{
		double v = constants[k / 3][k % 3];
		if (!isfinite(v) || (k / 3 != 1 && !(v > 0.0)))
		{
			snprintf(why, size, "orthotropy %s = %g must be finite%s", names[k], v,
			         k / 3 != 1 ? " and > 0 (Pa)" : "");
			return false;
		}
	}
	double n[9];
	if (!fmOrthotropy_NormalStiffness(o, n))
	{
		snprintf(why, size,
		         "orthotropic constants E = %g, %g, %g Pa, nu12 = %g, nu13 = %g, nu23 = %g are "
		         "not a stable material: the compliance must be positive definite "
		         "(|nu12| < sqrt(E1/E2), |nu13| < sqrt(E1/E3), |nu23| < sqrt(E2/E3) and "
		         "1 - nu12 nu21 - nu13 nu31 - nu23 nu32 - 2 nu21 nu32 nu13 > 0)",
		         o->E[0], o->E[1], o->E[2], o->nu[0], o->nu[1], o->nu[2]);
		return false;
	}
	return true;
}

// sigma(e) of the orthotropic stiffness for a symmetric strain-like @p e (the file's comment).
static fmMat3 fmOrthotropicStress(const double n[9], const fmOrthotropy* o, const fmMat3* e)
{
	fmMat3 s;
	for (int i = 0; i < 3; ++i)
		s.m[4 * i] = n[3 * i] * e->m[0] + n[3 * i + 1] * e->m[4] + n[3 * i + 2] * e->m[8];
	s.m[1] = s.m[3] = 2.0 * o->G[0] * e->m[1];
	s.m[2] = s.m[6] = 2.0 * o->G[1] * e->m[2];
	s.m[5] = s.m[7] = 2.0 * o->G[2] * e->m[5];
	return s;
}

static fmMat3 fmSym(const fmMat3* a)
{
	fmMat3 s;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			s.m[3 * i + j] = 0.5 * (a->m[3 * i + j] + a->m[3 * j + i]);
	return s;
}

// op(A) op(B), op transposing where asked: one loop for every product here (the page's .wasm
// keeps one copy of it rather than ten unrolled ones).
static fmMat3 fmProduct(const fmMat3* A, bool transposeA, const fmMat3* B, bool transposeB)
{
	fmMat3 C;
	for (int i = 0; i < 3; ++i)
		for (int j = 0; j < 3; ++j)
		{
			double sum = 0.0;
			for (int k = 0; k < 3; ++k)
				sum += A->m[transposeA ? 3 * k + i : 3 * i + k] *
				       B->m[transposeB ? 3 * j + k : 3 * k + j];
			C.m[3 * i + j] = sum;
		}
	return C;
}

// R A R^T (@p in false) or R^T A R (@p in true).
static fmMat3 fmTurn(const fmMat3* R, const fmMat3* A, bool in)
{
	fmMat3 RA = fmProduct(R, in, A, false);
	return fmProduct(&RA, false, R, !in);
}

// The orthotropic models in the axes: psi, P' at F' (Fp), and the directional derivative
// of P' along dFp when @p dFp is not NULL (into dP).
typedef struct fmOrthoPoint
{
	double n[9];
	const fmOrthotropy* o;
	bool green; // StVK: strain (F'^T F' - I) / 2 and P' = F' S
	fmMat3 Fp, S;
} fmOrthoPoint;

static double fmOrthoStress(fmOrthoPoint* q, fmMat3* Pp)
{
	fmMat3 e = q->green ? fmProduct(&q->Fp, true, &q->Fp, false) : fmSym(&q->Fp);
	for (int k = 0; k < 9; ++k)
		e.m[k] = (q->green ? 0.5 : 1.0) * (e.m[k] - (k % 4 == 0 ? 1.0 : 0.0));
	q->S = fmOrthotropicStress(q->n, q->o, &e);
	*Pp = q->green ? fmProduct(&q->Fp, false, &q->S, false) : q->S;
	return 0.5 * fmDDot(&e, &q->S);
}

static fmMat3 fmOrthoDirection(const fmOrthoPoint* q, const fmMat3* dFp)
{
	if (!q->green)
	{
		fmMat3 de = fmSym(dFp);
		return fmOrthotropicStress(q->n, q->o, &de);
	}
	fmMat3 FtdF = fmProduct(&q->Fp, true, dFp, false), de = fmSym(&FtdF);
	fmMat3 dS = fmOrthotropicStress(q->n, q->o, &de), a = fmProduct(dFp, false, &q->S, false);
	fmMat3 b = fmProduct(&q->Fp, false, &dS, false);
	for (int k = 0; k < 9; ++k)
		a.m[k] += b.m[k];
	return a;
}

static double fmOrtho_Evaluate(const fmMaterial* m, const fmMat3* R, const fmMat3* F, fmMat3* P,
                               double* dPdF, bool project)
{
	fmOrthoPoint q;
	q.o = &m->orthotropy;
	q.green = m->model == fm_orthotropicStvk;
	q.Fp = fmTurn(R, F, true);
	if (!fmOrthotropy_NormalStiffness(q.o, q.n))
		memset(q.n, 0, sizeof q.n); // (validated materials never get here)
	fmMat3 Pp;
	double psi = fmOrthoStress(&q, &Pp);
	if (P)
		*P = fmTurn(R, &Pp, false);
	for (int kl = 0; dPdF != NULL && kl < 9; ++kl)
	{
		// dF = e_k e_l^T in the world is R^T e_k e_l^T R in the axes: rows k and l of R.
		int k = kl / 3, l = kl % 3;
		fmMat3 dFp;
		for (int a = 0; a < 3; ++a)
			for (int b = 0; b < 3; ++b)
				dFp.m[3 * a + b] = R->m[3 * k + a] * R->m[3 * l + b];
		fmMat3 dPp = fmOrthoDirection(&q, &dFp), dP = fmTurn(R, &dPp, false);
		for (int ij = 0; ij < 9; ++ij)
			dPdF[9 * ij + kl] = dP.m[ij];
	}
	if (q.green && fmDet(F) < FM_STVK_FLOOR_J)
	{
		fmMaterial scaled = *m; // the floor's stiffness from the Voigt average
		fmOrthotropy_VoigtLame(q.o, &scaled.lambda, &scaled.mu);
		psi += fmMaterial_AddStvkFloor(&scaled, F, P, dPdF);
	}
	// The linear stiffness is positive semi-definite already; StVK's stress term is not: the
	// nearest positive semi-definite tangent (the 9x9 eigen-solve) for the Newton matrix.
	if (dPdF != NULL && project && q.green)
		fmProjectPSD9(dPdF);
	return psi;
}

static double fmFibre_Evaluate(const fmMaterial* m, const fmMat3* R, const fmMat3* F, fmMat3* P,
                               double* dPdF, bool project)
{
	fmMaterial nh = *m;
	nh.model = fm_neoHookean;
	double psi = fmNeoHookean_Evaluate(&nh, F, P);
	if (dPdF != NULL)
		fmInvariantModel_Evaluate(&nh, F, NULL, dPdF);
	const double a[3] = {R->m[0], R->m[3], R->m[6]}, k = m->fibreStiffness;
	double Fa[3];
	for (int i = 0; i < 3; ++i)
		Fa[i] = F->m[3 * i] * a[0] + F->m[3 * i + 1] * a[1] + F->m[3 * i + 2] * a[2];
	double stretch = Fa[0] * Fa[0] + Fa[1] * Fa[1] + Fa[2] * Fa[2] - 1.0; // I4 - 1
	for (int i = 0; P != NULL && i < 3; ++i)
		for (int j = 0; j < 3; ++j)
			P->m[3 * i + j] += 0.5 * k * stretch * Fa[i] * a[j];
	// dP_ij / dF_kl = k / 2 ((I4 - 1) d_ik a_j a_l + 2 (F a)_i a_j (F a)_k a_l).
	const double first = 0.5 * k * stretch;
	for (int ij = 0; dPdF != NULL && ij < 9; ++ij)
		for (int kl = 0; kl < 9; ++kl)
		{
			int i = ij / 3, j = ij % 3, kk = kl / 3, l = kl % 3;
			dPdF[9 * ij + kl] +=
			    (i == kk ? first * a[j] * a[l] : 0.0) + k * Fa[i] * a[j] * Fa[kk] * a[l];
		}
	// The Newton matrix: the nearest positive semi-definite tangent (the 9x9 eigen-solve).
	if (dPdF != NULL && project)
		fmProjectPSD9(dPdF);
	return psi + 0.125 * k * stretch * stretch;
}

double fmAniso_EvaluateOwn(const fmMaterial* material, const fmMat3* F, fmMat3* P, double* dPdF,
                           bool project)
{
	fmMat3 R = fmMaterial_Axes(material, NULL);
	return fmAniso_Evaluate(material, &R, F, P, dPdF, project);
}

double fmAniso_Evaluate(const fmMaterial* material, const fmMat3* R, const fmMat3* F, fmMat3* P,
                        double* dPdF, bool project)
{
	if (material->model == fm_fibreNeoHookean)
		return fmFibre_Evaluate(material, R, F, P, dPdF, project);
	return fmOrtho_Evaluate(material, R, F, P, dPdF, project);
}

void fmMaterial_SetScale(fmMaterial* material)
{
	if (fmMaterialModel_IsOrthotropic(material->model))
		fmOrthotropy_VoigtLame(&material->orthotropy, &material->lambda, &material->mu);
}
