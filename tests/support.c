#include "support.h"

#include "core/core.h"
#include "test.h"

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

fmWorldDef fmTestFreeWorldDef(void)
{
	fmWorldDef def = fmDefaultWorldDef();
	def.gravity = fmMakeVec3(0, 0, 0);
	def.floor.enabled = false;
	return def;
}

bool fmTestHouseMesh(fmTetMesh* mesh, fmVec3 offset)
{
	if (fmLoadTetGen(FEMTO_MESH_DIR "/house2.node", FEMTO_MESH_DIR "/house2.ele", mesh, NULL) !=
	    fm_ok)
		return false;
	fmMeshTransform placement = fmDefaultMeshTransform();
	placement.scale = 0.4;
	placement.center = true;
	placement.swapYZ = true;
	placement.translate = offset;
	fmTetMesh_Transform(mesh, &placement);
	return true;
}

fmBodyId fmTestMakeHouse(fmWorldId* world, const fmWorldDef* worldDef, const fmBodyDef* bodyDef)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (!fmTestHouseMesh(&mesh, fmMakeVec3(0.0, 0.0, 0.0)))
		return none;
	fmWorldDef wdef = worldDef ? *worldDef : fmDefaultWorldDef();
	*world = fmCreateWorld(&wdef);
	fmBodyDef bdef = bodyDef ? *bodyDef : fmDefaultBodyDef();
	bdef.mesh = &mesh;
	fmBodyId body;
	fmResult r = fmCreateBody(*world, &bdef, &body, NULL);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

fmBodyId fmTestMakeBox(fmWorldId* world, int nx, int ny, int nz, fmVec3 size, fmMaterial material,
                       fmForceModel forceModel)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (fmMakeBoxMesh(nx, ny, nz, fmMakeVec3(0, 0, 0), size, &mesh) != fm_ok)
		return none;
	fmWorldDef wdef = fmTestFreeWorldDef();
	*world = fmCreateWorld(&wdef);
	fmBodyDef bdef = fmDefaultBodyDef();
	bdef.mesh = &mesh;
	bdef.material = material;
	bdef.forceModel = forceModel;
	bdef.massMode = fm_massFromDensity;
	bdef.density = 1000.0;
	bdef.damping = 1.0;
	bdef.smoothing = 0.0;
	fmBodyId body;
	fmResult r = fmCreateBody(*world, &bdef, &body, NULL);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

fmMat3 fmTestRandomRotation(void)
{
	double q[4], n;
	do
	{
		n = 0.0;
		for (int k = 0; k < 4; ++k)
		{
			q[k] = fmTestRandom(-1, 1);
			n += q[k] * q[k];
		}
	} while (n < 1e-3 || n > 1.0);
	n = sqrt(n);
	double w = q[0] / n, x = q[1] / n, y = q[2] / n, z = q[3] / n;
	fmMat3 R = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
	             2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
	             2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
	return R;
}

static double fmTestEnergyAt(fmBodyId body, const double* x, double* work)
{
	fmBody_SetPositions(body, x);
	return fmBody_ComputeElasticForces(body, work);
}

void fmTestCheckForcesAreMinusGradient(int* failures_, fmBodyId body, int stride, double tolerance)
{
	int n3 = 3 * fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * (size_t)n3);
	double* f = malloc(sizeof(double) * (size_t)n3);
	double* work = malloc(sizeof(double) * (size_t)n3);
	fmBody_CopyPositions(body, x, n3 / 3);
	fmBody_ComputeElasticForces(body, f);
	double scale = 0.0;
	for (int k = 0; k < n3; ++k)
		scale = fmax(scale, fabs(f[k]));
	CHECK(scale > 0.0);
	const double h = 1e-6;
	for (int k = 0; k < n3; k += stride)
	{
		double saved = x[k];
		x[k] = saved + h;
		double ep = fmTestEnergyAt(body, x, work);
		x[k] = saved - h;
		double em = fmTestEnergyAt(body, x, work);
		x[k] = saved;
		CHECK_NEAR(f[k], -(ep - em) / (2 * h), tolerance * scale);
	}
	fmBody_SetPositions(body, x);
	free(x);
	free(f);
	free(work);
}

void fmTestPerturb(fmBodyId body, double amplitude)
{
	int n3 = 3 * fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * (size_t)n3);
	fmBody_CopyPositions(body, x, n3 / 3);
	for (int k = 0; k < n3; ++k)
		x[k] += fmTestRandom(-amplitude, amplitude);
	fmBody_SetPositions(body, x);
	free(x);
}

void fmTestBarOnRollers(fmBodyId body, const double* rest, double length, double stretch, bool hold)
{
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_CopyPositions(body, x, n);
	for (int i = 0; i < n; ++i)
	{
		unsigned axes = 0;
		for (int k = 0; k < 3; ++k)
			if (rest[3 * i + k] < 1e-9)
				axes |= 1u << k;
		if (hold && rest[3 * i] > length - 1e-9)
		{
			axes |= 1u;
			x[3 * i] = length * stretch;
		}
		fmBody_SetPinnedAxes(body, i, axes);
	}
	fmBody_SetPositions(body, x);
	free(x);
}

// A read-back buffer of the test support, grown as needed (kept until exit).
typedef struct fmTestBuffer
{
	double* values;
	int vertexCapacity;
} fmTestBuffer;

static const double* fmTestCopyState(fmTestBuffer* buffer, fmBodyId body, bool velocities)
{
	int n = fmBody_GetVertexCount(body);
	if (n > buffer->vertexCapacity)
	{
		free(buffer->values);
		buffer->values = malloc(sizeof(double) * 3 * (size_t)n);
		buffer->vertexCapacity = buffer->values ? n : 0;
	}
	fmResult r = velocities ? fmBody_CopyVelocities(body, buffer->values, buffer->vertexCapacity)
	                        : fmBody_CopyPositions(body, buffer->values, buffer->vertexCapacity);
	if (r != fm_ok)
	{
		fprintf(stderr, "test support: reading a body's state back failed: %s\n", fmResultName(r));
		exit(3);
	}
	return buffer->values;
}

const double* fmTestPositions(fmBodyId body)
{
	static fmTestBuffer s_positions;
	return fmTestCopyState(&s_positions, body, false);
}

const double* fmTestVelocities(fmBodyId body)
{
	static fmTestBuffer s_velocities;
	return fmTestCopyState(&s_velocities, body, true);
}

static int s_asserts;
static fmAssertFcn* s_previousAssert;

static int fmTestRecordAssert(const char* condition, const char* fileName, int lineNumber)
{
	(void)condition;
	(void)fileName;
	(void)lineNumber;
	++s_asserts;
	return 0;
}

void fmTestRecordAssertsBegin(void)
{
	s_previousAssert = fmGetAssertFcn();
	fmSetAssertFcn(fmTestRecordAssert);
	s_asserts = 0;
}

int fmTestAssertCount(void)
{
	return s_asserts;
}

int fmTestRecordAssertsEnd(void)
{
	fmSetAssertFcn(s_previousAssert);
	return s_asserts;
}

fmVec3 fmTestMomentum(fmBodyId body)
{
	const double* v = fmTestVelocities(body);
	const double* m = fmBody_GetMasses(body);
	fmVec3 p = fmMakeVec3(0.0, 0.0, 0.0);
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		p = fmMulAdd(p, m[i], fmLoad(v, i));
	return p;
}

double fmTestMass(fmBodyId body)
{
	const double* m = fmBody_GetMasses(body);
	double total = 0.0;
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		total += m[i];
	return total;
}
