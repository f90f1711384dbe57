// Contact (src/contact/contact.c, src/contact/collider.c, src/world/query.c): bodies rest on
// colliders and on each other without interpenetrating beyond the thickness, Coulomb friction on an
// incline follows g (sin a - mu cos a), fast bodies do not tunnel through thin colliders, kinematic
// colliders push and feel the push, resting contact gains no energy, rays hit the deformed surface,
// filtered pairs pass through each other, events begin and end, and the results are the same
// bits for any number of workers.
#include "support.h"
#include "test.h"

#include "body/body.h"
#include "contact/penalty.h"
#include "core/core.h"
#include "math/geometry.h"
#include "solver/solver_cache.h"
#include "world/world.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// The seeds' house (0.4 scale, centred, y up) moved by @p offset, into @p world.
static fmBodyId addHouse(int* failures_, fmWorldId world, fmVec3 offset, const fmBodyDef* def)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (!fmTestHouseMesh(&mesh, offset))
		return none;
	fmBodyDef bdef = def ? *def : fmDefaultBodyDef();
	bdef.mesh = &mesh;
	fmBodyId body;
	fmResult r = fmCreateBody(world, &bdef, &body, NULL);
	CHECK_INT(r, fm_ok);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

// A box body of cells^3 cubes spanning [lo, hi].
static fmBodyId addBox(int* failures_, fmWorldId world, int cells, fmVec3 lo, fmVec3 hi,
                       const fmBodyDef* def)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (fmMakeBoxMesh(cells, cells, cells, lo, hi, &mesh) != fm_ok)
		return none;
	fmBodyDef bdef = def ? *def : fmDefaultBodyDef();
	bdef.mesh = &mesh;
	fmBodyId body;
	fmResult r = fmCreateBody(world, &bdef, &body, NULL);
	CHECK_INT(r, fm_ok);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

// A Neo-Hookean body of Young's modulus @p youngs (Pa), nu = 0.3, 500 kg/m^3.
static fmBodyDef softDef(double youngs)
{
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fmMakeMaterial(fm_neoHookean, youngs, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 500.0;
	return def;
}

static fmBodyDef implicitHouseDef(void)
{
	return softDef(5e4);
}

// Whether point p lies inside tet abcd (barycentric coordinates all above -eps).
static bool insideTet(fmVec3 p, fmVec3 a, fmVec3 b, fmVec3 c, fmVec3 d)
{
	fmMat3 T = fmMat3FromColumns(fmSub(b, a), fmSub(c, a), fmSub(d, a)), inverse;
	if (!fmInverse(&T, &inverse))
		return false;
	fmVec3 l = fmMatVec(&inverse, fmSub(p, a));
	const double eps = -1e-9;
	return l.x > eps && l.y > eps && l.z > eps && l.x + l.y + l.z < 1.0 - eps;
}

// The diagonal of @p body's bounding box (m).
static double bodyDiagonal(fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	const double* x = fmTestPositions(body);
	fmVec3 lo = fmLoad(x, 0), hi = lo;
	for (int i = 0; i < n; ++i)
	{
		fmVec3 p = fmLoad(x, i);
		lo = fmMakeVec3(fmin(lo.x, p.x), fmin(lo.y, p.y), fmin(lo.z, p.z));
		hi = fmMakeVec3(fmax(hi.x, p.x), fmax(hi.y, p.y), fmax(hi.z, p.z));
	}
	return fmLength(fmSub(hi, lo));
}

// How far point @p p is from the surface of @p other (positions @p y).
static double surfaceDistance(fmVec3 p, fmBodyId other, const double* y)
{
	int triangles = 0;
	const int* surface = fmBody_GetSurface(other, &triangles);
	double closest = INFINITY;
	for (int t = 0; t < triangles; ++t)
	{
		fmVec3 a = fmLoad(y, surface[3 * t]), b = fmLoad(y, surface[3 * t + 1]),
		       c = fmLoad(y, surface[3 * t + 2]);
		double w[3];
		fmClosestOnTriangle(p, a, b, c, w);
		fmVec3 q = fmAdd(fmAdd(fmScale(w[0], a), fmScale(w[1], b)), fmScale(w[2], c));
		closest = fmin(closest, fmLength(fmSub(p, q)));
	}
	return closest;
}

// The deepest a surface vertex of any body in @p bodies is inside another's tets (m, 0 when
// none is), and in @p count how many are inside.
static double deepestInside(const fmBodyId* bodies, int bodyCount, int* count);

// Surface vertices of @p body inside a tet of @p other; @p deepest (may be NULL) gets the
// largest distance of one of them from @p other's surface.
static int verticesInsideDepth(fmBodyId body, fmBodyId other, double* deepest)
{
	int n = fmBody_GetVertexCount(body), m = fmBody_GetVertexCount(other);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	double* y = malloc(sizeof(double) * 3 * (size_t)m);
	fmBody_CopyPositions(body, x, n);
	fmBody_CopyPositions(other, y, m);
	int triangles = 0, inside = 0;
	const int* surface = fmBody_GetSurface(body, &triangles);
	const int* tets = fmBody_GetTets(other);
	char* seen = calloc((size_t)n, 1);
	for (int k = 0; k < 3 * triangles; ++k)
	{
		int i = surface[k];
		if (seen[i]++)
			continue;
		fmVec3 p = fmLoad(x, i);
		for (int t = 0; t < fmBody_GetTetCount(other); ++t)
			if (insideTet(p, fmLoad(y, tets[4 * t]), fmLoad(y, tets[4 * t + 1]),
			              fmLoad(y, tets[4 * t + 2]), fmLoad(y, tets[4 * t + 3])))
			{
				inside += 1;
				if (deepest)
					*deepest = fmax(*deepest, surfaceDistance(p, other, y));
				break;
			}
	}
	free(seen);
	free(x);
	free(y);
	return inside;
}

static int verticesInside(fmBodyId body, fmBodyId other)
{
	return verticesInsideDepth(body, other, NULL);
}

static double deepestInside(const fmBodyId* bodies, int bodyCount, int* count)
{
	double deepest = 0.0;
	*count = 0;
	for (int a = 0; a < bodyCount; ++a)
		for (int b = 0; b < bodyCount; ++b)
			*count += a != b ? verticesInsideDepth(bodies[a], bodies[b], &deepest) : 0;
	return deepest;
}

// Three soft boxes dropped on each other come to rest stacked, in both integrators: every
// frame passes the health checks, no surface vertex of a box is inside another's tets, nothing
// is below the floor.
TEST(three_boxes_stack)
{
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = integrators[k];
		wdef.floor.height = 0.0;
		wdef.floor.friction = fm_floorCoulomb;
		wdef.floor.frictionCoefficient = 0.5;
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = softDef(1e5);
		fmBodyId boxes[3];
		for (int h = 0; h < 3; ++h)
			boxes[h] = addBox(failures_, world, 3, fmMakeVec3(-0.3, 0.1 + 0.8 * h, -0.3),
			                  fmMakeVec3(0.3, 0.7 + 0.8 * h, 0.3), &def);
		double frame = 1.0 / 60.0;
		int substeps = integrators[k] == fm_implicit ? 1 : 20, failed = 0;
		for (int f = 0; f < 120; ++f)
			failed += fmWorld_Step(world, frame, substeps) != fm_ok;
		int inside = 0;
		double lowest = INFINITY, y[3];
		for (int a = 0; a < 3; ++a)
		{
			lowest = fmin(lowest, fmBody_GetStats(boxes[a]).lowestY);
			y[a] = fmBody_GetStats(boxes[a]).centerOfMass.y;
			for (int b = 0; b < 3; ++b)
				inside += a != b ? verticesInside(boxes[a], boxes[b]) : 0;
		}
		printf("  %s: %d failed frames, %d surface vertices inside another box, lowest y %.4f, "
		       "centres at y %.3f %.3f %.3f\n",
		       integrators[k] == fm_implicit ? "implicit" : "explicit", failed, inside, lowest,
		       y[0], y[1], y[2]);
		CHECK_INT(failed, 0);
		CHECK_INT(inside, 0);
		CHECK(lowest >= -1e-6);
		CHECK(y[2] > y[1] + 0.4 && y[1] > y[0] + 0.4); // stacked, not merged
		fmDestroyWorld(world);
	}
}

// A world of @p integrator with three houses of @p def above each other (offset sideways, so
// that the upper ones land on the roofs below and slide off them), the floor at -2.1 m.
static fmWorldId threeHouses(int* failures_, fmIntegrator integrator, const fmBodyDef* def,
                             fmBodyId houses[3])
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.floor.height = -2.1;
	fmWorldId world = fmCreateWorld(&wdef);
	for (int h = 0; h < 3; ++h)
		houses[h] = addHouse(failures_, world, fmMakeVec3(0.3 * h, 4.3 * h, 0.0), def);
	return world;
}

// Three houses (the seeds' mesh, Neo-Hookean at E = 50 kPa, 500 kg/m^3) dropped on each other,
// 5 s in both integrators (implicit at 1/60 s, explicit at 30 substeps): no frame refused,
// nothing below the floor, everything finite, no surface vertex deeper inside another house than
// the thickness. (The seeds' own StVK houses: the next test.)
TEST(three_houses_dropped_on_each_other)
{
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	for (int k = 0; k < 2; ++k)
	{
		fmBodyDef def = implicitHouseDef();
		fmBodyId houses[3];
		fmWorldId world = threeHouses(failures_, integrators[k], &def, houses);
		// The default thickness: 1% of the smallest body's rest bounding-box diagonal.
		double thickness = 0.01 * bodyDiagonal(houses[0]);
		// 5 s; 1.5 s with FEMTO_TEST_QUICK (under the sanitizers): all three have landed by then.
		int failed = 0, frames = fmTestCount(300, 90);
		for (int f = 0; f < frames; ++f)
			failed += fmWorld_Step(world, 1.0 / 60.0, k == 0 ? 1 : 30) != fm_ok;
		int inside = 0;
		double lowest = INFINITY;
		bool finite = true;
		for (int a = 0; a < 3; ++a)
		{
			fmBodyStats stats = fmBody_GetStats(houses[a]);
			lowest = fmin(lowest, stats.lowestY);
			finite = finite && isfinite(stats.kineticEnergy) && isfinite(stats.centerOfMass.y);
		}
		double deepest = deepestInside(houses, 3, &inside);
		printf("  %s: %d refused frames, %d surface vertices inside another house, the deepest "
		       "%.4f m (thickness %.4f), lowest y %.4f (floor -2.1)\n",
		       k == 0 ? "implicit" : "explicit", failed, inside, deepest, thickness, lowest);
		CHECK_INT(failed, 0);
		CHECK(lowest >= -2.1 - 1e-9);
		CHECK(finite);
		CHECK(deepest <= thickness);
		fmDestroyWorld(world);
	}
}

// The seeds' own houses (StVK, their Lame constants, 1 kg a vertex) dropped on each other as
// above (they land on the roofs below and slide off), both integrators: with StVK's volume floor
// (material.h) no tet is inside out at any frame's end (before it: 254 of the bottom house's 1389
// by 1.5 s), no frame refused, nothing below the floor.
TEST(three_houses_of_the_seeds_carry_each_other)
{
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	for (int k = 0; k < 2; ++k)
	{
		fmBodyDef def = fmDefaultBodyDef();
		fmBodyId houses[3];
		fmWorldId world = threeHouses(failures_, integrators[k], &def, houses);
		int failed = 0, inverted = 0, frames = fmTestCount(300, 90);
		double lowest = INFINITY;
		for (int f = 0; f < frames; ++f)
		{
			failed += fmWorld_Step(world, 1.0 / 60.0, k == 0 ? 1 : 30) != fm_ok;
			for (int a = 0; a < 3; ++a)
			{
				fmBodyStats stats = fmBody_GetStats(houses[a]);
				inverted = stats.invertedTets > inverted ? stats.invertedTets : inverted;
				lowest = fmin(lowest, stats.lowestY);
			}
		}
		printf("  %s: %d refused frames, at most %d inverted tets in a house at a frame's end, "
		       "lowest y %.4f (floor -2.1), centres at y %.2f %.2f %.2f\n",
		       k == 0 ? "implicit" : "explicit", failed, inverted, lowest,
		       fmBody_GetStats(houses[0]).centerOfMass.y, fmBody_GetStats(houses[1]).centerOfMass.y,
		       fmBody_GetStats(houses[2]).centerOfMass.y);
		CHECK_INT(failed, 0);
		CHECK_INT(inverted, 0);
		CHECK(lowest >= -2.1 - 1e-9);
		fmDestroyWorld(world);
	}
}

// A box of one cell turned 45 degrees about @p axis (0: x, 2: z), centred at @p centre.
static fmBodyId addTurnedCube(int* failures_, fmWorldId world, int axis, fmVec3 centre,
                              const fmBodyDef* def)
{
	fmBodyId none = {0, 0, 0, 0};
	fmTetMesh mesh;
	if (fmMakeBoxMesh(1, 1, 1, fmMakeVec3(-0.2, -0.2, -0.2), fmMakeVec3(0.2, 0.2, 0.2), &mesh) !=
	    fm_ok)
		return none;
	const double c = sqrt(0.5);
	for (int i = 0; i < mesh.nodeCount; ++i)
	{
		double* p = mesh.positions + 3 * i;
		double u = axis == 0 ? p[1] : p[0], v = axis == 0 ? p[2] : p[1];
		double ru = c * u - c * v, rv = c * u + c * v;
		if (axis == 0)
			p[1] = ru, p[2] = rv;
		else
			p[0] = ru, p[1] = rv;
		p[0] += centre.x, p[1] += centre.y, p[2] += centre.z;
	}
	fmBodyDef bdef = *def;
	bdef.mesh = &mesh;
	fmBodyId body;
	fmResult r = fmCreateBody(world, &bdef, &body, NULL);
	CHECK_INT(r, fm_ok);
	fmFreeTetMesh(&mesh);
	return r == fm_ok ? body : none;
}

// Edge against edge: a cube of one cell standing on an edge along x is dropped crosswise onto a
// pinned cube whose top edge runs along z. Their vertices never come near each other's faces
// while the edges cross, so only the edge test holds them: explicit substeps (projection) and
// implicit steps at 1/60 s (frozen edge planes in the solve) keep the upper cube's edge above
// the lower one's (within the thickness) while it is over it. Without edges, it sinks 0.19 m.
TEST(crossed_edges_do_not_pass)
{
	const fmIntegrator integrators[2] = {fm_explicit, fm_implicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.floor.enabled = false;
		wdef.integrator = integrators[k];
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = softDef(1e6);
		fmBodyId low = addTurnedCube(failures_, world, 2, fmMakeVec3(0.0, 0.0, 0.0), &def);
		fmBodyId high = addTurnedCube(failures_, world, 0, fmMakeVec3(0.0, 0.62, 0.0), &def);
		CHECK(fmBody_PinBox(low, fmMakeVec3(-1.0, -1.0, -1.0), fmMakeVec3(1.0, 0.0, 1.0)) > 0);
		double worst = INFINITY;
		int over = 0;
		for (int f = 0; f < 60; ++f)
		{
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, k == 0 ? 40 : 1), fm_ok);
			fmBodyStats a = fmBody_GetStats(high), b = fmBody_GetStats(low);
			const double* x = fmTestPositions(low);
			double top = -INFINITY;
			for (int i = 0; i < fmBody_GetVertexCount(low); ++i)
				top = fmax(top, x[3 * i + 1]);
			if (fabs(a.centerOfMass.x - b.centerOfMass.x) < 0.1 &&
			    fabs(a.centerOfMass.z - b.centerOfMass.z) < 0.1)
			{
				over += 1;
				worst = fmin(worst, a.lowestY - top);
			}
		}
		double thickness = 0.01 * sqrt(3.0) * 0.4;
		printf("  %s: %d frames over the lower cube, its edge at least %.4f m above the lower "
		       "edge (thickness %.4f)\n",
		       k == 0 ? "explicit" : "implicit", over, worst, thickness);
		CHECK(over > 20);
		CHECK(worst > -thickness);
		fmDestroyWorld(world);
	}
}

static void countPoints(const float* points, int count, float size, fmHexColor color, void* context)
{
	(void)points, (void)size, (void)color;
	*(int*)context += count;
}

// A house dropped on a large static sphere (radius 8 m, its top 1 m above the floor) comes to
// rest on it: no vertex inside the sphere, and the sphere carries the house's weight.
TEST(house_rests_on_a_sphere)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderDef sphere = fmDefaultColliderDef();
	sphere.shape = fm_shapeSphere;
	sphere.center = fmMakeVec3(0.0, -10.0, 0.0);
	sphere.radius = 8.0;
	sphere.friction = 0.8;
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(world, &sphere, &collider, NULL), fm_ok);
	fmBodyDef def = implicitHouseDef();
	fmBodyId house = addHouse(failures_, world, fmMakeVec3(0.0, 0.5, 0.0), &def);
	for (int f = 0; f < 300; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	int n = fmBody_GetVertexCount(house);
	const double* x = fmTestPositions(house);
	const double* masses = fmBody_GetMasses(house);
	double closest = INFINITY, weight = 0.0;
	for (int i = 0; i < n; ++i)
	{
		closest = fmin(closest, fmLength(fmSub(fmLoad(x, i), sphere.center)) - sphere.radius);
		weight += 9.8 * masses[i];
	}
	fmBodyStats stats = fmBody_GetStats(house);
	fmVec3 force;
	fmCollider_GetContactForce(collider, &force, NULL);
	printf("  closest vertex %.2e m from the sphere, lowest y %.4f, kinetic %.2e J; the sphere "
	       "carries %.0f N of the house's %.0f N\n",
	       closest, stats.lowestY, stats.kineticEnergy, -force.y, weight);
	CHECK(closest > -1e-6);
	CHECK(stats.lowestY > -3.0); // on the sphere, not the floor
	CHECK_REL(-force.y, weight, 0.1, 0.0);
	// The debug draw shows the contacts (none of them on the floor here).
	int contacts = fmWorld_GetContacts(world, NULL, 0), drawn = 0;
	fmDebugDraw draw = fmDefaultDebugDraw();
	draw.flags = fm_drawContacts;
	draw.drawPoints = countPoints;
	draw.context = &drawn;
	CHECK_INT(fmWorld_Draw(world, &draw), fm_ok);
	CHECK(contacts > 0);
	CHECK_INT(drawn, contacts);
	fmDestroyWorld(world);
}

// A stiff block on a plane inclined 30 degrees: it slides with friction 0.3 at
// g (sin 30 - 0.3 cos 30) = 2.354 m/s^2 and sticks with 0.7 (tan 30 = 0.577), both
// integrators (implicit: friction inside the solve, lagged one step: penalty.h).
TEST(friction_on_an_incline)
{
	const double angle = 30.0 * 3.14159265358979 / 180.0;
	const struct
	{
		double mu;
		fmIntegrator integrator;
	} cases[4] = {{0.3, fm_implicit}, {0.3, fm_explicit}, {0.7, fm_explicit}, {0.7, fm_implicit}};
	for (int k = 0; k < 4; ++k)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = cases[k].integrator;
		wdef.floor.enabled = false;
		// The incline is the plane y = 0; gravity is tilted instead (the same physics).
		wdef.gravity = fmMakeVec3(9.8 * sin(angle), -9.8 * cos(angle), 0.0);
		fmWorldId world = fmCreateWorld(&wdef);
		fmColliderDef plane = fmDefaultColliderDef();
		plane.friction = cases[k].mu;
		fmColliderId collider;
		CHECK_INT(fmCreateCollider(world, &plane, &collider, NULL), fm_ok);
		fmBodyDef def = fmDefaultBodyDef();
		def.material = fmMakeMaterial(fm_neoHookean, 1e7, 0.3);
		def.massMode = fm_massFromDensity;
		def.density = 1000.0;
		def.damping = 1.0;
		def.smoothing = 0.0;
		fmBodyId block = addBox(failures_, world, 2, fmMakeVec3(-0.1, 0.002, -0.1),
		                        fmMakeVec3(0.1, 0.202, 0.1), &def);
		int substeps = cases[k].integrator == fm_implicit ? 1 : 50;
		double x[3];
		for (int f = 0; f < 90; ++f)
		{
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, substeps), fm_ok);
			if (f % 15 == 14)
				x[f / 30] = fmBody_GetStats(block).centerOfMass.x;
		}
		double acceleration = (x[2] - 2.0 * x[1] + x[0]) / (0.5 * 0.5);
		double expected = 9.8 * (sin(angle) - cases[k].mu * cos(angle));
		printf("  mu %.1f, %s: slid %.4f m in 1 s, acceleration %.3f m/s^2 (Coulomb: %.3f)\n",
		       cases[k].mu, cases[k].integrator == fm_implicit ? "implicit" : "explicit",
		       x[2] - x[0], acceleration, fmax(expected, 0.0));
		// Sticking: no acceleration; the block creeps by at most a few centimetres a second
		// (explicit: vertex-level friction; implicit: the slip width of static friction).
		if (expected < 0.0)
			CHECK(fabs(acceleration) < 0.05 && fabs(x[2] - x[0]) < 0.05);
		else
			CHECK_REL(acceleration, expected, 0.05, 0.0);
		fmDestroyWorld(world);
	}
}

// What holds the incline's block: a plane collider under tilted gravity, the Coulomb floor under
// tilted gravity, a plane collider tilted in the world, another body (a pinned slab, tilted).
typedef enum inclineGround
{
	incline_collider,
	incline_floor,
	incline_tilted_collider,
	incline_body,
	incline_grounds
} inclineGround;

// Turn a mesh's points about z by @p angle.
static void turnAboutZ(fmTetMesh* mesh, double angle)
{
	for (int i = 0; i < mesh->nodeCount; ++i)
	{
		double* p = mesh->positions + 3 * i;
		double x = p[0], y = p[1];
		p[0] = cos(angle) * x - sin(angle) * y;
		p[1] = sin(angle) * x + cos(angle) * y;
	}
}

// A world of @p integrator with the 30 degree incline of @p ground at friction @p mu; returns
// the downhill direction.
static fmVec3 makeIncline(int* failures_, fmWorldId* world, fmIntegrator integrator,
                          inclineGround ground, double mu, double angle)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.floor.enabled = ground == incline_floor;
	wdef.floor.height = 0.0;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.floor.frictionCoefficient = mu;
	bool tilted = ground == incline_tilted_collider || ground == incline_body;
	wdef.gravity =
	    tilted ? fmMakeVec3(0.0, -9.8, 0.0) : fmMakeVec3(9.8 * sin(angle), -9.8 * cos(angle), 0.0);
	*world = fmCreateWorld(&wdef);
	fmColliderDef plane = fmDefaultColliderDef();
	plane.friction = mu;
	plane.normal = tilted ? fmMakeVec3(-sin(angle), cos(angle), 0.0) : fmMakeVec3(0.0, 1.0, 0.0);
	fmColliderId collider;
	if (ground == incline_collider || ground == incline_tilted_collider)
		CHECK_INT(fmCreateCollider(*world, &plane, &collider, NULL), fm_ok);
	if (ground == incline_body)
	{
		fmTetMesh slab;
		CHECK_INT(
		    fmMakeBoxMesh(24, 1, 3, fmMakeVec3(-6.0, -0.2, -0.5), fmMakeVec3(1.0, 0.0, 0.5), &slab),
		    fm_ok);
		turnAboutZ(&slab, angle);
		fmBodyDef def = fmDefaultBodyDef();
		def.mesh = &slab;
		def.material = fmMakeMaterial(fm_neoHookean, 1e7, 0.3);
		def.friction = mu;
		fmBodyId body;
		CHECK_INT(fmCreateBody(*world, &def, &body, NULL), fm_ok);
		for (int i = 0; i < slab.nodeCount; ++i)
			fmBody_SetPinnedAxes(body, i, 7);
		fmFreeTetMesh(&slab);
	}
	return tilted ? fmMakeVec3(-cos(angle), -sin(angle), 0.0) : fmMakeVec3(1.0, 0.0, 0.0);
}

// A stiff 0.2 m block set on the incline (2 mm above it), friction @p mu.
static fmBodyId inclineBlock(int* failures_, fmWorldId world, fmIntegrator integrator,
                             inclineGround ground, double mu, double angle)
{
	fmTetMesh mesh;
	CHECK_INT(
	    fmMakeBoxMesh(2, 2, 2, fmMakeVec3(-0.1, 0.002, -0.1), fmMakeVec3(0.1, 0.202, 0.1), &mesh),
	    fm_ok);
	if (ground == incline_tilted_collider || ground == incline_body)
		turnAboutZ(&mesh, angle);
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = &mesh;
	def.material = fmMakeMaterial(fm_neoHookean, 1e7, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 1000.0;
	def.damping = 1.0;
	// Explicit: a little material damping (damping ratio beta omega / 2: 0.03 at 100 Hz, 0.3 at
	// 1 kHz): an undamped stiff block keeps ringing in explicit substeps, and its contacts ratchet
	// it down the slope (0.1 to 2.4 mm/s at 50 to 200 substeps, colliders too; docs/contact.md).
	// The implicit step dissipates the ringing itself.
	def.rayleighStiffness = integrator == fm_explicit ? 1e-4 : 0.0;
	def.smoothing = 0.0;
	def.friction = mu;
	fmBodyId block;
	CHECK_INT(fmCreateBody(world, &def, &block, NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	return block;
}

// Issue 29's friction that holds, on a 30 degree incline against a plane collider, the Coulomb
// floor, a tilted collider and another body: with mu = 0.7 (tan 30 = 0.577) the block's mean
// speed from 2.5 s to 10.5 s is under 0.1 mm/s (implicit: the spring of static friction is
// anchored where the contact first held, FM_FRICTION_STRIDE; explicit: the slip friction takes
// back leaves the positions too, fmContactResponse_CreepStep, for a vertex against a collider,
// a triangle or an edge of another body); with mu = 0.3 it slides at Coulomb's
// g (sin 30 - 0.3 cos 30) = 2.354 m/s^2 within 1%.
TEST(static_friction_holds_and_sliding_is_coulombs)
{
	const double angle = 30.0 * 3.14159265358979 / 180.0;
	static const char* const names[incline_grounds] = {"plane collider", "Coulomb floor",
	                                                   "tilted collider", "pinned body"};
	for (int run = 0; run < 2 * incline_grounds; ++run)
	{
		fmIntegrator integrator = run < incline_grounds ? fm_implicit : fm_explicit;
		int ground = run % incline_grounds, substeps = integrator == fm_implicit ? 1 : 100;
		for (int sliding = 0; sliding < 2; ++sliding)
		{
			double mu = sliding ? 0.3 : 0.7;
			fmWorldId world;
			fmVec3 downhill =
			    makeIncline(failures_, &world, integrator, (inclineGround)ground, mu, angle);
			fmBodyId block =
			    inclineBlock(failures_, world, integrator, (inclineGround)ground, mu, angle);
			// Sticking: 2.5 s to 10.5 s (2.5 s to 3.5 s under the sanitizers, FEMTO_TEST_QUICK).
			const int frames = sliding ? 90 : fmTestCount(631, 211);
			double s[3] = {0.0, 0.0, 0.0}, at150 = 0.0;
			int failed = 0;
			for (int f = 0; f < frames; ++f)
			{
				failed += fmWorld_Step(world, 1.0 / 60.0, substeps) != fm_ok;
				double along = fmDot(fmBody_GetStats(block).centerOfMass, downhill);
				if (f < 90 && f % 30 == 29)
					s[f / 30] = along; // 0.5, 1 and 1.5 s
				at150 = f == 150 ? along : at150;
				s[2] = f == frames - 1 && !sliding ? along : s[2];
			}
			CHECK_INT(failed, 0);
			if (sliding)
			{
				double acceleration = (s[2] - 2.0 * s[1] + s[0]) / 0.25;
				double expected = 9.8 * (sin(angle) - mu * cos(angle));
				printf("  %s, %s, mu 0.3: %.4f m/s^2 (Coulomb %.4f, %+.2f%%)\n", names[ground],
				       integrator == fm_implicit ? "implicit" : "explicit", acceleration, expected,
				       100.0 * (acceleration - expected) / expected);
				CHECK_REL(acceleration, expected, 0.01, 0.0);
			}
			else
			{
				double speed = (s[2] - at150) / ((frames - 1 - 150) / 60.0);
				printf("  %s, %s, mu 0.7: mean speed %.2e mm/s from 2.5 s to %.1f s\n",
				       names[ground], integrator == fm_implicit ? "implicit" : "explicit",
				       1e3 * speed, (frames - 1) / 60.0);
				CHECK(fabs(speed) < 1e-4);
			}
			fmDestroyWorld(world);
		}
	}
}

// A body at 10 m/s against a 1 cm thick static box, one implicit step a frame (17 cm a step):
// it stops on its side.
TEST(no_tunnelling_through_a_thin_collider)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.enabled = false;
	wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderDef wall = fmDefaultColliderDef();
	wall.shape = fm_shapeBox;
	wall.center = fmMakeVec3(0.5, 0.0, 0.0);
	wall.halfExtents = fmMakeVec3(0.005, 1.0, 1.0);
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(world, &wall, &collider, NULL), fm_ok);
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 1000.0;
	fmBodyId body =
	    addBox(failures_, world, 3, fmMakeVec3(-0.2, -0.1, -0.1), fmMakeVec3(0.0, 0.1, 0.1), &def);
	int n = fmBody_GetVertexCount(body);
	double* v = calloc(3 * (size_t)n, sizeof(double));
	for (int i = 0; i < n; ++i)
		v[3 * i] = 10.0;
	fmBody_SetVelocities(body, v);
	free(v);
	for (int f = 0; f < 30; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	const double* x = fmTestPositions(body);
	double farthest = -INFINITY;
	for (int i = 0; i < n; ++i)
		farthest = fmax(farthest, x[3 * i]);
	printf("  farthest vertex at x = %.4f (the wall's near face at 0.495)\n", farthest);
	CHECK(farthest < 0.495 + 1e-9);
	fmDestroyWorld(world);
}

static void xRange(fmBodyId body, double* lo, double* hi)
{
	int n = fmBody_GetVertexCount(body);
	const double* x = fmTestPositions(body);
	*lo = INFINITY;
	*hi = -INFINITY;
	for (int i = 0; i < n; ++i)
	{
		*lo = fmin(*lo, x[3 * i]);
		*hi = fmax(*hi, x[3 * i]);
	}
}

// Two plates 2 cm thick meeting at 20 m/s each (explicit, substeps from the stability limit):
// in no frame do they overlap, and they come apart. (The implicit integrator does not pass this
// yet: the plates cross within the first 1/60 s step; docs/contact.md.)
static void thinPlatesMeet(int* failures_, fmIntegrator integrator, int substeps, int frames)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.enabled = false;
	wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
	wdef.autoSubstep = true;
	wdef.integrator = integrator;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fmMakeMaterial(fm_neoHookean, 1e7, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 1000.0;
	fmBodyId plates[2];
	for (int k = 0; k < 2; ++k)
	{
		double x0 = k ? 0.05 : -0.07;
		fmTetMesh mesh;
		CHECK_INT(fmMakeBoxMesh(1, 6, 6, fmMakeVec3(x0, -0.3, -0.3),
		                        fmMakeVec3(x0 + 0.02, 0.3, 0.3), &mesh),
		          fm_ok);
		def.mesh = &mesh;
		CHECK_INT(fmCreateBody(world, &def, &plates[k], NULL), fm_ok);
		fmFreeTetMesh(&mesh);
		int n = fmBody_GetVertexCount(plates[k]);
		double* v = calloc(3 * (size_t)n, sizeof(double));
		for (int i = 0; i < n; ++i)
			v[3 * i] = k ? -20.0 : 20.0;
		fmBody_SetVelocities(plates[k], v);
		free(v);
	}
	double closest = INFINITY, lo0, hi0, lo1, hi1;
	int mostSteps = 0;
	for (int f = 0; f < frames; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, substeps), fm_ok);
		xRange(plates[0], &lo0, &hi0);
		xRange(plates[1], &lo1, &hi1);
		closest = fmin(closest, lo1 - hi0);
		int steps = fmWorld_GetStepStats(world).steps;
		mostSteps = steps > mostSteps ? steps : mostSteps;
	}
	printf("  %s, %d substeps: closest approach of the faces %.4f m (thickness %.4f); after %d "
	       "frames the plates' centres at x = %.3f and %.3f; at most %d substeps a frame\n",
	       integrator == fm_implicit ? "implicit" : "explicit", substeps, closest,
	       0.01 * sqrt(0.02 * 0.02 + 0.6 * 0.6 * 2.0), frames, 0.5 * (lo0 + hi0), 0.5 * (lo1 + hi1),
	       mostSteps);
	CHECK(closest > 0.0);
	// Explicit: apart again after 1/3 s. Implicit: backward Euler at 1/60 s damps the plates'
	// rebound away (their elastic period is far shorter than the step): they stop, face to face,
	// in their order.
	if (integrator == fm_explicit)
		CHECK(frames < 20 || (hi0 < -0.5 && lo1 > 0.5));
	else
		CHECK(lo0 + hi0 < lo1 + hi1);
	fmDestroyWorld(world);
}

TEST(thin_plates_meeting_fast_do_not_cross)
{
	thinPlatesMeet(failures_, fm_explicit, 1, 20);
	thinPlatesMeet(failures_, fm_implicit, 1, 20); // the step cut into pieces at the impact
	// Steps the explicit integrator could take: the projection alone (no frozen planes).
	thinPlatesMeet(failures_, fm_implicit, 600, 3);
}

// A kinematic paddle swept through a resting body pushes it along and feels it.
// A kinematic box collider 0.4 m thick moving at 10, 1,000 and 3,000 m/s at a free 1 m box: a
// collider that moves more than its thickness in a substep can pass over the body's vertices
// between two substeps (3,000 m/s, implicit: the box goes through untouched), and the step says
// so in its warning, with the substeps that would do; a failure in such a frame (1,000 m/s,
// explicit) names it as the likely cause. At 10 m/s, nothing is said. (Before, all of these
// were silent, or "try a smaller dt" though substeps were automatic.)
static bool fastColliderRun(int* failures_, double speed, fmIntegrator integrator, int substeps,
                            int* refused, fmDiagnostic* said)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef(); // 1 kg a vertex
	def.material = fmMakeMaterial(fm_neoHookean, 1e5, 0.3);
	addBox(failures_, world, 4, fmMakeVec3(-0.5, -0.5, -0.5), fmMakeVec3(0.5, 0.5, 0.5), &def);
	fmColliderDef c = fmDefaultColliderDef();
	c.shape = fm_shapeBox;
	c.center = fmMakeVec3(-2.0, 0.0, 0.0);
	c.halfExtents = fmMakeVec3(0.2, 0.3, 0.3);
	c.velocity = fmMakeVec3(speed, 0.0, 0.0);
	fmColliderId id;
	CHECK_INT(fmCreateCollider(world, &c, &id, NULL), fm_ok);
	*refused = 0;
	bool any = false;
	for (int f = 0; f < 2; ++f)
	{
		fmResult r = fmWorld_Step(world, 1.0 / 60.0, substeps);
		*refused += r != fm_ok;
		const fmDiagnostic* e = fmWorld_GetLastError(world);
		if ((!any && e->warningCount > 0) || (r != fm_ok && *refused == 1))
			*said = *e; // the first warning, or the first refusal
		any = any || r != fm_ok || e->warningCount > 0;
	}
	fmDestroyWorld(world);
	return any;
}

TEST(a_collider_faster_than_its_thickness_is_reported)
{
	int refused;
	fmDiagnostic e;
	CHECK(!fastColliderRun(failures_, 10.0, fm_implicit, 1, &refused, &e));
	CHECK(fastColliderRun(failures_, 3000.0, fm_implicit, 1, &refused, &e));
	printf("  3000 m/s, implicit: %s\n", e.warning);
	CHECK_STR_CONTAINS(e.warning, "moves 50 m in a substep of 0.0167 s, more than its 0.4 m "
	                              "thickness: bodies in its way can pass through it unhit");
	CHECK_STR_CONTAINS(e.warning, "take 125 substeps a frame");
	CHECK(fastColliderRun(failures_, 1000.0, fm_explicit, 20, &refused, &e));
	CHECK(refused > 0);
	printf("  1000 m/s, explicit: %s\n", e.message);
	CHECK_STR_CONTAINS(e.message, "the likely cause: the collider in slot 0 moves 0.833 m in a "
	                              "substep, more than its 0.4 m thickness");
}

TEST(kinematic_paddle_pushes)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.height = 0.0;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.floor.frictionCoefficient = 0.3;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	fmBodyId body =
	    addBox(failures_, world, 3, fmMakeVec3(0.0, 0.0, -0.15), fmMakeVec3(0.3, 0.3, 0.15), &def);
	fmColliderDef paddle = fmDefaultColliderDef();
	paddle.shape = fm_shapeBox;
	paddle.center = fmMakeVec3(-0.3, 0.25, 0.0); // from 0.05 m above the floor up
	paddle.halfExtents = fmMakeVec3(0.02, 0.2, 0.3);
	paddle.velocity = fmMakeVec3(1.0, 0.0, 0.0);
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(world, &paddle, &collider, NULL), fm_ok);
	double pushMax = 0.0;
	for (int f = 0; f < 60; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		fmVec3 force;
		fmCollider_GetContactForce(collider, &force, NULL);
		pushMax = fmax(pushMax, -force.x);
	}
	fmBodyStats stats = fmBody_GetStats(body);
	double paddleX = fmCollider_GetPosition(collider).x;
	const double* x = fmTestPositions(body);
	double back = INFINITY; // of the vertices the paddle reaches
	for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
		if (x[3 * i + 1] > 0.06)
			back = fmin(back, x[3 * i]);
	printf("  paddle at x %.3f, the body's back face at %.3f, centre %.3f; largest push %.1f N\n",
	       paddleX, back, stats.centerOfMass.x, pushMax);
	CHECK(back > paddleX + 0.02 - 1e-6); // never passed
	CHECK(stats.centerOfMass.x > 0.4);   // pushed along (it started at 0.15)
	CHECK(pushMax > 0.0);                // the paddle felt the body
	fmDestroyWorld(world);
}

// Resting contact on a plane collider, undamped, over 10 s: the energy (kinetic, elastic and
// gravity's potential) never rises by more than 0.5% of the body's weight times its size.
TEST(resting_contact_gains_no_energy)
{
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = integrators[k];
		wdef.floor.enabled = false;
		fmWorldId world = fmCreateWorld(&wdef);
		fmColliderDef plane = fmDefaultColliderDef();
		plane.offset = -1.0;
		fmColliderId collider;
		CHECK_INT(fmCreateCollider(world, &plane, &collider, NULL), fm_ok);
		fmBodyDef def = fmDefaultBodyDef();
		def.material = fmMakeMaterial(fm_stvk, 5e4, 0.3);
		def.massMode = fm_massFromDensity;
		def.density = 300.0;
		def.damping = 1.0;
		def.smoothing = 0.0;
		fmBodyId body = addBox(failures_, world, 3, fmMakeVec3(-0.2, -0.99, -0.2),
		                       fmMakeVec3(0.2, -0.59, 0.2), &def);
		double frame = 1.0 / 60.0;
		int substeps = integrators[k] == fm_implicit ? 1 : 20;
		double start = 0.0, highest = -INFINITY, weight = 0.0;
		const double* masses = fmBody_GetMasses(body);
		for (int i = 0; i < fmBody_GetVertexCount(body); ++i)
			weight += 9.8 * masses[i];
		for (int f = 0; f < 600; ++f)
		{
			CHECK_INT(fmWorld_Step(world, frame, substeps), fm_ok);
			fmBodyStats s = fmBody_GetStats(body);
			double energy = s.kineticEnergy + s.elasticEnergy + s.gravityEnergy;
			if (f == 30) // landed
				start = energy;
			if (f > 30)
				highest = fmax(highest, energy);
		}
		double allowed = 0.005 * weight * 0.4;
		printf("  %s: energy rose by at most %.3e J (allowed %.3e J)\n",
		       integrators[k] == fm_implicit ? "implicit" : "explicit", highest - start, allowed);
		CHECK(highest - start <= allowed);
		fmDestroyWorld(world);
	}
}

// A ray straight down onto a box body hits its top face where the geometry says, with an
// upward normal; rays that miss, and a filter that excludes the body, find nothing.
TEST(ray_cast_hits_the_deformed_surface)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.enabled = false;
	wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	fmBodyId body =
	    addBox(failures_, world, 2, fmMakeVec3(0.0, 0.0, 0.0), fmMakeVec3(1.0, 1.0, 1.0), &def);
	// Deform it: the top face raised by 0.25 m in the middle (a bulge).
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_CopyPositions(body, x, n);
	for (int i = 0; i < n; ++i)
		if (x[3 * i + 1] > 0.99 && fabs(x[3 * i] - 0.5) < 1e-9 && fabs(x[3 * i + 2] - 0.5) < 1e-9)
			x[3 * i + 1] += 0.25;
	fmBody_SetPositions(body, x);
	free(x);
	fmRayHit hit;
	bool found = fmWorld_CastRay(world, fmMakeVec3(0.5, 3.0, 0.5), fmMakeVec3(0.0, -4.0, 0.0),
	                             fmDefaultFilter(), &hit);
	CHECK(found);
	CHECK(fmBody_IsValid(hit.body));
	CHECK_NEAR(hit.point.y, 1.25, 1e-12);
	CHECK_NEAR(hit.fraction, (3.0 - 1.25) / 4.0, 1e-12);
	CHECK(hit.normal.y > 0.0);
	CHECK(hit.vertex >= 0 && hit.triangle >= 0);
	// Off the bulge's peak, on a sloped triangle: the height is linear between the peak and the
	// face's edge (the triangles of the 2x2x2 box's top face meet at its centre).
	found = fmWorld_CastRay(world, fmMakeVec3(0.75, 3.0, 0.5), fmMakeVec3(0.0, -4.0, 0.0),
	                        fmDefaultFilter(), &hit);
	CHECK(found);
	CHECK_NEAR(hit.point.y, 1.125, 1e-12);
	CHECK(!fmWorld_CastRay(world, fmMakeVec3(2.0, 3.0, 0.5), fmMakeVec3(0.0, -4.0, 0.0),
	                       fmDefaultFilter(), &hit));
	fmFilter none = {1u, 0u};
	CHECK(
	    !fmWorld_CastRay(world, fmMakeVec3(0.5, 3.0, 0.5), fmMakeVec3(0.0, -4.0, 0.0), none, &hit));
	// A collider in front of the body is hit first.
	fmColliderDef sphere = fmDefaultColliderDef();
	sphere.shape = fm_shapeSphere;
	sphere.center = fmMakeVec3(0.5, 2.0, 0.5);
	sphere.radius = 0.25;
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(world, &sphere, &collider, NULL), fm_ok);
	CHECK(fmWorld_CastRay(world, fmMakeVec3(0.5, 3.0, 0.5), fmMakeVec3(0.0, -4.0, 0.0),
	                      fmDefaultFilter(), &hit));
	CHECK(fmCollider_IsValid(hit.collider));
	CHECK_NEAR(hit.point.y, 2.25, 1e-6);
	fmDestroyWorld(world);
}

// Two bodies whose filters exclude each other pass through each other; with the default
// filters the same drop stacks them, and the pair's contact begins (an event) and ends when
// the top one is thrown off.
// Sphere overlaps: a box body is found when the sphere reaches its deformed surface or holds
// its centre inside it, with the nearest surface point and vertex; colliders by their distance;
// filters apply.
TEST(sphere_overlaps)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = fmDefaultBodyDef();
	def.filter.categoryBits = 2;
	fmBodyId box =
	    addBox(failures_, world, 2, fmMakeVec3(0.0, 0.0, 0.0), fmMakeVec3(1.0, 1.0, 1.0), &def);
	fmColliderDef sphere = fmDefaultColliderDef();
	sphere.shape = fm_shapeSphere;
	sphere.center = fmMakeVec3(3.0, 0.0, 0.0);
	sphere.radius = 0.5;
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(world, &sphere, &collider, NULL), fm_ok);
	fmOverlap found[4];
	fmFilter all = fmDefaultFilter();
	// 5 cm above the top face, over its centre vertex (0.5, 1, 0.5).
	fmVec3 above = fmMakeVec3(0.5, 1.05, 0.5);
	CHECK_INT(fmWorld_OverlapSphere(world, above, 0.04, all, found, 4), 0);
	CHECK_INT(fmWorld_OverlapSphere(world, above, 0.06, all, found, 4), 1);
	CHECK(found[0].body.index1 == box.index1 && found[0].collider.index1 == 0);
	CHECK_NEAR(found[0].distance, 0.05, 1e-12);
	CHECK_NEAR(found[0].point.y, 1.0, 1e-12);
	int vertex = found[0].vertex;
	const double* x = fmTestPositions(box);
	int internal = -1;
	for (int i = 0; i < fmBody_GetVertexCount(box); ++i)
		if (fmLength(fmSub(fmLoad(x, i), fmMakeVec3(0.5, 1.0, 0.5))) < 1e-12)
			internal = i;
	CHECK(internal >= 0 && vertex == internal); // the mesh's numbering is the user's here
	// Inside: distance 0, however small the sphere.
	CHECK_INT(fmWorld_OverlapSphere(world, fmMakeVec3(0.4, 0.5, 0.6), 1e-3, all, found, 4), 1);
	CHECK_NEAR(found[0].distance, 0.0, 0.0);
	// Both, counted beyond the capacity; the collider's nearest point is on the sphere.
	CHECK_INT(fmWorld_OverlapSphere(world, fmMakeVec3(2.0, 0.5, 0.5), 1.0, all, found, 1), 2);
	CHECK_INT(fmWorld_OverlapSphere(world, fmMakeVec3(2.0, 0.0, 0.0), 1.0, all, found, 4), 2);
	CHECK(found[1].collider.index1 == collider.index1 && found[1].vertex == -1);
	CHECK_NEAR(found[1].point.x, 2.5, 1e-12);
	CHECK_NEAR(found[1].distance, 0.5, 1e-12);
	// A filter that does not see category 2 finds only the collider.
	fmFilter noBodies = {1u, 1u};
	CHECK_INT(fmWorld_OverlapSphere(world, fmMakeVec3(2.0, 0.0, 0.0), 1.0, noBodies, found, 4), 1);
	CHECK(found[0].collider.index1 == collider.index1);
	fmDestroyWorld(world);
}

static int countSleepEvents(fmWorldId world, bool asleep, fmBodyId body)
{
	fmSleepEvent events[16];
	int n = fmWorld_GetSleepEvents(world, events, 16), count = 0;
	for (int k = 0; k < n && k < 16; ++k)
		count += events[k].asleep == asleep && events[k].body.index1 == body.index1;
	return count;
}

// An implicit world (1/60 s steps to come) with a Coulomb floor at y = 0 and two Neo-Hookean
// boxes of @p cells^3 cells (E = 100 kPa), a 0.4 m one held 0.1 m above a 0.6 m one.
static fmWorldId stackedBoxes(int* failures_, int cells, bool sleep, fmBodyId* low, fmBodyId* high)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.height = 0.0;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.contact.enableSleep = sleep;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	*low = addBox(failures_, world, cells, fmMakeVec3(-0.3, 0.05, -0.3), fmMakeVec3(0.3, 0.65, 0.3),
	              &def);
	*high = addBox(failures_, world, cells, fmMakeVec3(-0.2, 0.75, -0.2),
	               fmMakeVec3(0.2, 1.15, 0.2), &def);
	return world;
}

// Islands and sleeping: two boxes stacked on the floor fall asleep together (one island, in
// the same frame), stay bit-for-bit still while asleep, and wake together when a third box
// lands on them, which then rests on top instead of passing through; the API wakes too.
TEST(islands_sleep_and_wake)
{
	fmBodyId low, high;
	fmWorldId world = stackedBoxes(failures_, 3, true, &low, &high);
	int fellLow = -1, fellHigh = -1;
	for (int f = 0; f < 600 && (fellLow < 0 || fellHigh < 0); ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		if (fellLow < 0 && countSleepEvents(world, true, low))
			fellLow = f;
		if (fellHigh < 0 && countSleepEvents(world, true, high))
			fellHigh = f;
	}
	printf("  the stack fell asleep at frames %d and %d\n", fellLow, fellHigh);
	CHECK(fellLow > 30 && fellLow == fellHigh);
	fmContactEvent events[8];
	for (int f = 0; f < 30; ++f) // asleep, the pair has no end event
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		CHECK_INT(fmWorld_GetContactEvents(world, events, 8), 0);
	}
	CHECK(!fmBody_IsAwake(low) && !fmBody_IsAwake(high));
	int n = fmBody_GetVertexCount(high);
	double* before = malloc(sizeof(double) * 3 * (size_t)n);
	double* after = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_CopyPositions(high, before, n);
	for (int f = 0; f < 30; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	fmBody_CopyPositions(high, after, n);
	CHECK(memcmp(before, after, sizeof(double) * 3 * (size_t)n) == 0);
	// A third box lands on the sleeping stack.
	fmBodyDef def = softDef(1e5);
	fmBodyId top = addBox(failures_, world, 3, fmMakeVec3(-0.15, 1.4, -0.15),
	                      fmMakeVec3(0.15, 1.7, 0.15), &def);
	int wokeAt = -1;
	for (int f = 0; f < 120; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		if (wokeAt < 0 && countSleepEvents(world, false, low) &&
		    countSleepEvents(world, false, high))
			wokeAt = f;
	}
	int inside = verticesInside(top, high) + verticesInside(high, low);
	printf("  woken at frame %d after the third box was added; %d vertices inside another box, "
	       "top box's lowest point %.3f\n",
	       wokeAt, inside, fmBody_GetStats(top).lowestY);
	CHECK(wokeAt >= 0);
	CHECK_INT(inside, 0);
	CHECK(fmBody_GetStats(top).lowestY > 0.9); // on the stack (its top near 1.0 m)
	// The API: asleep on request, awake on an impulse.
	fmBody_SetAwake(top, false);
	CHECK(!fmBody_IsAwake(top) && !fmBody_IsAwake(low)); // its island went with it
	fmBody_ApplyImpulse(top, fmMakeVec3(0.0, 1.0, 0.0));
	CHECK(fmBody_IsAwake(top) && fmBody_IsAwake(low));
	free(before);
	free(after);
	fmDestroyWorld(world);
}

// Surface vertices of a body inside its own tets that were far from them in the rest shape
// (all four corners more than @p apart away): the body passing through itself.
static int selfPenetrations(fmBodyId body, const double* rest, double apart)
{
	int n = fmBody_GetVertexCount(body), m = fmBody_GetTetCount(body), triangles = 0, inside = 0;
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	fmBody_CopyPositions(body, x, n);
	const int* tets = fmBody_GetTets(body);
	const int* surface = fmBody_GetSurface(body, &triangles);
	char* seen = calloc((size_t)n, 1);
	for (int k = 0; k < 3 * triangles; ++k)
	{
		int i = surface[k];
		if (seen[i]++)
			continue;
		for (int t = 0; t < m; ++t)
		{
			const int* c = tets + 4 * t;
			bool far = true;
			for (int e = 0; e < 4; ++e)
				far = far && fmLength(fmSub(fmLoad(rest, c[e]), fmLoad(rest, i))) > apart;
			if (far && insideTet(fmLoad(x, i), fmLoad(x, c[0]), fmLoad(x, c[1]), fmLoad(x, c[2]),
			                     fmLoad(x, c[3])))
			{

				inside += 1;
				break;
			}
		}
	}
	free(seen);
	free(x);
	return inside;
}

// Self-collision: a beam 2 m long and 0.2 m thick, clamped from x = 0 to 0.8 m, has its free
// end dragged by kinematic targets over the top and back, turned over, to lie 8 cm over the
// clamped half (its centre line at y = 0.18, its lower face 2 cm into the clamped half's top).
// With self-collision the returning arm rests on the clamped one; without it, it sinks into it
// (which shows that the measure works).
TEST(self_collision_folds_a_beam)
{
	int inside[2] = {0, 0};
	double lowest[2] = {0.0, 0.0};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = fm_implicit;
		wdef.floor.enabled = false;
		wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = fmDefaultBodyDef();
		def.material = fmMakeMaterial(fm_neoHookean, 2e5, 0.3);
		def.massMode = fm_massFromDensity;
		def.density = 100.0;
		def.selfCollision = k == 0;
		fmTetMesh mesh;
		CHECK_INT(
		    fmMakeBoxMesh(20, 2, 2, fmMakeVec3(0.0, -0.1, -0.1), fmMakeVec3(2.0, 0.1, 0.1), &mesh),
		    fm_ok);
		def.mesh = &mesh;
		fmBodyId beam;
		CHECK_INT(fmCreateBody(world, &def, &beam, NULL), fm_ok);
		fmFreeTetMesh(&mesh);
		CHECK(fmBody_PinBox(beam, fmMakeVec3(-0.01, -1.0, -1.0), fmMakeVec3(0.81, 1.0, 1.0)) > 0);
		int ends[16], count = 0, n = fmBody_GetVertexCount(beam);
		double* rest = malloc(sizeof(double) * 3 * (size_t)n);
		fmBody_CopyPositions(beam, rest, n);
		for (int i = 0; i < n && count < 16; ++i)
			if (rest[3 * i] > 1.99)
				ends[count++] = i;
		CHECK_INT(count, 9);
		fmVec3 goal[16];
		const double pi = 3.14159265358979;
		for (int f = 0; f < 150; ++f)
		{
			// The end's centre turns about (0.9, 0.125) from (2, 0) to (0.1, 0.25) while the end
			// face turns over (1.5 s), then sinks by 7 cm (0.5 s) and is held.
			double t = fmin(f / 90.0, 1.0), down = fmin(fmax((f - 90) / 30.0, 0.0), 1.0);
			double a0 = atan2(-0.125, 1.1), a1 = atan2(0.125, -0.8);
			double r0 = sqrt(1.1 * 1.1 + 0.125 * 0.125), r1 = sqrt(0.8 * 0.8 + 0.125 * 0.125);
			double angle = a0 + t * (a1 - a0), radius = r0 + t * (r1 - r0);
			fmVec3 centre = fmMakeVec3(0.9 + radius * cos(angle),
			                           0.125 + radius * sin(angle) - 0.07 * down, 0.0);
			double c = cos(pi * t), sn = sin(pi * t);
			for (int e = 0; e < count; ++e)
			{
				fmVec3 offset = fmSub(fmLoad(rest, ends[e]), fmMakeVec3(2.0, 0.0, 0.0));
				goal[e] = fmAdd(centre, fmMakeVec3(offset.x * c - offset.y * sn,
				                                   offset.x * sn + offset.y * c, offset.z));
			}
			CHECK_INT(fmBody_SetTargets(beam, ends, goal, count, 2e3), fm_ok);
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		}
		inside[k] = selfPenetrations(beam, rest, 0.4);
		double* x = malloc(sizeof(double) * 3 * (size_t)n);
		fmBody_CopyPositions(beam, x, n);
		lowest[k] = INFINITY;
		for (int i = 0; i < n; ++i)
			if (rest[3 * i] > 1.5)
				lowest[k] = fmin(lowest[k], x[3 * i + 1]);
		free(x);
		free(rest);
		fmDestroyWorld(world);
	}
	printf("  with self-collision: %d surface vertices inside the beam's own far tets, the "
	       "returning end's lowest point at y = %.3f; without: %d, at y = %.3f\n",
	       inside[0], lowest[0], inside[1], lowest[1]);
	CHECK_INT(inside[0], 0);
	CHECK(lowest[0] > 0.1); // on the clamped half's top face (y = 0.1)
	CHECK(inside[1] > 0);   // without, it passes into itself
}

static int s_allocations;

static void* countingAlloc(size_t size, size_t alignment)
{
	s_allocations += 1;
	size_t rounded = (size + alignment - 1) / alignment * alignment;
	return aligned_alloc(alignment, rounded > 0 ? rounded : alignment);
}

static void countingFree(void* memory, size_t size)
{
	(void)size;
	free(memory);
}

// Once warmed up, contact steps allocate nothing: two boxes touching, a mesh collider, sleep
// and events on, both integrators (the buffers grow to the scene and stay).
TEST(warm_contact_steps_allocate_nothing)
{
	fmSetAllocator(countingAlloc, countingFree);
	const fmIntegrator integrators[2] = {fm_implicit, fm_explicit};
	int counts[2] = {-1, -1};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = integrators[k];
		wdef.floor.enabled = false;
		wdef.contact.enableSleep = true;
		fmWorldId world = fmCreateWorld(&wdef);
		fmVec3 vertices[4] = {fmMakeVec3(-3, 0, -3), fmMakeVec3(3, 0, -3), fmMakeVec3(3, 0, 3),
		                      fmMakeVec3(-3, 0, 3)};
		int triangles[6] = {0, 2, 1, 0, 3, 2};
		fmColliderDef ground = fmDefaultColliderDef();
		ground.shape = fm_shapeMesh;
		ground.vertices = vertices;
		ground.vertexCount = 4;
		ground.triangles = triangles;
		ground.triangleCount = 2;
		fmColliderId id;
		CHECK_INT(fmCreateCollider(world, &ground, &id, NULL), fm_ok);
		fmBodyDef def = softDef(1e5);
		addBox(failures_, world, 2, fmMakeVec3(-0.3, 0.0, -0.3), fmMakeVec3(0.3, 0.6, 0.3), &def);
		addBox(failures_, world, 2, fmMakeVec3(-0.2, 0.65, -0.2), fmMakeVec3(0.2, 1.05, 0.2), &def);
		int substeps = k == 0 ? 1 : 20;
		for (int f = 0; f < 30; ++f)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, substeps), fm_ok);
		s_allocations = 0;
		int contacts = 0;
		for (int f = 0; f < 30; ++f)
		{
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, substeps), fm_ok);
			contacts = fmWorld_GetContacts(world, NULL, 0) > contacts
			               ? fmWorld_GetContacts(world, NULL, 0)
			               : contacts;
		}
		counts[k] = s_allocations;
		CHECK(contacts > 0);
		fmDestroyWorld(world);
	}
	fmSetAllocator(NULL, NULL);
	printf("  allocations in 30 warm frames: implicit %d, explicit %d\n", counts[0], counts[1]);
	CHECK_INT(counts[0], 0);
	CHECK_INT(counts[1], 0);
}

TEST(filters_and_events)
{
	for (int filtered = 0; filtered < 2; ++filtered)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = fm_implicit;
		wdef.floor.height = 0.0;
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = softDef(2e5);
		fmBodyId lower = addBox(failures_, world, 3, fmMakeVec3(-0.3, 0.0, -0.3),
		                        fmMakeVec3(0.3, 0.3, 0.3), &def);
		if (filtered)
			def.filter.maskBits = ~1u; // ignores category 1, the lower box's
		fmBodyId upper = addBox(failures_, world, 3, fmMakeVec3(-0.2, 0.5, -0.2),
		                        fmMakeVec3(0.2, 0.9, 0.2), &def);
		int begins = 0, ends = 0;
		double upperLowest = 0.0;
		for (int f = 0; f < 120; ++f)
		{
			if (f == 90)
			{
				upperLowest = fmBody_GetStats(upper).lowestY;
				fmBody_ApplyImpulse(upper, fmMakeVec3(0.0, 4.0, 0.0));
			}
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
			fmContactEvent events[8];
			int count = fmWorld_GetContactEvents(world, events, 8);
			for (int e = 0; e < count && e < 8; ++e)
			{
				bool pair = events[e].body.index1 == lower.index1 &&
				            events[e].otherBody.index1 == upper.index1;
				begins += pair && events[e].begin;
				ends += pair && !events[e].begin;
			}
		}
		printf("  %s: upper box's lowest point %.3f, %d begin and %d end events\n",
		       filtered ? "filtered" : "colliding", upperLowest, begins, ends);
		if (filtered)
		{
			CHECK(upperLowest < 0.1); // fell through the lower box to the floor
			CHECK_INT(begins, 0);
		}
		else
		{
			CHECK(begins >= 1);
			CHECK(ends >= 1);
		}
		fmDestroyWorld(world);
	}
}

// The mean position of @p body's vertices.
static fmVec3 meanPosition(fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	const double* x = fmTestPositions(body);
	fmVec3 sum = fmMakeVec3(0.0, 0.0, 0.0);
	for (int i = 0; i < n; ++i)
		sum = fmAdd(sum, fmLoad(x, i));
	return fmScale(1.0 / n, sum);
}

// Two coarse boxes (2 x 2 x 2 cells) stacked on a Coulomb floor, implicit at 1/60 s: the upper
// one stays on the lower one and the stack comes to rest. Friction between the bodies acts on
// the velocities after the solve; the positions follow (x = x0 + h v). When they did not, the
// upper box crept 45 mm along the lower one from 2 s to 10 s with up to 6.4e-4 J of kinetic
// energy in the last second (now 5.9 mm and 3.4e-5 J).
TEST(stacked_boxes_do_not_creep)
{
	fmBodyId low, high;
	fmWorldId world = stackedBoxes(failures_, 2, false, &low, &high);
	fmVec3 start = fmSub(meanPosition(high), meanPosition(low));
	double kinetic = 0.0, drift = 0.0;
	for (int f = 1; f <= 600; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		fmVec3 moved = fmSub(fmSub(meanPosition(high), meanPosition(low)), start);
		if (f == 120)
			drift = -hypot(moved.x, moved.z); // measured from 2 s, once landed
		if (f >= 540)
			kinetic = fmax(kinetic, fmBody_GetStats(high).kineticEnergy +
			                            fmBody_GetStats(low).kineticEnergy);
		if (f == 600)
			drift += hypot(moved.x, moved.z);
	}
	printf("  the upper box moved %.2f mm along the lower one from 2 s to 10 s; at most %.2e J "
	       "of kinetic energy in the last second\n",
	       1e3 * drift, kinetic);
	CHECK(fabs(drift) < 0.015);
	CHECK(kinetic < 2e-4);
	fmDestroyWorld(world);
}

// Whether two collider ids name the same collider.
static bool sameCollider(fmColliderId a, fmColliderId b)
{
	return a.index1 == b.index1 && a.generation == b.generation && a.world0 == b.world0 &&
	       a.worldGeneration == b.worldGeneration;
}

// The world floor reports as a collider in both integrators: a box dropped on it begins a pair
// with the floor's collider id (ending it again only when it bounces off), rests with the floor
// carrying its weight (the reaction force), its contacts are in the list with the floor's normal, a
// ray hits the floor, lifting the box ends the pair, and destroying the floor's collider lets the
// box fall; a body whose filter does not meet the floor's falls through it.
static void floorReports(int* failures_, fmIntegrator integrator, bool filtered)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.floor.height = 0.0;
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderId floor = fmWorld_GetFloorCollider(world);
	CHECK(fmCollider_IsValid(floor));
	fmBodyDef def = softDef(2e5);
	if (filtered)
		def.filter.maskBits = ~1u; // ignores category 1, the floor's
	fmBodyId box =
	    addBox(failures_, world, 3, fmMakeVec3(-0.3, 0.1, -0.3), fmMakeVec3(0.3, 0.4, 0.3), &def);
	int substeps = integrator == fm_implicit ? 1 : 20;
	int begins = 0, ends = 0, late = 0;
	double weight = 0.0;
	const double* masses = fmBody_GetMasses(box);
	for (int i = 0; i < fmBody_GetVertexCount(box); ++i)
		weight += 9.8 * masses[i];
	for (int f = 0; f < 150; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, substeps), fm_ok);
		fmContactEvent events[4];
		int count = fmWorld_GetContactEvents(world, events, 4);
		for (int e = 0; e < count && e < 4; ++e)
		{
			begins += sameCollider(events[e].collider, floor) && events[e].begin;
			ends += sameCollider(events[e].collider, floor) && !events[e].begin;
		}
		late += f >= 90 ? count : 0;
	}
	fmVec3 force, torque;
	fmCollider_GetContactForce(floor, &force, &torque);
	int count = fmWorld_GetContacts(world, NULL, 0), onFloor = 0;
	fmContactPoint* points = malloc(sizeof(fmContactPoint) * (size_t)(count > 0 ? count : 1));
	count = fmWorld_GetContacts(world, points, count);
	bool alongNormal = true;
	for (int k = 0; k < count; ++k)
	{
		if (!sameCollider(points[k].collider, floor))
			continue;
		onFloor += 1;
		alongNormal = alongNormal && points[k].normal.y == 1.0 && points[k].impulse >= 0.0 &&
		              fabs(points[k].point.y) < 1e-6;
	}
	free(points);
	double lowest = fmBody_GetStats(box).lowestY;
	printf("  %s%s: %d begin, %d end events; %d floor contacts; the floor carries %.2f N of the "
	       "box's %.2f N (torque %.2e N m), lowest y %.4f\n",
	       integrator == fm_implicit ? "implicit" : "explicit", filtered ? ", filtered" : "",
	       begins, ends, onFloor, -force.y, weight, fmLength(torque), lowest);
	if (filtered)
	{
		CHECK(lowest < -1.0); // fell through
		CHECK_INT(begins + onFloor, 0);
		fmDestroyWorld(world);
		return;
	}
	CHECK(begins >= 1);          // landing (an explicit box may bounce off and land again)
	CHECK_INT(ends, begins - 1); // and on the floor now
	CHECK_INT(late, 0);          // resting: no events in the last second
	CHECK(onFloor > 0 && alongNormal);
	CHECK_INT(fmWorld_GetStepStats(world).contacts, count);
	CHECK_REL(-force.y, weight, 0.02, 0.0); // the box pushes the floor down
	CHECK(fabs(force.x) < 0.02 * weight && fabs(force.z) < 0.02 * weight);
	// A ray beside the box hits the floor's plane.
	fmRayHit hit;
	CHECK(fmWorld_CastRay(world, fmMakeVec3(2.0, 1.0, 0.5), fmMakeVec3(0.0, -2.0, 0.0),
	                      fmDefaultFilter(), &hit));
	CHECK(sameCollider(hit.collider, floor));
	CHECK_NEAR(hit.point.y, 0.0, 1e-12);
	// Thrown up, the box leaves the floor: the pair ends.
	fmBody_ApplyImpulse(box, fmMakeVec3(0.0, 3.0, 0.0));
	for (int f = 0; f < 10; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, substeps), fm_ok);
		fmContactEvent events[4];
		int n = fmWorld_GetContactEvents(world, events, 4);
		for (int e = 0; e < n && e < 4; ++e)
			ends += sameCollider(events[e].collider, floor) && !events[e].begin;
	}
	CHECK_INT(ends, begins);
	// Without its floor the box falls.
	fmDestroyCollider(floor);
	CHECK(!fmCollider_IsValid(floor));
	CHECK(!fmCollider_IsValid(fmWorld_GetFloorCollider(world)));
	for (int f = 0; f < 60; ++f)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, substeps), fm_ok);
	CHECK(fmBody_GetStats(box).lowestY < -1.0);
	// A floor put back is a new collider: the old id stays stale.
	CHECK_INT(fmWorld_SetFloor(world, &wdef.floor), fm_ok);
	CHECK(fmCollider_IsValid(fmWorld_GetFloorCollider(world)) && !fmCollider_IsValid(floor));
	fmDestroyWorld(world);
}

TEST(floor_reports_as_a_collider)
{
	for (int filtered = 0; filtered < 2; ++filtered)
	{
		floorReports(failures_, fm_explicit, filtered);
		floorReports(failures_, fm_implicit, filtered);
	}
}

// The same contact scene on 1 and 3 workers: the same bits.
// The last substep's contacts between two bodies.
static int bodyContacts(fmWorldId world)
{
	int count = fmWorld_GetContacts(world, NULL, 0), between = 0;
	fmContactPoint* points = malloc(sizeof(fmContactPoint) * (size_t)(count > 0 ? count : 1));
	count = fmWorld_GetContacts(world, points, count);
	for (int k = 0; k < count; ++k)
		between += fmBody_IsValid(points[k].otherBody);
	free(points);
	return between;
}

// The contact detection runs on the workers (vertex and edge items in ranges): the same bits
// for 1, 2 and 3 workers, in both integrators (the explicit one also finds edge contacts).
static void contactSameForWorkers(int* failures_, fmIntegrator integrator)
{
	enum
	{
		houses = 4
	};
	double* result[3] = {NULL, NULL, NULL};
	int n = 0, contacts = 0, groups = 0, together = 0;
	// (The explicit frames take about 40 substeps each: 30 of them see the houses touch. The
	// quick count, under the sanitizers, still sees them touch: checked below.)
	const int frames = integrator == fm_implicit ? fmTestCount(60, 20) : fmTestCount(30, 5);
	for (int k = 0; k < 3; ++k)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = integrator;
		wdef.autoSubstep = integrator == fm_explicit;
		wdef.workerCount = k + 1;
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = implicitHouseDef();
		// Three houses stacked 3 cm apart, the second shifted, and one far off: the top and the
		// bottom house, and the far one, step at once (one schedule group), the middle after.
		const fmVec3 at[houses] = {
		    {0.0, -1.0, 0.0}, {0.3, 3.03, 0.0}, {0.0, 7.06, 0.0}, {30.0, -1.0, 0.0}};
		fmBodyId body[houses];
		for (int h = 0; h < houses; ++h)
			body[h] = addHouse(failures_, world, at[h], &def);
		fmColliderDef sphere = fmDefaultColliderDef();
		sphere.shape = fm_shapeSphere;
		sphere.center = fmMakeVec3(1.5, -2.5, 0.0);
		fmColliderId collider;
		CHECK_INT(fmCreateCollider(world, &sphere, &collider, NULL), fm_ok);
		for (int f = 0; f < frames; ++f)
		{
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, integrator == fm_implicit ? 1 : 10), fm_ok);
			contacts += k == 0 ? bodyContacts(world) : 0;
			const fmSchedule* schedule = &fmGetWorld(world)->schedule;
			groups = schedule->groupCount > groups ? schedule->groupCount : groups;
			for (int g = 0; g < schedule->groupCount; ++g)
			{
				int size = schedule->groupStart[g + 1] - schedule->groupStart[g];
				together = size > together ? size : together;
			}
		}
		n = fmBody_GetVertexCount(body[0]);
		result[k] = malloc(sizeof(double) * 3 * houses * (size_t)n);
		for (int h = 0; h < houses && result[k] != NULL; ++h)
			fmBody_CopyPositions(body[h], result[k] + 3 * h * n, n);
		fmDestroyWorld(world);
	}
	printf("  %s: %d body-body contacts at the frames' ends over %d frames; up to %d schedule "
	       "groups, up to %d bodies stepping at once\n",
	       integrator == fm_implicit ? "implicit" : "explicit", contacts, frames, groups, together);
	CHECK(contacts > 0); // the houses did meet
	// The implicit barrier's groups: {bottom, top, far} and {middle}; explicit: all at once.
	CHECK_INT(groups, integrator == fm_implicit ? 2 : 1);
	CHECK_INT(together, integrator == fm_implicit ? 3 : houses);
	for (int k = 1; k < 3; ++k)
		CHECK(result[0] && result[k] &&
		      memcmp(result[0], result[k], sizeof(double) * 3 * houses * (size_t)n) == 0);
	for (int k = 0; k < 3; ++k)
		free(result[k]);
}

TEST(contact_is_deterministic_across_workers)
{
	contactSameForWorkers(failures_, fm_implicit);
	contactSameForWorkers(failures_, fm_explicit);
}

// Bad collider defs are refused with the field named.
TEST(bad_colliders_are_refused)
{
	fmWorldDef start = fmDefaultWorldDef();
	fmWorldId world = fmCreateWorld(&start);
	fmColliderId id;
	fmDiagnostic diag;
	fmColliderDef def = fmDefaultColliderDef();
	def.normal = fmMakeVec3(0.0, 0.0, 0.0);
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "normal");
	def = fmDefaultColliderDef();
	def.shape = fm_shapeSphere;
	def.radius = -1.0;
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "radius");
	def = fmDefaultColliderDef();
	def.friction = NAN;
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "friction");
	def = fmDefaultColliderDef();
	def.shape = (fmShapeType)42;
	CHECK_INT(fmCreateCollider(world, &def, &id, &diag), fm_errParameter);
	fmColliderDef raw;
	memset(&raw, 0, sizeof raw);
	CHECK_INT(fmCreateCollider(world, &raw, &id, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "fmDefaultColliderDef");
	CHECK(!fmCollider_IsValid(id));
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.contact.iterations = 0;
	CHECK_INT(fmWorldDef_Validate(&wdef, &diag), fm_errParameter);
	CHECK_STR_CONTAINS(diag.message, "iterations");
	fmDestroyWorld(world);
}

// Two bodies touching, stepped far beyond the explicit stability limit: the step that blows up
// reports a numerical failure (the frame's checks), never a hang or a broad phase out of memory
// on the non-finite positions.
TEST(blow_up_near_contact_is_reported)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.height = 0.0;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	addBox(failures_, world, 3, fmMakeVec3(-0.3, 0.0, -0.3), fmMakeVec3(0.3, 0.6, 0.3), &def);
	addBox(failures_, world, 3, fmMakeVec3(-0.3, 0.61, -0.3), fmMakeVec3(0.3, 1.21, 0.3), &def);
	fmResult result = fm_ok;
	for (int f = 0; f < 60 && result == fm_ok; ++f)
		result = fmWorld_Step(world, 0.02, 1); // 4x the stability limit
	CHECK_INT(result, fm_errNumerical);
	fmDestroyWorld(world);
}

// ---- stick colliders: the seeds' floor as a half-space collider --------------------------------

// A world in @p integrator whose ground is y = -3: the world floor with the seeds' stick
// friction, or (with @p collider) the half-space collider y = -3 with stick, the floor off.
static fmWorldId stickGround(int* failures_, fmIntegrator integrator, bool collider)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.floor.height = -3.0;
	wdef.floor.friction = fm_floorStick;
	wdef.floor.enabled = !collider;
	fmWorldId world = fmCreateWorld(&wdef);
	if (collider)
	{
		fmColliderDef plane = fmDefaultColliderDef();
		plane.offset = -3.0;
		plane.stick = true;
		plane.friction = 0.0; // ignored with stick
		fmColliderId id;
		CHECK_INT(fmCreateCollider(world, &plane, &id, NULL), fm_ok);
	}
	return world;
}

// Explicit: the seeds' house dropped (the seeds' 3 ms substeps) for 2 s; implicit: a box of
// 0.4 m dropped from 0.3 m above the ground while moving sideways at 2 m/s, 1/60 s steps, 2 s.
// Copies the final positions into @p out; @p sideways gets the centre's x at 1 s and 2 s.
static int dropOnStickGround(int* failures_, fmIntegrator integrator, bool collider, double* out,
                             int capacity, double sideways[2], int* unconverged, double* energy)
{
	fmWorldId world = stickGround(failures_, integrator, collider);
	fmBodyId body;
	bool implicit = integrator == fm_implicit;
	if (implicit)
	{
		fmBodyDef def = implicitHouseDef();
		def.smoothing = 0.0;
		body = addBox(failures_, world, 3, fmMakeVec3(-0.3, -2.7, -0.3), fmMakeVec3(0.3, -2.5, 0.3),
		              &def);
		fmBody_ApplyImpulse(body, fmMakeVec3(1.0, 0.0, 0.0));
	}
	else
		body = addHouse(failures_, world, fmMakeVec3(0.0, 0.0, 0.0), NULL);
	*unconverged = 0;
	for (int f = 0; f < (implicit ? 120 : 67); ++f)
	{
		CHECK_INT(fmWorld_Step(world, implicit ? 1.0 / 60.0 : 0.03, implicit ? 1 : 10), fm_ok);
		*unconverged += fmWorld_GetStepStats(world).unconvergedSteps;
		if (f == (implicit ? 59 : 32))
			sideways[0] = fmBody_GetStats(body).centerOfMass.x;
	}
	sideways[1] = fmBody_GetStats(body).centerOfMass.x;
	*energy = fmBody_GetStats(body).kineticEnergy;
	int count = fmBody_GetVertexCount(body);
	CHECK(count <= capacity && fmBody_CopyPositions(body, out, capacity) == fm_ok);
	fmDestroyWorld(world);
	return count;
}

// A stick plane collider is the seeds' stick floor. Explicit: the seeds' house dropped on the
// plane y = -3 with stick is, after 2 s (in its second bounce), where the same house is on the
// world floor with fm_floorStick, within 1 cm (measured 3.2 mm; its top falls 4.9 m). The two
// differ only in the velocity a vertex keeps when it is put back on the surface (the floor
// turns the depth into (height - y_start) / dt, the collider zeroes the approach): at most a
// substep's motion at the impact speed (6 m/s x 3 ms = 1.8 cm) a bounce, and far less after.
// Implicit (the floor an active set, the collider a penalty with lagged stick friction in the
// solve): a flat box thrown sideways at 1 m/s stops where it lands on both, within one step's
// sideways motion (1 m/s x 1/60 s = 1.7 cm; measured 7.4 mm: the collider's first step of
// contact has no lagged friction yet), is at rest after 2 s (kinetic energy 1e-7 J) and moved
// by 1e-5 m in the second second; Newton converges at every step.
TEST(stick_collider_matches_the_stick_floor)
{
	enum
	{
		capacity = 4096
	};
	static double onFloor[3 * capacity], onCollider[3 * capacity];
	for (int k = 0; k < 2; ++k)
	{
		fmIntegrator integrator = k == 0 ? fm_explicit : fm_implicit;
		double floorX[2], colliderX[2], floorEnergy, colliderEnergy;
		int floorUnconverged, colliderUnconverged;
		int n = dropOnStickGround(failures_, integrator, false, onFloor, capacity, floorX,
		                          &floorUnconverged, &floorEnergy);
		dropOnStickGround(failures_, integrator, true, onCollider, capacity, colliderX,
		                  &colliderUnconverged, &colliderEnergy);
		double worst = 0.0;
		for (int i = 0; i < 3 * n; ++i)
			worst = fmax(worst, fabs(onFloor[i] - onCollider[i]));
		printf("  %s: positions differ by at most %.3g m; centre x at 1 s and 2 s: floor %.5f, "
		       "%.5f, collider %.5f, %.5f; kinetic energy %.3g J, %.3g J; unconverged steps: "
		       "floor %d, collider %d\n",
		       k == 0 ? "explicit" : "implicit", worst, floorX[0], floorX[1], colliderX[0],
		       colliderX[1], floorEnergy, colliderEnergy, floorUnconverged, colliderUnconverged);
		CHECK(worst < (integrator == fm_implicit ? 1.0 / 60.0 : 0.01));
		CHECK_INT(colliderUnconverged, 0);
		if (integrator == fm_implicit)
			CHECK(fabs(floorX[1] - floorX[0]) < 1e-3 && fabs(colliderX[1] - colliderX[0]) < 1e-3 &&
			      floorEnergy < 1e-3 && colliderEnergy < 1e-3);
	}
}

// The rotation by @p angle (rad) about the unit axis @p k (Rodrigues), applied to @p v.
static fmVec3 rotateAbout(fmVec3 k, double angle, fmVec3 v)
{
	double c = cos(angle), s = sin(angle);
	fmVec3 out = fmAdd(fmScale(c, v), fmScale(s, fmCross(k, v)));
	return fmMulAdd(out, (1.0 - c) * fmDot(k, v), k);
}

// A stiff 20 cm box set on a plane through the origin inclined 30 degrees about the horizontal
// axis @p axis (gravity stays -y), with stick or with Coulomb friction @p mu, for 1 s. Returns
// how far its centre moved down the slope; @p unconverged gets the implicit steps above the
// tolerance.
static double boxOnIncline(int* failures_, fmIntegrator integrator, fmVec3 axis, bool stick,
                           double mu, int* unconverged, double* half)
{
	const double angle = 30.0 * 3.14159265358979 / 180.0;
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderDef plane = fmDefaultColliderDef();
	plane.normal = rotateAbout(axis, angle, fmMakeVec3(0.0, 1.0, 0.0));
	plane.stick = stick;
	plane.friction = mu;
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(world, &plane, &collider, NULL), fm_ok);
	fmTetMesh mesh;
	fmBodyId block = {0, 0, 0, 0};
	if (fmMakeBoxMesh(2, 2, 2, fmMakeVec3(-0.1, 0.002, -0.1), fmMakeVec3(0.1, 0.202, 0.1), &mesh) ==
	    fm_ok)
	{
		for (int i = 0; i < mesh.nodeCount; ++i)
		{
			double* p = mesh.positions + 3 * i;
			fmVec3 q = rotateAbout(axis, angle, fmMakeVec3(p[0], p[1], p[2]));
			p[0] = q.x, p[1] = q.y, p[2] = q.z;
		}
		fmBodyDef def = fmDefaultBodyDef();
		def.mesh = &mesh;
		def.material = fmMakeMaterial(fm_neoHookean, 1e7, 0.3);
		def.massMode = fm_massFromDensity;
		def.damping = 1.0;
		def.smoothing = 0.0;
		CHECK_INT(fmCreateBody(world, &def, &block, NULL), fm_ok);
		fmFreeTetMesh(&mesh);
	}
	// Down the slope: gravity's part along the plane.
	fmVec3 n = fmScale(1.0 / fmLength(plane.normal), plane.normal), g = fmMakeVec3(0, -1, 0);
	fmVec3 down = fmMulAdd(g, -fmDot(g, n), n);
	down = fmScale(1.0 / fmLength(down), down);
	fmVec3 start = fmBody_GetStats(block).centerOfMass;
	*unconverged = 0;
	for (int f = 0; f < 60; ++f)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, integrator == fm_implicit ? 1 : 50), fm_ok);
		*unconverged += fmWorld_GetStepStats(world).unconvergedSteps;
		if (f == 29)
			*half = fmDot(fmSub(fmBody_GetStats(block).centerOfMass, start), down);
	}
	double slid = fmDot(fmSub(fmBody_GetStats(block).centerOfMass, start), down);
	fmDestroyWorld(world);
	return slid;
}

// A stick plane collider holds a box on a 30 degree incline, inclined about the z axis and about
// a horizontal axis at 35 degrees to x, in both integrators: under 3 cm down the slope in 1 s
// (measured 1.3 and 1.7 cm explicit, 1.6 and 1.7 mm implicit, most of it while the box lands;
// then a creep of 8 to 10 mm/s explicit, the h^2 a a vertex moves in the substep before its
// velocity is zeroed again, and none implicit, where the positions follow the velocities the
// stick took back: before, the stick spring's stretch m g sin(30) h^2 / (kappa m_contact) a
// step crept 4 to 5 mm/s), with Newton converging at every step, while with Coulomb friction
// 0.3 it slides 1.2 m (g (sin 30 - 0.3 cos 30) = 2.35 m/s^2).
TEST(stick_collider_holds_on_an_incline)
{
	const fmVec3 axes[2] = {fmMakeVec3(0.0, 0.0, 1.0), fmMakeVec3(cos(0.61), 0.0, sin(0.61))};
	for (int k = 0; k < 8; ++k)
	{
		fmIntegrator integrator = k & 1 ? fm_implicit : fm_explicit;
		bool stick = (k & 2) == 0;
		int unconverged;
		double half;
		double slid =
		    boxOnIncline(failures_, integrator, axes[k >> 2], stick, 0.3, &unconverged, &half);
		printf("  %s, %s, %s: slid %.4g m in 1 s (%.4g m in the second half), unconverged "
		       "steps %d\n",
		       k >> 2 ? "axis (0.82, 0, 0.57)" : "axis z",
		       integrator == fm_implicit ? "implicit" : "explicit", stick ? "stick" : "mu 0.3",
		       slid, slid - half, unconverged);
		CHECK_INT(unconverged, 0);
		CHECK(stick ? fabs(slid) < 0.03 : slid > 0.5);
		if (stick && integrator == fm_implicit)
			CHECK(fabs(slid - half) < 1e-4); // no creep once landed (it was 1.9 to 2.4 mm)
	}
}

// Stick is relative to the collider's surface: a box set on a stick plane that moves along
// itself at 1 m/s (a conveyor belt) is carried at the belt's speed in both integrators
// (measured 0.99 m explicit, 0.98 m implicit in 1 s), while on a frictionless belt it stays put.
TEST(stick_collider_carries_on_a_conveyor)
{
	for (int k = 0; k < 4; ++k)
	{
		fmIntegrator integrator = k & 1 ? fm_implicit : fm_explicit;
		bool stick = k < 2;
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = integrator;
		wdef.floor.enabled = false;
		fmWorldId world = fmCreateWorld(&wdef);
		fmColliderDef plane = fmDefaultColliderDef();
		plane.stick = stick;
		plane.friction = 0.0;
		plane.velocity = fmMakeVec3(1.0, 0.0, 0.0);
		fmColliderId collider;
		CHECK_INT(fmCreateCollider(world, &plane, &collider, NULL), fm_ok);
		fmBodyDef def = fmDefaultBodyDef();
		def.material = fmMakeMaterial(fm_neoHookean, 1e6, 0.3);
		def.massMode = fm_massFromDensity;
		def.damping = 1.0;
		def.smoothing = 0.0;
		fmBodyId block = addBox(failures_, world, 2, fmMakeVec3(-0.1, 0.002, -0.1),
		                        fmMakeVec3(0.1, 0.202, 0.1), &def);
		double x0 = fmBody_GetStats(block).centerOfMass.x;
		for (int f = 0; f < 60; ++f)
			CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, integrator == fm_implicit ? 1 : 50), fm_ok);
		double moved = fmBody_GetStats(block).centerOfMass.x - x0;
		printf("  %s, %s belt: carried %.4f m in 1 s\n",
		       integrator == fm_implicit ? "implicit" : "explicit",
		       stick ? "stick" : "frictionless", moved);
		CHECK(stick ? moved > 0.9 && moved < 1.01 : fabs(moved) < 0.01);
		fmDestroyWorld(world);
	}
}

// A body put half inside another by fmBody_SetPositions (made apart: a body made overlapping is
// refused), and 64 small boxes all moved to one place: the next step is refused with
// fm_errParameter naming the two bodies, every body goes back to where the last frame left it,
// and the step after runs. Before, the half-inside pair stayed stuck for good implicitly (all 60
// surface vertices 0.45 m deep, every solve stalled) and partly entangled explicitly, and the 64
// boxes took 4 to 6 s a frame implicitly without end, or 2.7 s for each refused explicit frame.
static void setOverlappingIsRefused(int* failures_, fmIntegrator integrator)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.floor.height = 0.0;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	fmBodyId boxes[2] = {
	    addBox(failures_, world, 4, fmMakeVec3(-0.5, 0.0, -0.5), fmMakeVec3(0.5, 1.0, 0.5), &def),
	    addBox(failures_, world, 4, fmMakeVec3(2.7, 0.5, -0.3), fmMakeVec3(3.7, 1.5, 0.7), &def)};
	int n = fmBody_GetVertexCount(boxes[1]);
	double* apart = malloc(sizeof(double) * 3 * (size_t)n);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	memcpy(apart, fmTestPositions(boxes[1]), sizeof(double) * 3 * (size_t)n);
	memcpy(x, apart, sizeof(double) * 3 * (size_t)n);
	for (int i = 0; i < n; ++i)
		x[3 * i] -= 3.0;
	fmBody_SetPositions(boxes[1], x);
	bool implicit = integrator == fm_implicit;
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 20), fm_errParameter);
	const char* message = fmWorld_GetLastError(world)->message;
	printf("  %s: %s\n", implicit ? "implicit" : "explicit", message);
	CHECK_STR_CONTAINS(message, "body 1: the positions set since the last frame");
	CHECK_STR_CONTAINS(message, "across or inside body 0");
	CHECK(memcmp(fmTestPositions(boxes[1]), apart, sizeof(double) * 3 * (size_t)n) == 0);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 20), fm_ok);
	fmDestroyWorld(world);
	free(apart), free(x);

	// 64 small boxes made apart, then all moved to one place.
	wdef.maxBodies = 64;
	world = fmCreateWorld(&wdef);
	fmBodyId small[64];
	for (int k = 0; k < 64; ++k)
		small[k] = addBox(failures_, world, 2, fmMakeVec3(0.5 * k, 1.0, 0.0),
		                  fmMakeVec3(0.5 * k + 0.2, 1.2, 0.2), &def);
	double moved[27 * 3];
	for (int k = 0; k < 64; ++k)
	{
		memcpy(moved, fmTestPositions(small[k]), sizeof moved);
		for (int i = 0; i < 27; ++i)
			moved[3 * i] -= 0.5 * k;
		fmBody_SetPositions(small[k], moved);
	}
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 20), fm_errParameter);
	CHECK_STR_CONTAINS(fmWorld_GetLastError(world)->message,
	                   "the positions set since the last frame");
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, implicit ? 1 : 20), fm_ok);
	CHECK(fmTestPositions(small[63])[0] > 31.0); // where it was made
	fmDestroyWorld(world);
}

TEST(bodies_set_overlapping_are_refused)
{
	setOverlappingIsRefused(failures_, fm_implicit);
	setOverlappingIsRefused(failures_, fm_explicit);
}

// Whether a 1 m / 3 box around (x + 0.5, 0.5, 0.5) can be made in @p world (made, it is destroyed
// again).
static bool boxCanBeMade(fmWorldId world, double x, const fmBodyDef* def)
{
	fmTetMesh mesh;
	if (fmMakeBoxMesh(2, 2, 2, fmMakeVec3(x + 0.33, 0.33, 0.33), fmMakeVec3(x + 0.67, 0.67, 0.67),
	                  &mesh) != fm_ok)
		return false;
	fmBodyDef bdef = *def;
	bdef.mesh = &mesh;
	fmBodyId body;
	fmResult r = fmCreateBody(world, &bdef, &body, NULL);
	fmFreeTetMesh(&mesh);
	if (r == fm_ok)
		fmDestroyBody(body);
	return r == fm_ok;
}

// @p body's positions moved by @p dx along x, through fmBody_SetPositions.
static void shiftBody(fmBodyId body, double dx)
{
	int n = fmBody_GetVertexCount(body);
	double* x = malloc(sizeof(double) * 3 * (size_t)n);
	if (x == NULL || fmBody_CopyPositions(body, x, n) != fm_ok)
	{
		free(x);
		return;
	}
	for (int i = 0; i < n; ++i)
		x[3 * i] += dx;
	fmBody_SetPositions(body, x);
	free(x);
}

// The audit at creation caches each body's box while no vertex moves (a thousand props made one
// after another cost the boxes of those before, not their vertices): every call that moves
// vertices (a step, fmBody_SetPositions, fmWorld_RestoreSnapshot) leaves the cache stale, so a
// new body is refused where a body is now and made where it was.
TEST(creation_audits_bodies_where_they_are_now)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.gravity = fmMakeVec3(0, 0, 0);
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	fmBodyId a = addBox(failures_, world, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &def);
	CHECK(!boxCanBeMade(world, 0.0, &def)); // (A's box cached)
	CHECK(boxCanBeMade(world, 2.0, &def));
	// Stepped: A slides 2 m along x in 2 s.
	int n = fmBody_GetVertexCount(a);
	double* v = calloc(3 * (size_t)n, sizeof *v);
	for (int i = 0; v != NULL && i < n; ++i)
		v[3 * i] = 1.0;
	fmBody_SetVelocities(a, v);
	free(v);
	for (int frame = 0; frame < 120; ++frame)
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 4), fm_ok);
	CHECK(!boxCanBeMade(world, 2.0, &def));
	CHECK(boxCanBeMade(world, 0.0, &def));
	// Stopped, and set back by hand.
	double* rest = calloc(3 * (size_t)n, sizeof *rest);
	if (rest != NULL)
		fmBody_SetVelocities(a, rest);
	free(rest);
	shiftBody(a, -2.0);
	CHECK(!boxCanBeMade(world, 0.0, &def));
	CHECK(boxCanBeMade(world, 2.0, &def));
	// Saved there, moved again, restored.
	size_t size = fmWorld_GetSnapshotSize(world);
	void* snapshot = malloc(size);
	CHECK_INT(fmWorld_SaveSnapshot(world, snapshot, size, NULL), fm_ok);
	shiftBody(a, 2.0);
	CHECK(!boxCanBeMade(world, 2.0, &def));
	CHECK_INT(fmWorld_RestoreSnapshot(world, snapshot, size), fm_ok);
	CHECK(!boxCanBeMade(world, 0.0, &def));
	CHECK(boxCanBeMade(world, 2.0, &def));
	free(snapshot);
	fmDestroyWorld(world);
}

// A self-colliding body whose own surface crosses at rest (two tets overlapping in one mesh: an
// outside audit's case, which then showed self crossings at every substep) is refused with the
// first crossing; without self-collision the same mesh is a body like any other.
TEST(a_body_crossing_itself_is_refused_with_self_collision)
{
	double x[24] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
	for (int k = 12; k < 24; ++k)
		x[k] = x[k - 12] + 0.1;
	int tets[8] = {0, 1, 2, 3, 4, 5, 6, 7};
	fmTetMesh mesh = {.nodeCount = 8, .positions = x, .tetCount = 2, .tets = tets};
	for (int self = 1; self >= 0; --self)
	{
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = fm_implicit;
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = softDef(1e5);
		def.mesh = &mesh;
		def.selfCollision = self != 0;
		fmBodyId body;
		fmDiagnostic diag;
		fmResult r = fmCreateBody(world, &def, &body, &diag);
		if (self)
		{
			printf("  %s\n", diag.message);
			CHECK_INT(r, fm_errParameter);
			CHECK(strstr(diag.message, "crosses itself at rest") != NULL);
		}
		else
			CHECK_INT(r, fm_ok);
		fmDestroyWorld(world);
	}
}

// A body made overlapping another it collides with is refused with the reason (a crossing edge
// or a vertex inside, and which body); one wholly inside another too (no edge crosses: its
// vertices are inside). Made touching, with filters that do not meet, or in a world without
// body contact, it is made.
TEST(overlapping_bodies_are_refused_at_creation)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.floor.height = 0.0;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	addBox(failures_, world, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &def);
	struct
	{
		fmVec3 lo, hi;
		const char* what;
	} refused[2] = {{{0.43, 0.57, 0.31}, {1.43, 1.57, 1.31}, "edges crossing"},
	                {{0.3, 0.3, 0.3}, {0.6, 0.6, 0.6}, "vertices inside"}};
	for (int k = 0; k < 2; ++k)
	{
		fmTetMesh mesh;
		CHECK_INT(fmMakeBoxMesh(2, 2, 2, refused[k].lo, refused[k].hi, &mesh), fm_ok);
		fmBodyDef bdef = def;
		bdef.mesh = &mesh;
		fmBodyId body;
		fmDiagnostic diag;
		CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_errParameter);
		printf("  %s: %s\n", refused[k].what, diag.message);
		CHECK(strstr(diag.message, "would start overlapping body 0") != NULL);
		CHECK(strstr(diag.message, k == 0 ? "(0 surface edges" : ", 0 surface vertices and") ==
		      NULL);
		CHECK(!fmBody_IsValid(body));
		// A filter the first body's does not meet (category 2 against its category 1): made.
		bdef.filter.categoryBits = 2;
		bdef.filter.maskBits = 2;
		CHECK_INT(fmCreateBody(world, &bdef, &body, &diag), fm_ok);
		fmDestroyBody(body);
		// A world without body contact: made.
		fmWorldDef apart = wdef;
		apart.contact.bodies = false;
		fmWorldId free = fmCreateWorld(&apart);
		bdef.filter = fmDefaultFilter();
		addBox(failures_, free, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &def);
		CHECK_INT(fmCreateBody(free, &bdef, &body, &diag), fm_ok);
		fmDestroyWorld(free);
		fmFreeTetMesh(&mesh);
	}
	// Touching face to face: made.
	fmBodyId touching = addBox(failures_, world, 2, fmMakeVec3(0, 1, 0), fmMakeVec3(1, 2, 1), &def);
	CHECK(fmBody_IsValid(touching));
	// The same box again at the same place: no edge crosses and no vertex is strictly inside
	// (each lies on the other's surface), but the interiors overlap: refused by its tets' centres
	// (64 boxes made at one place were all made before, and ground for seconds a frame).
	fmTetMesh same;
	CHECK_INT(fmMakeBoxMesh(2, 2, 2, fmMakeVec3(0, 0, 0), fmMakeVec3(1, 1, 1), &same), fm_ok);
	fmBodyDef sameDef = def;
	sameDef.mesh = &same;
	fmBodyId twin;
	fmDiagnostic diag;
	CHECK_INT(fmCreateBody(world, &sameDef, &twin, &diag), fm_errParameter);
	printf("  the same box twice: %s\n", diag.message);
	CHECK_STR_CONTAINS(diag.message, "0 surface edges crossing surface triangles, 0 surface "
	                                 "vertices and 96 tet centres inside"); // 48 each way
	fmFreeTetMesh(&same);
	fmDestroyWorld(world);
}

// The implicit edge planes' penalty (penalty.c, fmEdgePlane): its gradient is its energy's
// (central differences over the edge's six coordinates), its Hessian product the gradient's,
// and the matrix-free product the assembled blocks' (one operator on both solver paths).
TEST(edge_plane_penalty_gradient)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.enabled = false;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	fmBodyId id =
	    addBox(failures_, world, 2, fmMakeVec3(0.0, 0.0, 0.0), fmMakeVec3(0.4, 0.4, 0.4), &def);
	fmColliderDef far = fmDefaultColliderDef(); // (a collider: the contact stage's arrays)
	far.shape = fm_shapeSphere;
	far.center = fmMakeVec3(0.0, -50.0, 0.0);
	fmColliderId collider;
	CHECK_INT(fmCreateCollider(world, &far, &collider, NULL), fm_ok);
	CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
	fmBody* b = fmGetBody(id);
	CHECK(b != NULL && b->contact.surfaceVertex != NULL);
	if (b == NULL || b->contact.surfaceVertex == NULL)
	{
		fmDestroyWorld(world);
		return;
	}
	int a = b->mesh.surface[0], c = b->mesh.surface[1];
	const double h = 1.0 / 60.0, thickness = 0.01;
	fmVec3 n = fmScale(1.0 / sqrt(1.05), fmMakeVec3(0.2, 1.0, 0.1));
	fmVec3 q = fmAdd(fmScale(0.7, fmLoad(b->state.x, a)), fmScale(0.3, fmLoad(b->state.x, c)));
	FM_FREE_ARRAY(b->contact.edgePlanes, fmEdgePlane, b->contact.edgePlaneCapacity);
	b->contact.edgePlanes = FM_ALLOC_ARRAY(fmEdgePlane, 1);
	b->contact.edgePlaneCapacity = b->contact.edgePlanes ? 1 : 0;
	b->contact.edgePlaneCount = b->contact.edgePlaneCapacity;
	if (b->contact.edgePlaneCount == 1)
		b->contact.edgePlanes[0] = (fmEdgePlane){a, c, 0.3, n, fmDot(n, q) + 0.5 * thickness};
	fmContactPenalty penalty = {
	    NULL, 0, FM_PENALTY_KAPPA / (h * h), thickness, b->state.x, h, b, false, NULL, NULL};
	int n3 = 3 * b->mesh.vertexCount;
	double* x = malloc(sizeof(double) * (size_t)n3);
	double* gradient = calloc((size_t)n3, sizeof(double));
	double* dx = calloc((size_t)n3, sizeof(double));
	double* y = calloc((size_t)n3, sizeof(double));
	double* blocks = calloc(9 * (size_t)b->mesh.vertexCount, sizeof(double));
	memcpy(x, b->state.x, sizeof(double) * (size_t)n3);
	double energy = fmContactPenalty_Energy(&penalty, b, x, gradient), worst = 0.0;
	const int vertices[2] = {a, c};
	for (int k = 0; k < 6; ++k)
	{
		int dof = 3 * vertices[k / 3] + k % 3;
		const double e = 1e-7;
		x[dof] += e;
		double up = fmContactPenalty_Energy(&penalty, b, x, NULL);
		x[dof] -= 2.0 * e;
		double down = fmContactPenalty_Energy(&penalty, b, x, NULL);
		x[dof] += e;
		worst = fmax(worst, fabs((up - down) / (2.0 * e) - gradient[dof]) /
		                        fmax(1e-12, fabs(gradient[dof])));
		dx[dof] = 0.1 * (k + 1);
	}
	fmContactPenalty_AddProduct(&penalty, b, x, dx, y);
	// The product is the gradient's derivative along dx (central differences; the penalty is
	// quadratic in x with its planes frozen, so they agree to round-off), the edge's coupling of
	// its two vertices included, and the assembled blocks (pattern of the solver's cache) give
	// the same product. The pattern-free blocks are the diagonal ones alone.
	double* up = calloc((size_t)n3, sizeof(double));
	double* down = calloc((size_t)n3, sizeof(double));
	const double step = 1e-6;
	for (int k = 0; k < n3; ++k)
		x[k] += step * dx[k];
	fmContactPenalty_Energy(&penalty, b, x, up);
	for (int k = 0; k < n3; ++k)
		x[k] -= 2.0 * step * dx[k];
	fmContactPenalty_Energy(&penalty, b, x, down);
	for (int k = 0; k < n3; ++k)
		x[k] += step * dx[k];
	fmImplicitCache* cache = b->solverCache;
	CHECK(cache != NULL);
	double* assembled = cache ? calloc(9 * (size_t)cache->pattern.blocks, sizeof(double)) : NULL;
	if (assembled)
		fmContactPenalty_AddHessian(&penalty, b, x, &cache->pattern, assembled);
	fmContactPenalty_AddHessian(&penalty, b, x, NULL, blocks);
	double derivative = 0.0, product = 0.0, diagonalOnly = 0.0, size = 0.0;
	for (int k = 0; k < 6; ++k)
	{
		int i = vertices[k / 3], r = k % 3;
		size = fmax(size, fabs(y[3 * i + r]));
		derivative =
		    fmax(derivative, fabs(y[3 * i + r] - (up[3 * i + r] - down[3 * i + r]) / (2.0 * step)));
		double fromBlocks = 0.0, fromDiagonal = 0.0;
		for (int col = 0; col < 3; ++col)
			fromDiagonal += blocks[9 * (size_t)i + 3 * r + col] * dx[3 * i + col];
		for (int j = 0; cache && assembled && j < 2; ++j)
		{
			int slot = fmBsr_Find(&cache->pattern, i, vertices[j]);
			CHECK(slot >= 0);
			for (int col = 0; slot >= 0 && col < 3; ++col)
				fromBlocks += assembled[9 * (size_t)slot + 3 * r + col] * dx[3 * vertices[j] + col];
		}
		product = fmax(product, fabs(y[3 * i + r] - fromBlocks));
		diagonalOnly = fmax(diagonalOnly, fabs(y[3 * i + r] - fromDiagonal));
	}
	printf("  energy %.4g J, gradient against central differences within %.2g (relative); "
	       "product %.4g N: against the gradient's differences within %.2g, the assembled "
	       "blocks within %.2g, the diagonal blocks alone off by %.2g\n",
	       energy, worst, size, derivative, product, diagonalOnly);
	CHECK(energy > 0.0);
	CHECK(worst < 1e-5);
	CHECK(derivative < 1e-6 * size);
	CHECK(product < 1e-9 * size);
	CHECK(diagonalOnly > 1e-3 * size); // the coupling is there, and the check can see it
	free(up), free(down), free(assembled);
	free(x), free(gradient), free(dx), free(y), free(blocks);
	fmDestroyWorld(world);
}

// ---- barrier contact (issue 29): audited at every substep ---------------------------------------

// The worst the audit found over the substeps it was called after, and the energy law: the
// listed bodies' (auditEnergyFrom) kinetic plus elastic energy less their start and the work done
// on them (their energy ledgers: gravity, the floor lifting a body that starts in it), its highest
// over the substeps, with the drop's energy (the kinetic energy at the start and the
// gravitational energy released down to its lowest).
typedef struct AuditLog
{
	fmWorldId world;
	int substeps;
	int failed; // audits that did not run
	int crossings, selfCrossings, inside, inverted;
	fmBodyId bodies[100];
	int bodyCount;
	double start, highest, startKinetic, startPotential, lowestPotential;
} AuditLog;

// The listed bodies' kinetic plus elastic energy less their start and the work done on them (J),
// with their kinetic and gravitational energy.
static double ledgerExcess(const AuditLog* log, double* kinetic, double* potential)
{
	*kinetic = *potential = 0.0;
	double excess = 0.0;
	for (int b = 0; b < log->bodyCount; ++b)
	{
		fmBodyStats st = fmBody_GetStats(log->bodies[b]);
		*kinetic += st.kineticEnergy;
		*potential += st.gravityEnergy;
		excess += st.kineticEnergy + st.elasticEnergy - st.initialEnergy - st.work;
	}
	return excess;
}

// Watch the energy of @p count bodies from now on (auditFrame after every frame): it may never
// exceed the start plus the work done by more than 0.5% of the drop's energy (checkClean);
// barriers and friction only store or take energy.
static void auditEnergyFrom(AuditLog* log, const fmBodyId* bodies, int count)
{
	log->bodyCount = count;
	for (int b = 0; b < count; ++b)
		log->bodies[b] = bodies[b];
	log->start = ledgerExcess(log, &log->startKinetic, &log->startPotential);
	log->highest = log->start;
	log->lowestPotential = log->startPotential;
}

static void auditSubstep(int substep, double time, void* context)
{
	(void)substep, (void)time;
	AuditLog* log = context;
	fmContactAudit a;
	log->substeps += 1;
	if (fmWorld_AuditContact(log->world, &a) != fm_ok)
	{
		log->failed += 1;
		return;
	}
	log->crossings = a.crossings > log->crossings ? a.crossings : log->crossings;
	log->selfCrossings =
	    a.selfCrossings > log->selfCrossings ? a.selfCrossings : log->selfCrossings;
	log->inside = a.verticesInside > log->inside ? a.verticesInside : log->inside;
	log->inverted = a.invertedTets > log->inverted ? a.invertedTets : log->inverted;
}

// The energy law after a frame (the ledgers book a frame's work at its end).
static void auditFrame(AuditLog* log)
{
	double kinetic, potential, e = ledgerExcess(log, &kinetic, &potential);
	log->highest = fmax(log->highest, e);
	log->lowestPotential = fmin(log->lowestPotential, potential);
}

static fmWorldId auditedWorld(fmWorldDef* wdef, AuditLog* log)
{
	memset(log, 0, sizeof *log);
	wdef->substepCallback = auditSubstep;
	wdef->substepContext = log;
	log->world = fmCreateWorld(wdef);
	return log->world;
}

static void checkClean(int* failures_, const AuditLog* log, const char* what)
{
	printf("  %s: %d substeps audited: at worst %d crossings, %d self crossings, %d vertices "
	       "inside, %d inverted tets\n",
	       what, log->substeps, log->crossings, log->selfCrossings, log->inside, log->inverted);
	CHECK(log->substeps > 0);
	CHECK_INT(log->failed, 0);
	CHECK_INT(log->crossings, 0);
	CHECK_INT(log->selfCrossings, 0);
	CHECK_INT(log->inside, 0);
	CHECK_INT(log->inverted, 0);
	if (log->bodyCount > 0)
	{
		double drop = log->startKinetic + fmax(0.0, log->startPotential - log->lowestPotential);
		printf("  %s: energy at most %+.3g J above the start plus the work done (%.3g%% of the "
		       "drop's %.4g J)\n",
		       what, log->highest - log->start, 100.0 * (log->highest - log->start) / drop, drop);
		CHECK(drop > 0.0);
		CHECK(log->highest - log->start <= 0.005 * drop);
	}
}

static double centreY(fmBodyId body)
{
	int n = fmBody_GetVertexCount(body);
	const double* x = fmTestPositions(body);
	double sum = 0.0;
	for (int i = 0; i < n; ++i)
		sum += x[3 * i + 1];
	return sum / n;
}

// The barrier tests' world: implicit at the game tolerance, the floor at y = 0, Coulomb friction
// 0.5 on the floor and between bodies.
static fmWorldDef barrierWorldDef(void)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.tolerance = FM_TOLERANCE_GAME;
	wdef.floor.height = 0.0;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.floor.frictionCoefficient = 0.5;
	wdef.contact.friction = 0.5;
	return wdef;
}

// The stacks' houses: @p model at Young's modulus @p youngs (Poisson 0.3), 100 kg/m^3, no velocity
// damping or smoothing.
static fmBodyDef stackHouseDef(fmMaterialModel model, double youngs)
{
	fmBodyDef def = softDef(youngs);
	def.material = fmMakeMaterial(model, youngs, 0.3);
	def.density = 100.0;
	def.damping = 1.0;
	def.smoothing = 0.0;
	return def;
}

// Two boxes made touching (the upper one's bottom face on the lower one's top, gap 0) in the air,
// the upper one pushed sideways at 0.3 m/s after the first frame: the barrier's CCD lets a pair at
// distance 0 move no more than a tenth of it, so both stood frozen in the air with every solve
// stalled. Now the first step stands still, the contact stage finds the pair touching
// (FM_BARRIER_TOUCHING) and parts it at the depenetration speed, and the boxes fall, slide and land
// under the barrier: every substep audited, the solve stalled in the first frame only, the upper
// box carried on above the lower one.
TEST(barrier_bodies_made_touching_part_and_fall)
{
	fmWorldDef wdef = barrierWorldDef();
	AuditLog log;
	fmWorldId world = auditedWorld(&wdef, &log);
	fmBodyDef def = stackHouseDef(fm_neoHookean, 1e5);
	fmBodyId low = addBox(failures_, world, 2, fmMakeVec3(0, 2, 0), fmMakeVec3(1, 3, 1), &def);
	fmBodyId up = addBox(failures_, world, 2, fmMakeVec3(0, 3, 0), fmMakeVec3(1, 4, 1), &def);
	const fmBodyId both[2] = {low, up};
	auditEnergyFrom(&log, both, 2);
	int stalled = 0, lastStalled = -1;
	for (int frame = 0; frame < 90; ++frame)
	{
		CHECK_INT(fmWorld_Step(world, 1.0 / 60.0, 1), fm_ok);
		fmStepStats st = fmWorld_GetStepStats(world);
		stalled += st.unconvergedSteps;
		lastStalled = st.unconvergedSteps > 0 ? frame : lastStalled;
		auditFrame(&log);
		if (frame == 0) // (the first step stands still: a velocity given before it is lost)
			fmBody_ApplyImpulse(up, fmMakeVec3(0.3, 0.0, 0.0));
	}
	double lowY = centreY(low), upY = centreY(up), upX = meanPosition(up).x;
	printf("  %d steps stalled (the last in frame %d); centres at y = %.3f and %.3f m, the upper "
	       "box %.3f m along x\n",
	       stalled, lastStalled + 1, lowY, upY, upX);
	checkClean(failures_, &log, "touching boxes");
	CHECK(lastStalled <= 0);
	CHECK(lowY < 0.6);       // landed (from 2.5 m)
	CHECK(upY > lowY + 0.8); // still on top
	CHECK(upX > 0.6);        // slid off its start (0.5) at first, friction slowing it
	fmDestroyWorld(world);
}

// Three Neo-Hookean houses (E = 200 kPa) dropped 0.5 m apart on a Coulomb floor, implicit at one
// step a 1/60 s frame: aligned, and each offset from the one below (0.3 m, then 0.5 m the other
// way: up to 12.5% of the 4 m width). Every substep is audited: no crossing, no vertex inside
// another house, no inverted tet; the aligned stack keeps its order, each house above the last.
// (Measured for the offset stack: the top house tilts off the middle one's roof overhang by
// 1.25 s: docs/contact.md, "Limits".)
TEST(barrier_stacks_of_three_houses_never_cross)
{
	const double offsets[2][3] = {{0.0, 0.0, 0.0}, {0.0, 0.3, -0.2}};
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = barrierWorldDef();
		AuditLog log;
		fmWorldId world = auditedWorld(&wdef, &log);
		fmBodyDef def = stackHouseDef(fm_neoHookean, 2e5);
		fmBodyId houses[3];
		for (int h = 0; h < 3; ++h)
			houses[h] =
			    addHouse(failures_, world, fmMakeVec3(offsets[k][h], 2.0 + 4.5 * h, 0.0), &def);
		auditEnergyFrom(&log, houses, 3);
		int failed = 0, frames = fmTestCount(180, 40);
		for (int f = 0; f < frames; ++f)
		{
			failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
			auditFrame(&log);
		}
		double y[3] = {centreY(houses[0]), centreY(houses[1]), centreY(houses[2])};
		printf("  %s stack after %d frames: centres at y = %.3f %.3f %.3f, %d refused frames\n",
		       k ? "offset" : "aligned", frames, y[0], y[1], y[2], failed);
		checkClean(failures_, &log, k ? "offset" : "aligned");
		CHECK_INT(failed, 0);
		if (k == 0)
			CHECK(y[0] < y[1] - 3.0 && y[1] < y[2] - 3.0);
		fmDestroyWorld(world);
	}
}

// The aligned stack of three houses above, settled (14 s: the stack's slow bounce on its soft
// barriers decays over seconds): the floor carries the three houses' weight within 1% (its force
// averaged over the last second, fmCollider_GetContactForce), each house still on the one below;
// with sleeping on, all three fall asleep, still stacked.
TEST(barrier_stack_rests_on_its_weight_and_sleeps)
{
	for (int sleep = 0; sleep < 2; ++sleep)
	{
		fmWorldDef wdef = barrierWorldDef();
		wdef.contact.enableSleep = sleep == 1;
		fmWorldId world = fmCreateWorld(&wdef);
		fmBodyDef def = stackHouseDef(fm_neoHookean, 2e5);
		fmBodyId houses[3];
		double weight = 0.0, carried = 0.0;
		for (int h = 0; h < 3; ++h)
		{
			houses[h] = addHouse(failures_, world, fmMakeVec3(0.0, 2.0 + 4.5 * h, 0.0), &def);
			const double* m = fmBody_GetMasses(houses[h]);
			for (int i = 0; i < fmBody_GetVertexCount(houses[h]); ++i)
				weight += 9.8 * m[i];
		}
		const int frames = 840, averaged = 60;
		int failed = 0;
		for (int f = 0; f < frames; ++f)
		{
			failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
			fmVec3 force, torque;
			fmCollider_GetContactForce(fmWorld_GetFloorCollider(world), &force, &torque);
			if (f >= frames - averaged)
				carried -= force.y / averaged;
		}
		double y[3] = {centreY(houses[0]), centreY(houses[1]), centreY(houses[2])};
		CHECK_INT(failed, 0);
		CHECK(y[0] < y[1] - 3.0 && y[1] < y[2] - 3.0);
		if (sleep)
		{
			int awake = 0;
			for (int h = 0; h < 3; ++h)
				awake += fmBody_IsAwake(houses[h]);
			printf("  with sleeping: %d of 3 awake after %d frames, centres at %.3f %.3f %.3f\n",
			       awake, frames, y[0], y[1], y[2]);
			CHECK_INT(awake, 0);
		}
		else
		{
			printf(
			    "  the floor carries %.1f N of the houses' %.1f N (%+.3f%%) over the last second\n",
			    carried, weight, 100.0 * (carried - weight) / weight);
			CHECK_REL(carried, weight, 0.01, 0.0);
		}
		fmDestroyWorld(world);
	}
}

// Three houses dropped 0.5 m apart, each offset from the one below (0.3 m, then 0.2 m the other
// way: up to 12.5% of the 4 m width), Neo-Hookean and StVK at E = 5 MPa, with sleeping on, every
// substep audited: they keep their order, each on the one below, and all three are asleep at
// 10 s. (The 200 kPa houses above and the seeds' own houses topple from the same offsets: three
// of them stand at about their column's buckling height, docs/contact.md "Limits".)
// FEMTO_TEST_QUICK: 45 frames, the audits alone.
TEST(barrier_offset_stacks_of_three_rest_and_sleep)
{
	const fmMaterialModel models[2] = {fm_neoHookean, fm_stvk};
	const int frames = fmTestCount(600, 45);
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = barrierWorldDef();
		wdef.contact.enableSleep = true;
		AuditLog log;
		fmWorldId world = auditedWorld(&wdef, &log);
		fmBodyDef def = stackHouseDef(models[k], 5e6);
		const double offsets[3] = {0.0, 0.3, -0.2};
		fmBodyId houses[3];
		for (int h = 0; h < 3; ++h)
			houses[h] =
			    addHouse(failures_, world, fmMakeVec3(offsets[h], 2.0 + 4.5 * h, 0.0), &def);
		auditEnergyFrom(&log, houses, 3);
		int failed = 0;
		for (int f = 0; f < frames; ++f)
		{
			failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
			auditFrame(&log);
		}
		double y[3] = {centreY(houses[0]), centreY(houses[1]), centreY(houses[2])};
		int awake =
		    fmBody_IsAwake(houses[0]) + fmBody_IsAwake(houses[1]) + fmBody_IsAwake(houses[2]);
		const char* what = k ? "StVK, offset" : "Neo-Hookean, offset";
		printf("  %s: after %d frames centres at y = %.3f %.3f %.3f, %d awake\n", what, frames,
		       y[0], y[1], y[2], awake);
		checkClean(failures_, &log, what);
		CHECK_INT(failed, 0);
		CHECK(y[0] < y[1] - 3.0 && y[1] < y[2] - 3.0);
		if (frames == 600)
			CHECK_INT(awake, 0);
		fmDestroyWorld(world);
	}
}

// Ten Neo-Hookean houses (E = 20 MPa: a 40 m column of the 200 kPa houses above buckles under its
// own weight, docs/contact.md "Stacks") dropped 0.5 m apart on a Coulomb floor, implicit at one
// step a 1/60 s frame, every substep audited: aligned, the floor carries their weight within 1%
// over the 14th second; each house offset from the one below by 15% of the 4 m width (0.36 m
// one way, 0.24 m the other), with sleeping on, all ten asleep at 14 s. Both keep their order,
// each house on the one below. (FEMTO_TEST_QUICK: 45 frames, the audits alone.)
TEST(barrier_stacks_of_ten_houses_rest_and_sleep)
{
	const int frames = fmTestCount(840, 45), averaged = 60;
	for (int k = 0; k < 2; ++k)
	{
		fmWorldDef wdef = barrierWorldDef();
		wdef.contact.enableSleep = k == 1;
		AuditLog log;
		fmWorldId world = auditedWorld(&wdef, &log);
		fmBodyDef def = stackHouseDef(fm_neoHookean, 2e7);
		fmBodyId houses[10];
		double weight = 0.0, carried = 0.0;
		for (int h = 0; h < 10; ++h)
		{
			double x = k == 0 || h == 0 ? 0.0 : h % 2 ? 0.36 : -0.24;
			houses[h] = addHouse(failures_, world, fmMakeVec3(x, 2.0 + 4.5 * h, 0.0), &def);
			const double* m = fmBody_GetMasses(houses[h]);
			for (int i = 0; i < fmBody_GetVertexCount(houses[h]); ++i)
				weight += 9.8 * m[i];
		}
		auditEnergyFrom(&log, houses, 10);
		int failed = 0;
		for (int f = 0; f < frames; ++f)
		{
			failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
			auditFrame(&log);
			fmVec3 force, torque;
			fmCollider_GetContactForce(fmWorld_GetFloorCollider(world), &force, &torque);
			if (f >= frames - averaged)
				carried -= force.y / averaged;
		}
		int stacked = 0, awake = 0;
		for (int h = 0; h < 10; ++h)
		{
			awake += fmBody_IsAwake(houses[h]);
			stacked += h == 0 || centreY(houses[h]) > centreY(houses[h - 1]) + 3.0;
		}
		const char* what = k ? "offset, sleeping on" : "aligned";
		printf("  %s: after %d frames %d of 10 houses each on the last, the top at y = %.3f, %d "
		       "awake\n",
		       what, frames, stacked, centreY(houses[9]), awake);
		if (k == 0)
			printf("  the floor carries %.1f N of the houses' %.1f N (%+.3f%%) over the last "
			       "second\n",
			       carried, weight, 100.0 * (carried - weight) / weight);
		checkClean(failures_, &log, what);
		CHECK_INT(failed, 0);
		CHECK_INT(stacked, 10);
		if (frames == 840 && k == 0)
			CHECK_REL(carried, weight, 0.01, 0.0);
		if (frames == 840 && k == 1)
			CHECK_INT(awake, 0);
		fmDestroyWorld(world);
	}
}

// femto bench's piles of ten houses (the seeds' mesh and mass, Neo-Hookean at Lame 20 kPa and
// 5 kPa, stacked 4.2 m apart, every other one shifted 0.4 m and 0.3 m so that the column topples
// into a pile), @p columns of them side by side 8 m apart along z, implicit at one step a 1/60 s
// frame to the game tolerance on a Coulomb floor, every substep audited: no crossing, no vertex
// inside another house, no inverted tet, no energy gained, no refused frame.
static void auditedPiles(int* failures_, int columns, int frames, const char* what)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.tolerance = FM_TOLERANCE_GAME;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.floor.frictionCoefficient = 0.5;
	wdef.maxBodies = 10 * columns;
	AuditLog log;
	fmWorldId world = auditedWorld(&wdef, &log);
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fmMakeMaterialLame(fm_neoHookean, 20000.0, 5000.0);
	def.damping = 1.0;
	def.smoothing = 0.0;
	fmBodyId houses[100];
	for (int i = 0; i < 10 * columns; ++i)
	{
		int h = i % 10;
		double z = 8.0 * (i / 10) + ((h / 2) % 2 ? 0.3 : -0.3);
		houses[i] = addHouse(failures_, world, fmMakeVec3(h % 2 ? 0.4 : -0.4, 4.2 * h, z), &def);
	}
	auditEnergyFrom(&log, houses, 10 * columns);
	int failed = 0;
	for (int f = 0; f < frames; ++f)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		auditFrame(&log);
	}
	double top = 0.0;
	for (int i = 0; i < 10 * columns; ++i)
		top = fmax(top, centreY(houses[i]));
	printf("  %s: after %d frames the highest centre at y = %.3f, %d refused frames\n", what,
	       frames, top, failed);
	checkClean(failures_, &log, what);
	CHECK_INT(failed, 0);
	fmDestroyWorld(world);
}

// One pile for 5 s: the top house falls 38 m in 2.8 s, then the pile settles.
// (FEMTO_TEST_QUICK: 1 s.)
TEST(barrier_ten_house_pile_never_crosses)
{
	auditedPiles(failures_, 1, fmTestCount(300, 60), "ten-house pile");
}

// femto bench's hundred houses (139k tets): ten piles side by side for 2 s, the first three or
// four houses of each landed on each other (the whole 5 s, 161 s of a core, is audited by hand:
// docs/contact.md, Limits). (FEMTO_TEST_QUICK: 3 frames.)
TEST(barrier_hundred_house_pile_never_crosses)
{
	auditedPiles(failures_, 10, fmTestCount(120, 3), "hundred-house pile");
}

// Issue 29's fast impacts, both integrators (explicit: autoSubstep), every substep audited (no
// crossing, no vertex inside, no inverted tet, no energy gained, no refused frame), 0.2 s: a
// 1 cm plate (0.6 m square, Neo-Hookean E = 10 MPa, 1000 kg/m^3) at 30 m/s onto a 1 cm box
// collider and onto a free 1 cm plate, and a 0.2 m box at 44.3 m/s (a 100 m fall) onto the
// 1 cm collider; the mover ends on its side of what it hit. (FEMTO_TEST_QUICK: 4 frames, the
// impacts are in the first.)
static void fastImpact(int* failures_, fmIntegrator integrator, int scene)
{
	static const char* const names[3] = {"plate at 30 m/s onto a 1 cm box collider",
	                                     "plate at 30 m/s onto a free 1 cm plate",
	                                     "box after a 100 m fall onto a 1 cm box collider"};
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = integrator;
	wdef.autoSubstep = integrator == fm_explicit;
	wdef.floor.enabled = false;
	wdef.gravity = fmMakeVec3(0.0, scene == 2 ? -9.8 : 0.0, 0.0);
	AuditLog log;
	fmWorldId world = auditedWorld(&wdef, &log);
	fmBodyDef def = fmDefaultBodyDef();
	def.material = fmMakeMaterial(fm_neoHookean, 1e7, 0.3);
	def.massMode = fm_massFromDensity;
	def.density = 1000.0;
	def.smoothing = 0.0;
	def.damping = 1.0;
	if (scene != 1)
	{
		fmColliderDef c = fmDefaultColliderDef();
		c.shape = fm_shapeBox;
		c.center = fmMakeVec3(0.0, -0.005, 0.0);
		c.halfExtents = fmMakeVec3(0.5, 0.005, 0.5);
		fmColliderId id;
		CHECK_INT(fmCreateCollider(world, &c, &id, NULL), fm_ok);
	}
	fmBodyId bodies[2];
	int count = 0;
	if (scene == 1)
		bodies[count++] = addBox(failures_, world, 1, fmMakeVec3(-0.3, -0.01, -0.3),
		                         fmMakeVec3(0.3, 0.0, 0.3), &def);
	fmTetMesh mesh;
	if (scene == 2)
		CHECK_INT(
		    fmMakeBoxMesh(2, 2, 2, fmMakeVec3(-0.1, 0.05, -0.1), fmMakeVec3(0.1, 0.25, 0.1), &mesh),
		    fm_ok);
	else
		CHECK_INT(
		    fmMakeBoxMesh(6, 1, 6, fmMakeVec3(-0.3, 0.1, -0.3), fmMakeVec3(0.3, 0.11, 0.3), &mesh),
		    fm_ok);
	def.mesh = &mesh;
	CHECK_INT(fmCreateBody(world, &def, &bodies[count], NULL), fm_ok);
	fmFreeTetMesh(&mesh);
	const fmBodyId mover = bodies[count++];
	int n = fmBody_GetVertexCount(mover);
	double* v = calloc(3 * (size_t)n, sizeof(double));
	CHECK(v != NULL);
	for (int i = 0; v != NULL && i < n; ++i)
		v[3 * i + 1] = scene == 2 ? -sqrt(2.0 * 9.8 * 100.0) : -30.0;
	if (v != NULL)
		fmBody_SetVelocities(mover, v);
	free(v);
	auditEnergyFrom(&log, bodies, count);
	const int frames = fmTestCount(12, 4);
	int failed = 0;
	for (int f = 0; f < frames; ++f)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		auditFrame(&log);
	}
	double lowest = fmBody_GetStats(mover).lowestY, top = 0.0;
	if (scene == 1)
	{
		const double* x = fmTestPositions(bodies[0]);
		top = -INFINITY;
		for (int i = 0; i < fmBody_GetVertexCount(bodies[0]); ++i)
			top = fmax(top, x[3 * i + 1]);
	}
	char what[160];
	snprintf(what, sizeof what, "%s, %s", names[scene],
	         integrator == fm_implicit ? "implicit" : "explicit");
	printf("  %s: the mover's lowest point at y = %.4f, the obstacle's top at %.4f\n", what, lowest,
	       top);
	checkClean(failures_, &log, what);
	CHECK_INT(failed, 0);
	CHECK(lowest > top);
	fmDestroyWorld(world);
}

TEST(barrier_fast_impacts_never_cross)
{
	for (int k = 0; k < 6; ++k)
		fastImpact(failures_, k < 3 ? fm_implicit : fm_explicit, k % 3);
}

// Two 2 cm plates closing at 40 m/s, implicit at one step a 1/60 s frame (the step moves each
// 0.33 m, sixteen times their thickness): the line search's collision detection stops every
// step short of the other plate; every substep audited clean, both plates' tets upright.
TEST(barrier_plates_at_40_m_s_never_cross)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
	wdef.floor.enabled = false;
	AuditLog log;
	fmWorldId world = auditedWorld(&wdef, &log);
	fmBodyDef def = softDef(1e7);
	def.density = 1000.0;
	fmBodyId plates[2];
	for (int k = 0; k < 2; ++k)
	{
		double x0 = k ? 0.05 : -0.07;
		fmTetMesh mesh;
		CHECK_INT(fmMakeBoxMesh(1, 6, 6, fmMakeVec3(x0, -0.3, -0.3),
		                        fmMakeVec3(x0 + 0.02, 0.3, 0.3), &mesh),
		          fm_ok);
		def.mesh = &mesh;
		CHECK_INT(fmCreateBody(world, &def, &plates[k], NULL), fm_ok);
		fmFreeTetMesh(&mesh);
		int n = fmBody_GetVertexCount(plates[k]);
		double* v = calloc(3 * (size_t)n, sizeof(double));
		for (int i = 0; i < n; ++i)
			v[3 * i] = k ? -20.0 : 20.0;
		fmBody_SetVelocities(plates[k], v);
		free(v);
	}
	auditEnergyFrom(&log, plates, 2);
	int failed = 0;
	for (int f = 0; f < 30; ++f)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		auditFrame(&log);
	}
	checkClean(failures_, &log, "plates");
	CHECK_INT(failed, 0);
	fmDestroyWorld(world);
}

// The folding bar: box:2,40,2 (E = 30 kPa, 1000 kg/m^3, 4 m) stood on its end 5 cm above the
// floor, self-collision on, nudged sideways at 0.3 m/s (the buckling's direction).
static fmBodyId addFoldingBar(int* failures_, fmWorldId world)
{
	fmBodyId none = {0, 0, 0, 0};
	fmBodyDef def = softDef(3e4);
	def.density = 1000.0;
	def.selfCollision = true;
	fmTetMesh mesh;
	if (fmMakeBoxMesh(2, 40, 2, fmMakeVec3(-0.1, 0.05, -0.1), fmMakeVec3(0.1, 4.05, 0.1), &mesh) !=
	    fm_ok)
		return none;
	def.mesh = &mesh;
	fmBodyId bar;
	fmResult r = fmCreateBody(world, &def, &bar, NULL);
	CHECK_INT(r, fm_ok);
	fmFreeTetMesh(&mesh);
	if (r != fm_ok)
		return none;
	int n = fmBody_GetVertexCount(bar);
	double* v = calloc(3 * (size_t)n, sizeof(double));
	for (int i = 0; v != NULL && i < n; ++i)
		v[3 * i] = 0.3;
	fmBody_SetVelocities(bar, v);
	free(v);
	return bar;
}

// A soft bar (box:2,40,2, E = 30 kPa, 4 m) stood on its end with self-collision on buckles and
// folds onto itself: implicit at 1/60 s, every substep audited, no self crossing, no inverted
// tet, every frame finite.
TEST(barrier_folding_bar_never_crosses_itself)
{
	fmWorldDef wdef = barrierWorldDef();
	AuditLog log;
	fmWorldId world = auditedWorld(&wdef, &log);
	fmBodyId bar = addFoldingBar(failures_, world);
	auditEnergyFrom(&log, &bar, 1);
	int failed = 0, frames = fmTestCount(240, 60);
	for (int f = 0; f < frames; ++f)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		auditFrame(&log);
	}
	printf("  the bar's centre at y = %.3f after %d frames (4.05 m tall at the start)\n",
	       centreY(bar), frames);
	checkClean(failures_, &log, "folding bar");
	CHECK_INT(failed, 0);
	CHECK(centreY(bar) < 1.5); // it fell and folded
	fmDestroyWorld(world);
}

// The crush's log: the audit's, and the deepest any vertex of the box reached past the press's
// lower face (negative: it stayed below it), over every substep.
typedef struct CrushLog
{
	AuditLog audit;
	fmBodyId box;
	fmColliderId press;
	double pressHalfHeight, past, lowest;
} CrushLog;

static void crushSubstep(int substep, double time, void* context)
{
	CrushLog* log = context;
	auditSubstep(substep, time, &log->audit);
	double face = fmCollider_GetPosition(log->press).y - log->pressHalfHeight;
	const double* x = fmTestPositions(log->box);
	for (int i = 0; i < fmBody_GetVertexCount(log->box); ++i)
	{
		log->past = fmax(log->past, x[3 * i + 1] - face);
		log->lowest = fmin(log->lowest, x[3 * i + 1]);
	}
}

// A 0.4 m box (E = 100 kPa) on a Coulomb floor crushed to 12% of its height by a kinematic box
// collider coming down at 0.2 m/s, then held there for a second; implicit at one step a frame and
// explicit (autoSubstep), Neo-Hookean and the seeds' StVK. Every substep: no tet inverted (the
// audit), no vertex past the press's face or below the floor; no refused frame. (Measured before
// the colliders' barrier: 19 and 16 tets inverted implicit, the inversion filter off under the
// collider penalty; explicit StVK flattened 2 corner tets to J = 0 at the floor while its volume
// floor was quadratic, finite at J = 0.)
TEST(barrier_box_crushed_to_12_percent_keeps_every_tet)
{
	const fmMaterialModel models[2] = {fm_neoHookean, fm_stvk};
	// The explicit runs (7,000 to 15,000 audited substeps each) only outside the sanitizers.
	const int runs = fmTestCount(4, 2);
	for (int run = 0; run < runs; ++run)
	{
		int k = run % 2;
		bool explicitRun = run >= 2;
		fmWorldDef wdef = fmDefaultWorldDef();
		wdef.integrator = explicitRun ? fm_explicit : fm_implicit;
		wdef.autoSubstep = explicitRun;
		wdef.floor.height = 0.0;
		wdef.floor.friction = fm_floorCoulomb;
		wdef.floor.frictionCoefficient = 0.5;
		CrushLog log;
		memset(&log, 0, sizeof log);
		log.past = -INFINITY;
		log.lowest = INFINITY;
		wdef.substepCallback = crushSubstep;
		wdef.substepContext = &log;
		log.audit.world = fmCreateWorld(&wdef);
		fmTetMesh mesh;
		CHECK_INT(
		    fmMakeBoxMesh(4, 4, 4, fmMakeVec3(-0.2, 0.0, -0.2), fmMakeVec3(0.2, 0.4, 0.2), &mesh),
		    fm_ok);
		fmBodyDef def = softDef(1e5);
		def.material = fmMakeMaterial(models[k], 1e5, 0.3);
		def.density = 1000.0;
		def.smoothing = 0.0;
		def.mesh = &mesh;
		CHECK_INT(fmCreateBody(log.audit.world, &def, &log.box, NULL), fm_ok);
		fmFreeTetMesh(&mesh);
		fmColliderDef press = fmDefaultColliderDef();
		press.shape = fm_shapeBox;
		press.center = fmMakeVec3(0.0, 0.6, 0.0);
		press.halfExtents = fmMakeVec3(0.5, 0.2, 0.5);
		press.velocity = fmMakeVec3(0.0, -0.352 / 1.76, 0.0); // its face from 0.4 m to 0.048 m
		log.pressHalfHeight = 0.2;
		CHECK_INT(fmCreateCollider(log.audit.world, &press, &log.press, NULL), fm_ok);
		int failed = 0, frames = (int)(1.76 * 60.0 + 0.5);
		for (int f = 0; f < frames + 60; ++f)
		{
			if (f == frames)
				fmCollider_SetVelocity(log.press, fmMakeVec3(0.0, 0.0, 0.0),
				                       fmMakeVec3(0.0, 0.0, 0.0));
			failed += fmWorld_Step(log.audit.world, 1.0 / 60.0, 1) != fm_ok;
		}
		double face = fmCollider_GetPosition(log.press).y - log.pressHalfHeight;
		static const char* const names[4] = {"Neo-Hookean crush, implicit", "StVK crush, implicit",
		                                     "Neo-Hookean crush, explicit", "StVK crush, explicit"};
		printf("  %s: the press's face at %.4f m (%.1f%% of the box's height); at worst a vertex "
		       "%.3g m past it, the lowest %.3g m; %d refused frames\n",
		       names[run], face, 100.0 * face / 0.4, log.past, log.lowest, failed);
		checkClean(failures_, &log.audit, names[run]);
		CHECK(face < 0.0481);
		// Implicit steps keep the box off the face (the colliders' barrier); explicit substeps
		// project a vertex that reached it onto it (to round-off).
		CHECK(log.past < (explicitRun ? 1e-12 : 0.0));
		CHECK(log.lowest >= 0.0);
		CHECK_INT(failed, 0);
		fmDestroyWorld(log.audit.world);
	}
}

// The folding bar of barrier_folding_bar_never_crosses_itself stepped explicit (autoSubstep),
// audited at every substep: no crossing of its surface with itself, no inverted tet, no refused
// frame, its energy never above the start plus the work done by more than 0.5% of the drop's.
// (It blew up at its first self contact, in frame 22, while the stage pushed its own surface back
// out to the thickness at once; then, finite, it ended 4 s with 27 to 35 self crossings and 3 to
// 5 inverted tets, up to 83 and 15 over the substeps, until its own edges met each other as
// different bodies' do.)
TEST(explicit_folding_bar_never_crosses_itself)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.autoSubstep = true;
	wdef.workerCount = 2;
	wdef.floor.height = 0.0;
	wdef.floor.friction = fm_floorCoulomb;
	wdef.floor.frictionCoefficient = 0.5;
	AuditLog log;
	fmWorldId world = auditedWorld(&wdef, &log);
	fmBodyId bar = addFoldingBar(failures_, world);
	auditEnergyFrom(&log, &bar, 1);
	int failed = 0, frames = fmTestCount(240, 60);
	for (int f = 0; f < frames; ++f)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		auditFrame(&log);
	}
	printf("  explicit: the bar's centre at y = %.3f after %d frames\n", centreY(bar), frames);
	checkClean(failures_, &log, "explicit folding bar");
	CHECK_INT(failed, 0);
	CHECK(centreY(bar) < 1.5 || frames < 240);
	fmDestroyWorld(world);
}

// A box made half inside a static box collider (0.2 m of its 0.4 m), implicit, no gravity: the
// colliders' barrier lets each vertex that starts inside stay as deep as it started less the
// depenetration speed's worth a step (its sink, penalty.h), so the box comes out at about that
// speed (1 m/s by default) with every tet upright. (Before the sink: its inside half was pushed
// to the surface in one step, 43 tets inside out and the box stuck flat on the collider; under
// the penalty it was catapulted at 11 m/s.)
// A barrier world looks for vertices caught inside another body only when something outside its
// solves can have put them there (fmContact_BeginFrame). A prescribed displacement is such a
// thing: it drives a small box into a larger one, is cleared, and the caught vertices must come
// out (pushed at the depenetration speed) as they did when every frame looked. A frame that
// skipped the search while the box moved, or after it stopped with vertices still inside, leaves
// them inside for good (the barrier cannot undo a crossing).
TEST(a_box_driven_into_another_comes_out_when_let_go)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.height = 0.0;
	wdef.floor.friction = fm_floorCoulomb;
	fmWorldId world = fmCreateWorld(&wdef);
	fmBodyDef def = softDef(1e5);
	fmBodyId base =
	    addBox(failures_, world, 4, fmMakeVec3(-0.2, 0.0, -0.2), fmMakeVec3(0.2, 0.4, 0.2), &def);
	fmBodyId top =
	    addBox(failures_, world, 2, fmMakeVec3(-0.1, 0.5, -0.1), fmMakeVec3(0.1, 0.7, 0.1), &def);
	CHECK(fmBody_IsValid(base) && fmBody_IsValid(top));
	// Every vertex of the small box, 0.25 m down over 0.25 s: its bottom 0.15 m into the base.
	CHECK_INT(fmBody_PrescribeDisplacement(top, fmMakeVec3(-1.0, 0.45, -1.0),
	                                       fmMakeVec3(1.0, 0.75, 1.0), 7,
	                                       fmMakeVec3(0.0, -0.25, 0.0), 0.25),
	          27);
	int failed = 0, mostInside = 0;
	fmContactAudit audit;
	memset(&audit, 0, sizeof audit);
	for (int f = 0; f < 20; ++f)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		CHECK_INT(fmWorld_AuditContact(world, &audit), fm_ok);
		mostInside = audit.verticesInside > mostInside ? audit.verticesInside : mostInside;
	}
	fmBody_ClearLoads(top);
	for (int i = 0; i < fmBody_GetVertexCount(top); ++i)
		fmBody_SetPinned(top, i, false);
	int frames = 0;
	for (; frames < 240 && (audit.verticesInside > 0 || audit.crossings > 0); ++frames)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		CHECK_INT(fmWorld_AuditContact(world, &audit), fm_ok);
	}
	printf("  driven in: up to %d vertices inside; let go, out after %d frames (%d inside, %d "
	       "crossings), %d refused frames\n",
	       mostInside, frames, audit.verticesInside, audit.crossings, failed);
	CHECK(mostInside > 0); // (the press did put vertices inside: the search had work)
	CHECK_INT(audit.verticesInside, 0);
	CHECK_INT(audit.crossings, 0);
	CHECK_INT(failed, 0);
	fmDestroyWorld(world);
}

TEST(body_made_inside_a_collider_comes_out_at_the_depenetration_speed)
{
	fmWorldDef wdef = fmDefaultWorldDef();
	wdef.integrator = fm_implicit;
	wdef.floor.enabled = false;
	wdef.gravity = fmMakeVec3(0.0, 0.0, 0.0);
	fmWorldId world = fmCreateWorld(&wdef);
	fmColliderDef slab = fmDefaultColliderDef();
	slab.shape = fm_shapeBox;
	slab.center = fmMakeVec3(0.0, -0.3, 0.0);
	slab.halfExtents = fmMakeVec3(1.0, 0.5, 1.0); // its top at y = 0.2
	fmColliderId id;
	CHECK_INT(fmCreateCollider(world, &slab, &id, NULL), fm_ok);
	fmBodyDef def = softDef(1e5);
	def.density = 1000.0;
	fmBodyId box =
	    addBox(failures_, world, 4, fmMakeVec3(-0.2, 0.0, -0.2), fmMakeVec3(0.2, 0.4, 0.2), &def);
	int n = fmBody_GetVertexCount(box), failed = 0, inverted = 0;
	double fastest = 0.0, lowest = 0.0;
	for (int f = 0; f < 60; ++f)
	{
		failed += fmWorld_Step(world, 1.0 / 60.0, 1) != fm_ok;
		const double* v = fmTestVelocities(box);
		for (int i = 0; i < n; ++i)
			fastest = fmax(fastest, fmLength(fmLoad(v, i)));
		inverted = fmBody_GetStats(box).invertedTets > inverted ? fmBody_GetStats(box).invertedTets
		                                                        : inverted;
		lowest = fmBody_GetStats(box).lowestY;
	}
	printf("  fastest vertex %.2f m/s, at most %d tets inverted, lowest y %.3f after 1 s (the "
	       "collider's top at 0.2), %d refused frames\n",
	       fastest, inverted, lowest, failed);
	CHECK_INT(failed, 0);
	CHECK_INT(inverted, 0);
	CHECK(fastest < 2.0 * wdef.floor.maxDepenetrationSpeed);
	CHECK(lowest > 0.2); // out
	fmDestroyWorld(world);
}
