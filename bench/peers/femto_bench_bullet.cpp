// femto-bench-bullet: Bullet's deformable world (btDeformableMultiBodyDynamicsWorld, implicit
// backward Euler) on the mesh `femto bench` writes, timed the way femto's implicit rows are:
// frames of DT after SETTLE frames of settling, the median of FRAMES timed frames.
//
//   femto-bench-bullet MESH.node MESH.ele LAMBDA MU FLOOR_Y [DT SETTLE FRAMES]
//
// MESH.node holds 0-based points with one attribute, the vertex mass in kg (femto's lumped
// masses); MESH.ele 0-based positively oriented tets. Neo-Hookean force with the Lame constants
// LAMBDA and MU (Pa), gravity -9.8 m/s^2 along y, a static floor whose top is y = FLOOR_Y.
// Prints one line "result: ms_per_frame M blew_up B lowest_y Y max_coordinate C bullet_version V"
// (B is 1 when a coordinate became non-finite or beyond 1e3 m; V is btGetVersion()). Exit status 0
// with a result, 1 for a bad input file, 2 for bad arguments. Built only when Bullet is found
// (bench/peers/CMakeLists.txt); never a dependency of the library or the femto tool.
#include <BulletSoftBody/btDeformableBodySolver.h>
#include <BulletSoftBody/btDeformableGravityForce.h>
#include <BulletSoftBody/btDeformableMultiBodyConstraintSolver.h>
#include <BulletSoftBody/btDeformableMultiBodyDynamicsWorld.h>
#include <BulletSoftBody/btDeformableNeoHookeanForce.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyHelpers.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

namespace
{

struct Arguments
{
	const char* nodePath = nullptr;
	const char* elePath = nullptr;
	double lambda = 0, mu = 0, floorY = 0;
	double dt = 1.0 / 60.0;
	int settle = 60;
	int frames = 5;
};

bool parseNumber(const char* text, double* value)
{
	char* end = nullptr;
	*value = std::strtod(text, &end);
	return end != text && *end == '\0' && std::isfinite(*value);
}

bool parseArguments(int argc, char** argv, Arguments* a)
{
	if (argc != 6 && argc != 9)
		return false;
	a->nodePath = argv[1];
	a->elePath = argv[2];
	double settle = a->settle, frames = a->frames;
	bool ok = parseNumber(argv[3], &a->lambda) && parseNumber(argv[4], &a->mu) &&
	          parseNumber(argv[5], &a->floorY);
	if (ok && argc == 9)
		ok = parseNumber(argv[6], &a->dt) && parseNumber(argv[7], &settle) &&
		     parseNumber(argv[8], &frames);
	a->settle = (int)settle;
	a->frames = (int)frames;
	return ok && a->mu > 0 && a->dt > 0 && a->settle >= 0 && a->frames >= 1 &&
	       a->frames <= 100000 && a->settle <= 100000;
}

// The whole file, NUL-terminated and ending in a newline (Bullet's TetGen reader walks lines).
bool readText(const char* path, std::string* text)
{
	std::ifstream in(path, std::ios::binary);
	if (!in)
		return false;
	std::ostringstream buffer;
	buffer << in.rdbuf();
	*text = buffer.str();
	if (text->empty() || text->back() != '\n')
		text->push_back('\n');
	return true;
}

// The first attribute of every point of a .node file: femto's vertex masses.
bool readMasses(const std::string& node, std::vector<double>* masses)
{
	std::istringstream in(node);
	int count = 0, dimensions = 0, attributes = 0, markers = 0;
	if (!(in >> count >> dimensions >> attributes >> markers) || dimensions != 3 ||
	    attributes < 1 || count < 4)
		return false;
	masses->assign((size_t)count, 0.0);
	for (int i = 0; i < count; ++i)
	{
		int index = -1;
		double x, y, z, mass;
		std::string rest;
		if (!(in >> index >> x >> y >> z >> mass) || index < 0 || index >= count || !(mass > 0))
			return false;
		std::getline(in, rest);
		(*masses)[(size_t)index] = mass;
	}
	return true;
}

// Bullet's world and what it uses, deleted in reverse order of declaration.
struct World
{
	btSoftBodyRigidBodyCollisionConfiguration configuration;
	btCollisionDispatcher dispatcher{&configuration};
	btDbvtBroadphase broadphase;
	btDeformableBodySolver bodySolver;
	btDeformableMultiBodyConstraintSolver constraintSolver;
	std::unique_ptr<btBoxShape> floorShape;
	std::unique_ptr<btDefaultMotionState> floorMotion;
	std::unique_ptr<btRigidBody> floor;
	std::unique_ptr<btDeformableGravityForce> gravity;
	std::unique_ptr<btDeformableNeoHookeanForce> elasticity;
	// Declared last, destroyed first: the world goes before what it points to.
	std::unique_ptr<btDeformableMultiBodyDynamicsWorld> world;
	btSoftBody* body = nullptr;

	~World()
	{
		if (body != nullptr)
		{
			world->removeSoftBody(body);
			delete body;
		}
		if (floor)
			world->removeRigidBody(floor.get());
	}
};

void addFloor(World* w, double floorY)
{
	// A static box whose top face is the floor plane (the sparse SDF needs a convex shape).
	w->floorShape.reset(new btBoxShape(btVector3(500, 50, 500)));
	btTransform placement;
	placement.setIdentity();
	placement.setOrigin(btVector3(0, btScalar(floorY - 50.0), 0));
	w->floorMotion.reset(new btDefaultMotionState(placement));
	btRigidBody::btRigidBodyConstructionInfo info(0, w->floorMotion.get(), w->floorShape.get());
	w->floor.reset(new btRigidBody(info));
	w->floor->setFriction(1);
	w->world->addRigidBody(w->floor.get());
}

bool buildWorld(const Arguments& a, const std::string& node, const std::string& ele,
                const std::vector<double>& masses, World* w)
{
	w->constraintSolver.setDeformableSolver(&w->bodySolver);
	w->world.reset(new btDeformableMultiBodyDynamicsWorld(
	    &w->dispatcher, &w->broadphase, &w->constraintSolver, &w->configuration, &w->bodySolver));
	btVector3 g(0, btScalar(-9.8), 0);
	w->world->setGravity(g);
	btSoftBodyWorldInfo& info = w->world->getWorldInfo();
	info.m_gravity = g;
	info.m_sparsesdf.setDefaultVoxelsz(0.25);
	info.m_sparsesdf.Reset();
	addFloor(w, a.floorY);

	w->body = btSoftBodyHelpers::CreateFromTetGenData(info, ele.c_str(), nullptr, node.c_str(),
	                                                  false, true, true);
	if (w->body == nullptr || w->body->m_nodes.size() != (int)masses.size())
		return false;
	w->world->addSoftBody(w->body);
	for (size_t i = 0; i < masses.size(); ++i)
		w->body->setMass((int)i, btScalar(masses[i]));
	w->body->getCollisionShape()->setMargin(btScalar(0.01));
	w->body->m_cfg.kKHR = 1;
	w->body->m_cfg.kCHR = 1;
	w->body->m_cfg.kDF = 1;
	w->body->m_cfg.collisions = btSoftBody::fCollision::SDF_RD | btSoftBody::fCollision::SDF_RDN;
	w->body->m_sleepingThreshold = 0; // never deactivate: a resting body must still be stepped
	w->body->setActivationState(DISABLE_DEACTIVATION);
	btSoftBodyHelpers::generateBoundaryFaces(w->body);
	w->gravity.reset(new btDeformableGravityForce(g));
	w->world->addForce(w->body, w->gravity.get());
	w->elasticity.reset(new btDeformableNeoHookeanForce(btScalar(a.mu), btScalar(a.lambda)));
	w->world->addForce(w->body, w->elasticity.get());
	w->world->setImplicit(true);
	w->world->setLineSearch(false);
	w->world->setUseProjection(true);
	return true;
}

// Lowest y and largest |coordinate|; false once a coordinate is not finite or beyond 1e3 m.
bool healthy(const btSoftBody* body, double* lowest, double* largest)
{
	*lowest = INFINITY;
	*largest = 0;
	for (int i = 0; i < body->m_nodes.size(); ++i)
		for (int axis = 0; axis < 3; ++axis)
		{
			double x = body->m_nodes[i].m_x[axis];
			if (!std::isfinite(x))
			{
				*largest = INFINITY;
				return false;
			}
			*largest = std::max(*largest, std::fabs(x));
			if (axis == 1)
				*lowest = std::min(*lowest, x);
		}
	return *largest <= 1e3;
}

} // namespace

int main(int argc, char** argv)
{
	Arguments a;
	if (!parseArguments(argc, argv, &a))
	{
		std::fprintf(stderr, "usage: femto-bench-bullet MESH.node MESH.ele LAMBDA MU FLOOR_Y "
		                     "[DT SETTLE FRAMES]\n");
		return 2;
	}
	std::string node, ele;
	std::vector<double> masses;
	if (!readText(a.nodePath, &node) || !readText(a.elePath, &ele))
	{
		std::fprintf(stderr, "femto-bench-bullet: cannot read %s or %s\n", a.nodePath, a.elePath);
		return 1;
	}
	if (!readMasses(node, &masses))
	{
		std::fprintf(stderr,
		             "%s: expected 0-based 3D points with a positive mass as first attribute\n",
		             a.nodePath);
		return 1;
	}
	World w;
	if (!buildWorld(a, node, ele, masses, &w))
	{
		std::fprintf(stderr, "femto-bench-bullet: Bullet did not build the body\n");
		return 1;
	}
	double lowest = 0, largest = 0;
	bool ok = true;
	for (int frame = 0; ok && frame < a.settle; ++frame)
	{
		w.world->stepSimulation(btScalar(a.dt), 1, btScalar(a.dt));
		ok = healthy(w.body, &lowest, &largest);
	}
	std::vector<double> seconds;
	for (int frame = 0; ok && frame < a.frames; ++frame)
	{
		auto start = std::chrono::steady_clock::now();
		w.world->stepSimulation(btScalar(a.dt), 1, btScalar(a.dt));
		std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
		seconds.push_back(elapsed.count());
		ok = healthy(w.body, &lowest, &largest);
	}
	double median = 0;
	if (!seconds.empty())
	{
		std::sort(seconds.begin(), seconds.end());
		size_t n = seconds.size();
		median = n % 2 ? seconds[n / 2] : 0.5 * (seconds[n / 2 - 1] + seconds[n / 2]);
	}
	std::printf("result: ms_per_frame %.4f blew_up %d lowest_y %.6g max_coordinate %.6g "
	            "bullet_version %d\n",
	            1e3 * median, ok ? 0 : 1, lowest, largest, btGetVersion());
	return 0;
}
