// The averaged nodal pressure tet (Bonet and Burton 1998): a material with nodalPressure keeps
// its energy without the volume term in each tet and puts the volume term on vertex patches,
//   E = sum_e V_e psi'(F_e) + sum_a W_a U(J_a),  J_a = S_a / V_a,  S_a = sum_{e at a} V_e J_e / 4,
// V_a the patch's rest volume (a quarter of each nodal tet around vertex a), W_a = sum V_e k_e / 4
// its bulk-weighted volume, J_e = det F_e (1 + tr(F_e - I) for linear elasticity). One volume
// constraint a vertex instead of one a tet: linear tets no longer lock as nu -> 0.5.
// With p_a = (W_a / V_a) U'(J_a), the nodal pressure, and p_e the mean of its tet's four:
//   dE/dx = sum_e V_e p_e dJ_e/dx,
//   d2E/dx2 = sum_a c_a s_a s_a^T + sum_e V_e p_e d2J_e/dx2,  s_a = dS_a/dx,
//   c_a = W_a U''(J_a) / V_a^2.
// The first Hessian term couples a vertex's whole patch (the Newton matrix's pattern is the tet
// graph's square, solver/nodal_hessian.h).
#pragma once

#include "fem/elastic_mesh.h"

// The volume term U(J) of a nodal material and its stiffness k (the model's volume coefficient):
typedef enum fmNodalLaw
{
	fm_nodalLinear,    // linear: lambda/2 (J - 1)^2 on the linearised J = 1 + tr(F - I)
	fm_nodalLog,       // neohookean, mooney-rivlin: k/2 l(J)^2, l the clamped log
	fm_nodalQuadratic, // neohookean-isochoric: kappa/2 (J - 1)^2
} fmNodalLaw;

// Make the mesh's nodal data from its materials (tetParts, patchVolume, patchBulk, nodalLaw,
// and the step's scratch: the calls below allocate nothing and run one at a time on a mesh),
// or free it when no material has nodalPressure. Fails (mesh unchanged) with fm_errParameter
// when the nodal materials' volume laws differ, fm_errOutOfMemory without memory.
fmResult fmNodalPressure_Prepare(fmElasticMesh* mesh, fmDiagnostic* diag);

// The nodal data made again from the materials as they are now, in place: after a material
// changed with its nodalPressure flag kept (a snapshot's restore). Nothing without nodal data.
void fmNodalPressure_Refresh(fmElasticMesh* mesh);

// Free the mesh's nodal data (none: nothing).
void fmNodalPressure_Free(fmElasticMesh* mesh);

// Whether the mesh has a nodal volume term.
static inline bool fmNodalPressure_On(const fmElasticMesh* mesh)
{
	return mesh->tetParts != NULL;
}

// Whether tet @p t puts its volume term on its vertices.
bool fmNodalPressure_TetIsNodal(const fmElasticMesh* mesh, int t);

// The patches' state at @p x: the nodal pressures p (vertexCount) and, when @p curvature is not
// NULL, c_a (vertexCount). Returns the nodal energy sum_a W_a U(J_a) (J).
double fmNodalPressure_State(const fmElasticMesh* mesh, const double* x, double* pressure,
                             double* curvature);

// The nodal energy at @p x with its forces -dE/dx added to @p f (when not NULL): serial, in tet
// order (the same bits for any worker count). Returns the energy (J).
double fmNodalPressure_AddForces(const fmElasticMesh* mesh, const double* x, double* f);

// dS_a/dx_b's share from tet @p t at @p x: grad[b] = V_t / 4 dJ_t/dx_b for its four nodes b.
void fmNodalPressure_TetGradients(const fmElasticMesh* mesh, const double* x, int t,
                                  fmVec3 grad[4]);

// The tet's 12x12 term V_t p d2J_t/dx2 at pressure @p p (its nodes' mean), exact (the projected
// Hessian leaves it out; zero for the linear law, whose J is linear in x, and not asked for),
// into @p K (row-major, node-major: 3 a + i).
void fmNodalPressure_TetHessian(const fmElasticMesh* mesh, const double* x, int t, double p,
                                double* K);

// The pressure @p pressure's mean over tet @p t's nodes.
double fmNodalPressure_TetMean(const fmElasticMesh* mesh, const double* pressure, int t);

// The most vertices a patch can have (4 times the most tets around a vertex): the size of the
// scratch fmNodalPressure_Patch writes.
int fmNodalPressure_MaxPatch(const fmElasticMesh* mesh);

// Vertex @p a's patch gradient s_a = dS_a/dx at @p x: its vertices and their 3-vectors, in the
// order the tets around a first reach them. Returns how many.
int fmNodalPressure_Patch(const fmElasticMesh* mesh, const double* x, int a, int* vertices,
                          fmVec3* grads);

// The absolute row sums of the nodal term's Hessian at @p x added to @p rowSum (3 per vertex),
// for the explicit stability limit's Gershgorin bound.
void fmNodalPressure_AddRowSums(const fmElasticMesh* mesh, const double* x, double* rowSum);

// A 3x3 block (row-major) of the nodal term's Hessian at (vertex @p row, vertex @p column).
typedef void fmNodalBlockFcn(void* context, int row, int column, const double block[9]);

// Every block of the nodal term's Hessian at @p x (made PSD when @p project: the patches'
// curvatures clamped at 0, the tets' pressure terms left out), handed to @p visit in
// a fixed order (the patches by vertex, then the tets); a block pair may come several times and
// is summed.
void fmNodalPressure_VisitHessian(const fmElasticMesh* mesh, const double* x, int project,
                                  fmNodalBlockFcn* visit, void* context);

// out += H dx, H the nodal term's Hessian (fmNodalPressure_VisitHessian).
void fmNodalPressure_AddProduct(const fmElasticMesh* mesh, const double* x, const double* dx,
                                double* out, int project);

// Its diagonal blocks added to @p blocks (9 per vertex).
void fmNodalPressure_AddDiagonal(const fmElasticMesh* mesh, const double* x, double* blocks,
                                 int project);
