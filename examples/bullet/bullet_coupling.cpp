// Two-way coupling of femto's soft bodies with Bullet's rigid bodies (docs/embedding.md,
// "Two-way coupling with a rigid-body engine").
//
//   bullet_coupling cushion   a rigid box dropped on a soft cushion comes to rest on it
//   bullet_coupling seesaw    a soft house tips a rigid seesaw on a torsion spring
//   bullet_coupling ball      a rigid ball bounces off a free soft pad in zero gravity
//
// Each frame, in this order: (1) every rigid body's pose and velocities drive its femto
// collider; (2) femto steps the frame; (3) the force and torque the soft bodies put on each
// collider over that frame go to its rigid body; (4) Bullet steps the same frame. Each scene
// prints its measurements and exits 0 only when its physical checks hold.
#include <btBulletDynamicsCommon.h>
#include <femto/femto.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <vector>

namespace
{

constexpr double kFrame = 1.0 / 60.0; // both engines step this much a frame
constexpr double kGravity = 9.8;
// Exchanges a frame: each is a step of femto then one of Bullet over a half frame. One a frame
// leaves the light rigid bodies here unstable (the box rocks on the cushion, the plank flings
// the house): docs/embedding.md, "Two-way coupling with a rigid-body engine".
constexpr int kExchanges = 2;

fmVec3 ToFemto(const btVector3& v)
{
	return fmMakeVec3(v.x(), v.y(), v.z());
}
btVector3 ToBullet(fmVec3 v)
{
	return btVector3(btScalar(v.x), btScalar(v.y), btScalar(v.z));
}

// A rotation as femto takes it (axis times angle, rad) from Bullet's quaternion, in double and
// by atan2: btQuaternion::getAngle's acos of a float w near 1 resolves angles only to about
// 1e-3 rad, and a collider that jitters by that shakes what rests on it.
fmVec3 AxisAngle(const btQuaternion& q)
{
	double x = q.x(), y = q.y(), z = q.z(), w = q.w();
	if (w < 0.0) // the same rotation, by the short way
		x = -x, y = -y, z = -z, w = -w;
	double s = std::sqrt(x * x + y * y + z * z);
	double scale = s > 1e-12 ? 2.0 * std::atan2(s, w) / s : 2.0 / w;
	return fmMakeVec3(scale * x, scale * y, scale * z);
}

// A rigid body of Bullet and the femto collider that stands for it.
struct Link
{
	btRigidBody* rigid;
	fmColliderId collider;
	fmVec3 force;  // what the soft bodies pushed on it over the last frame (N)
	fmVec3 torque; // about its centre of mass (N m)
};

// The coupling loop: owns the Bullet world; femto's world is the caller's.
class Coupling
{
  public:
	Coupling(fmWorldId world, btVector3 gravity)
	    : world_(world), dispatcher_(&configuration_),
	      bullet_(&dispatcher_, &broadphase_, &solver_, &configuration_)
	{
		bullet_.setGravity(gravity);
	}

	~Coupling()
	{
		for (auto& c : constraints_)
			bullet_.removeConstraint(c.get());
		for (auto& body : bodies_)
			bullet_.removeRigidBody(body.get());
	}

	Coupling(const Coupling&) = delete;
	Coupling& operator=(const Coupling&) = delete;

	fmWorldId World() const { return world_; }

	// A rigid body of @p shape and @p mass at @p position, with @p def (its shape's fields set
	// by the caller, centre and rotation left at rest) as its collider in femto.
	Link* AddRigid(std::unique_ptr<btCollisionShape> shape, double mass, btVector3 position,
	               fmColliderDef def)
	{
		btVector3 inertia(0, 0, 0);
		shape->calculateLocalInertia(btScalar(mass), inertia);
		btTransform start;
		start.setIdentity();
		start.setOrigin(position);
		states_.push_back(std::make_unique<btDefaultMotionState>(start));
		btRigidBody::btRigidBodyConstructionInfo info(btScalar(mass), states_.back().get(),
		                                              shape.get(), inertia);
		bodies_.push_back(std::make_unique<btRigidBody>(info));
		shapes_.push_back(std::move(shape));
		btRigidBody* rigid = bodies_.back().get();
		rigid->setActivationState(DISABLE_DEACTIVATION); // femto's forces must always reach it
		bullet_.addRigidBody(rigid);
		def.center = ToFemto(position);
		fmColliderId collider;
		fmDiagnostic diag;
		if (fmCreateCollider(world_, &def, &collider, &diag) != fm_ok)
		{
			std::fprintf(stderr, "collider: %s\n", diag.message);
			return nullptr;
		}
		links_.push_back(std::make_unique<Link>(Link{rigid, collider, {}, {}}));
		return links_.back().get();
	}

	void AddConstraint(std::unique_ptr<btTypedConstraint> constraint)
	{
		bullet_.addConstraint(constraint.get(), true);
		constraints_.push_back(std::move(constraint));
	}

	// One frame of both engines, exchanged @p exchanges times (each exchange: femto steps
	// frame / exchanges in @p femtoSubsteps substeps, then Bullet the same time). @p extra runs
	// before each of Bullet's steps (a spring's torque). The links' force and torque are the
	// frame's averages.
	template <typename Extra> fmResult Frame(int exchanges, int femtoSubsteps, Extra extra)
	{
		double h = kFrame / exchanges;
		for (auto& link : links_)
			link->force = link->torque = fmMakeVec3(0, 0, 0);
		for (int e = 0; e < exchanges; ++e)
		{
			for (auto& link : links_)
				PushPose(*link);
			fmResult result = fmWorld_Step(world_, h, femtoSubsteps);
			if (result != fm_ok)
				return result;
			for (auto& link : links_)
			{
				fmVec3 force, torque;
				fmCollider_GetContactForce(link->collider, &force, &torque);
				link->rigid->applyCentralForce(ToBullet(force));
				link->rigid->applyTorque(ToBullet(torque));
				link->force = fmAdd(link->force, fmScale(1.0 / exchanges, force));
				link->torque = fmAdd(link->torque, fmScale(1.0 / exchanges, torque));
			}
			extra();
			bullet_.stepSimulation(btScalar(h), 0); // one step of exactly h
		}
		return fm_ok;
	}

  private:
	// The collider goes where the rigid body is and moves with its velocities through femto's
	// step (femto moves a kinematic collider at each substep's start).
	static void PushPose(const Link& link)
	{
		const btRigidBody* rigid = link.rigid;
		const btTransform& t = rigid->getCenterOfMassTransform();
		fmCollider_SetTransform(link.collider, ToFemto(t.getOrigin()), AxisAngle(t.getRotation()));
		fmCollider_SetVelocity(link.collider, ToFemto(rigid->getLinearVelocity()),
		                       ToFemto(rigid->getAngularVelocity()));
	}

	fmWorldId world_;
	btDefaultCollisionConfiguration configuration_;
	btCollisionDispatcher dispatcher_;
	btDbvtBroadphase broadphase_;
	btSequentialImpulseConstraintSolver solver_;
	btDiscreteDynamicsWorld bullet_;
	std::vector<std::unique_ptr<btCollisionShape>> shapes_;
	std::vector<std::unique_ptr<btDefaultMotionState>> states_;
	std::vector<std::unique_ptr<btRigidBody>> bodies_;
	std::vector<std::unique_ptr<btTypedConstraint>> constraints_;
	std::vector<std::unique_ptr<Link>> links_;
};

// ---- helpers on femto's side --------------------------------------------------------------

struct SoftBody
{
	fmBodyId id;
	std::vector<double> masses;
	double mass;
};

bool MakeSoftBody(fmWorldId world, fmTetMesh* mesh, fmMaterial material, double density,
                  bool undamped, SoftBody* out)
{
	fmBodyDef def = fmDefaultBodyDef();
	def.mesh = mesh;
	def.material = material;
	def.massMode = fm_massFromDensity;
	def.density = density;
	if (undamped)
	{
		def.damping = 1.0; // both are momentum-free only when off: the checks count momentum
		def.smoothing = 0.0;
	}
	fmDiagnostic diag;
	if (fmCreateBody(world, &def, &out->id, &diag) != fm_ok)
	{
		std::fprintf(stderr, "body: %s\n", diag.message);
		return false;
	}
	int n = fmBody_GetVertexCount(out->id);
	const double* m = fmBody_GetMasses(out->id);
	out->masses.assign(m, m + n);
	out->mass = 0.0;
	for (double v : out->masses)
		out->mass += v;
	return true;
}

fmVec3 Momentum(const SoftBody& body)
{
	int n = fmBody_GetVertexCount(body.id);
	std::vector<double> v(3 * size_t(n));
	fmBody_CopyVelocities(body.id, v.data(), n);
	fmVec3 p = fmMakeVec3(0, 0, 0);
	for (int i = 0; i < n; ++i)
		p = fmAdd(p, fmScale(body.masses[size_t(i)], fmLoad(v.data(), i)));
	return p;
}

// Explicit substeps a frame: the step femto estimates as stable, with a margin.
int ExplicitSubsteps(fmWorldId world)
{
	double limit = 0.8 * fmWorld_EstimateExplicitStep(world);
	return std::max(1, int(std::ceil(kFrame / limit)));
}

bool Check(bool ok, const char* what)
{
	std::printf("  %s: %s\n", ok ? "ok" : "FAILED", what);
	return ok;
}

fmColliderDef BoxCollider(btVector3 half, bool stick)
{
	fmColliderDef def = fmDefaultColliderDef();
	def.shape = fm_shapeBox;
	def.halfExtents = ToFemto(half);
	def.stick = stick;
	return def;
}

// ---- the scenes ---------------------------------------------------------------------------

// A 20 kg rigid box dropped 5 cm onto a 1 m x 0.3 m x 1 m foam cushion lying on femto's
// floor: it must come to rest where the cushion carries its weight.
int Cushion()
{
	fmWorldDef wd = fmDefaultWorldDef();
	wd.integrator = fm_implicit;
	wd.tolerance = FM_TOLERANCE_ACCURATE;
	wd.floor.height = 0.0;
	wd.floor.friction = fm_floorCoulomb;
	fmWorldId world = fmCreateWorld(&wd);
	fmTetMesh mesh;
	fmMakeBoxMesh(6, 2, 6, fmMakeVec3(-0.5, 0.0, -0.5), fmMakeVec3(0.5, 0.3, 0.5), &mesh);
	SoftBody cushion;
	bool made =
	    MakeSoftBody(world, &mesh, fmMakeMaterial(fm_neoHookean, 5e4, 0.3), 200.0, false, &cushion);
	fmFreeTetMesh(&mesh);
	if (!made)
		return 1;
	const double boxMass = 20.0;
	int status = 1;
	{
		Coupling coupling(world, btVector3(0, btScalar(-kGravity), 0));
		btVector3 half(0.2f, 0.2f, 0.2f);
		Link* box = coupling.AddRigid(std::make_unique<btBoxShape>(half), boxMass,
		                              btVector3(0, 0.55f, 0), BoxCollider(half, false));
		if (box == nullptr)
			return 1;
		double worst = 0.0;
		for (int frame = 0; frame < 360; ++frame)
		{
			if (coupling.Frame(kExchanges, 1, [] {}) != fm_ok)
			{
				std::printf("  FAILED: femto's step: %s\n", fmWorld_GetLastError(world)->message);
				return 1;
			}
			if (frame >= 300)
				worst = std::max(worst, std::fabs(box->force.y / (boxMass * kGravity) - 1.0));
		}
		double speed = box->rigid->getLinearVelocity().length();
		double bottom = box->rigid->getCenterOfMassPosition().y() - 0.2;
		// The cushion's top under the box; the barrier keeps a gap below its reach, 1% of the
		// cushion's diagonal (docs/contact.md).
		int n = fmBody_GetVertexCount(cushion.id);
		std::vector<double> x(3 * size_t(n));
		fmBody_CopyPositions(cushion.id, x.data(), n);
		double top = -INFINITY, reach = 0.01 * std::sqrt(1.0 + 0.09 + 1.0);
		for (int i = 0; i < n; ++i)
			if (std::fabs(x[3 * size_t(i)]) < 0.2 && std::fabs(x[3 * size_t(i) + 2]) < 0.2)
				top = std::max(top, x[3 * size_t(i) + 1]);
		std::printf(
		    "cushion: the box (%.0f kg) rests on the cushion (its top under the box %.2f mm "
		    "down, the gap %.2f mm); the cushion pushes %.4f N up (m g = %.4f N), off by at "
		    "most %.4f%% over the last second; the box moves at %.2e m/s\n",
		    boxMass, 1e3 * (0.3 - top), 1e3 * (bottom - top), box->force.y, boxMass * kGravity,
		    100 * worst, speed);
		bool ok = Check(worst < 0.01, "the force is within 1% of m g over the last second");
		ok = Check(speed < 1e-3, "the box's speed at rest is below 1 mm/s") && ok;
		ok = Check(bottom > top && bottom - top < reach,
		           "the box rests on the cushion, within the contact's reach") &&
		     ok;
		ok = Check(top < 0.3, "the cushion is squashed under it") && ok;
		status = ok ? 0 : 1;
	}
	fmDestroyWorld(world);
	return status;
}

// The plank's tilt about z (rad; positive counter-clockwise) from its orientation.
double TiltOf(const btRigidBody* plank)
{
	btQuaternion q = plank->getOrientation();
	return 2.0 * std::atan2(double(q.z()), double(q.w()));
}

// The tilt (rad, negative: clockwise) at which a torsion spring of @p k (N m/rad) carries a
// weight @p weight (N) whose centre is @p r along a rigid lever and @p h above its axis: k theta
// = m g (r cos theta - h sin theta) by Newton's method from zero.
double StaticTilt(double k, double weight, double r, double h)
{
	double theta = 0.0;
	for (int i = 0; i < 50; ++i)
	{
		double f = k * theta + weight * (r * std::cos(theta) - h * std::sin(theta));
		double df = k - weight * (r * std::sin(theta) + h * std::cos(theta));
		theta -= f / df;
	}
	return theta;
}

// The seesaw's plank: 3 m x 0.1 m x 0.6 m, 20 kg, hinged at its centre 1 m up about z, its
// wood's Coulomb friction @p friction. nullptr when femto refuses its collider.
Link* AddSeesawPlank(Coupling& coupling, double friction)
{
	btVector3 half(1.5f, 0.05f, 0.3f);
	fmColliderDef wood = BoxCollider(half, false);
	wood.friction = friction;
	Link* plank =
	    coupling.AddRigid(std::make_unique<btBoxShape>(half), 20.0, btVector3(0, 1.0f, 0), wood);
	if (plank != nullptr)
		coupling.AddConstraint(std::make_unique<btHingeConstraint>(
		    *plank->rigid, btVector3(0, 0, 0), btVector3(0, 0, 1)));
	return plank;
}

// The seesaw's frames: @p frames exchanges with Bullet, the plank held by a torsion spring of
// @p k (N m/rad) and damper @p c (N m s/rad) about its hinge; @p worstLaw gets the worst frame's
// third-law residual across the engines (the body's momentum change less gravity's impulse,
// plus the plank's impulse, over m g dt), @p lowest the lowest tilt. False when a step fails.
bool SwingSeesaw(Coupling& coupling, Link* plank, const SoftBody& body, double k, double c,
                 int frames, double* worstLaw, double* lowest)
{
	fmVec3 g = fmMakeVec3(0.0, -kGravity, 0.0);
	*worstLaw = 0.0;
	*lowest = 0.0;
	for (int frame = 0; frame < frames; ++frame)
	{
		fmVec3 before = Momentum(body);
		auto spring = [&]
		{
			double tilt = TiltOf(plank->rigid);
			double spin = plank->rigid->getAngularVelocity().z();
			plank->rigid->applyTorque(btVector3(0, 0, btScalar(-k * tilt - c * spin)));
		};
		if (coupling.Frame(kExchanges, 1, spring) != fm_ok)
		{
			std::printf("  FAILED: femto's step in frame %d: %s\n", frame,
			            fmWorld_GetLastError(coupling.World())->message);
			return false;
		}
		// Newton's third law across the engines: what the body gained beyond gravity's impulse
		// is minus what was handed to Bullet's plank.
		fmVec3 gained = fmSub(Momentum(body), before);
		fmVec3 residual =
		    fmAdd(fmSub(gained, fmScale(body.mass * kFrame, g)), fmScale(kFrame, plank->force));
		*worstLaw = std::max(*worstLaw, fmLength(residual) / (body.mass * kGravity * kFrame));
		*lowest = std::min(*lowest, TiltOf(plank->rigid));
	}
	return true;
}

// A 3 m, 20 kg plank hinged at its centre, 1 m up, on a torsion spring; the seeds' house mesh,
// 1 m tall and 55 kg (StVK, stiffer than the seeds' to stand at this size), dropped 1 cm onto
// its right arm. It tips the plank until the spring carries it; the plank's wood has Coulomb
// friction 0.8, which holds the house at the tilt.
int Seesaw()
{
	fmWorldDef wd = fmDefaultWorldDef();
	wd.floor.enabled = false;
	wd.integrator = fm_implicit;
	wd.tolerance = FM_TOLERANCE_ACCURATE;
	fmWorldId world = fmCreateWorld(&wd);
	fmTetMesh mesh;
	fmDiagnostic diag;
	if (fmLoadTetGen(FEMTO_HOUSE_NODE, FEMTO_HOUSE_ELE, &mesh, &diag) != fm_ok)
	{
		std::fprintf(stderr, "%s:%d: %s\n", diag.file, diag.line, diag.message);
		return 1;
	}
	fmMeshTransform t = fmDefaultMeshTransform();
	t.scale = 0.1;
	t.center = true;
	t.swapYZ = true;
	fmTetMesh_Transform(&mesh, &t);
	fmMeshInfo info;
	fmTetMesh_GetInfo(&mesh, &info);
	const double plankTop = 1.05, arm = 0.9;
	fmMeshTransform place = fmDefaultMeshTransform();
	place.translate = fmMakeVec3(arm, plankTop + 0.01 - info.boundsMin.y, 0.0);
	fmTetMesh_Transform(&mesh, &place);
	SoftBody house;
	bool made =
	    MakeSoftBody(world, &mesh, fmMakeMaterialLame(fm_stvk, 1e5, 2.5e4), 100.0, true, &house);
	fmFreeTetMesh(&mesh);
	if (!made)
		return 1;
	const double k = 2400.0, c = 600.0; // the spring (N m/rad) and its damper (N m s/rad)
	fmVec3 com0 = fmBody_GetStats(house.id).centerOfMass;
	int status = 1;
	{
		Coupling coupling(world, btVector3(0, btScalar(-kGravity), 0));
		Link* plank = AddSeesawPlank(coupling, 0.8);
		if (plank == nullptr)
			return 1;
		double worstLaw, lowest;
		if (!SwingSeesaw(coupling, plank, house, k, c, 600, &worstLaw, &lowest))
			return 1;
		// The static solve: the rigid lever with the house's centre of mass where it was placed
		// (r along the plank, h above its axis) balances k theta = m g (r cos theta - h sin
		// theta) with theta the (negative) tilt; Newton's method from zero.
		double theta = StaticTilt(k, house.mass * kGravity, com0.x, com0.y - 1.0);
		double tilt = TiltOf(plank->rigid);
		std::printf(
		    "seesaw: the house (%.2f kg, implicit) tipped the plank to %.3f degrees; the "
		    "rigid lever's static solve says %.3f degrees (off by %.2f%%); Newton's third law "
		    "across the engines held to %.2e of m g dt in every frame\n",
		    house.mass, tilt * 180 / M_PI, theta * 180 / M_PI, 100 * std::fabs(tilt / theta - 1),
		    worstLaw);
		// Implicit: the momentum balance holds to the solve's tolerance (1e-6 relative).
		bool ok = Check(worstLaw < 1e-5, "the house's momentum change minus gravity's impulse is "
		                                 "minus the plank's impulse, every frame");
		ok = Check(std::fabs(tilt / theta - 1) < 0.03,
		           "the tilt is within 3% of the static solve") &&
		     ok;
		ok = Check(std::fabs(plank->rigid->getAngularVelocity().z()) < 1e-3,
		           "the plank is at rest") &&
		     ok;
		ok = Check(fmBody_GetStats(house.id).invertedTets == 0, "no tet of the house inverted") &&
		     ok;
		status = ok ? 0 : 1;
	}
	fmDestroyWorld(world);
	return status;
}

// The seesaw of Seesaw() with a 0.4 m foam cushion (8.6 kg) glued under its right arm
// (fmBody_AttachToCollider: two-way, the glue's pull is the plank's force): let go level, the
// plank swings down and settles where the spring carries the hanging cushion, which stays glued.
int Glued()
{
	fmWorldDef wd = fmDefaultWorldDef();
	wd.floor.enabled = false;
	wd.integrator = fm_implicit;
	wd.tolerance = FM_TOLERANCE_ACCURATE;
	fmWorldId world = fmCreateWorld(&wd);
	const double arm = 1.0, underside = 0.95;
	fmTetMesh mesh;
	SoftBody cushion;
	if (fmMakeBoxMesh(4, 4, 4, fmMakeVec3(arm - 0.2, underside - 0.4, -0.2),
	                  fmMakeVec3(arm + 0.2, underside, 0.2), &mesh) != fm_ok)
		return 1;
	bool made =
	    MakeSoftBody(world, &mesh, fmMakeMaterial(fm_neoHookean, 2e5, 0.3), 135.0, true, &cushion);
	fmFreeTetMesh(&mesh);
	if (!made)
		return 1;
	const double k = 600.0, c = 60.0; // the spring (N m/rad), a light damper (N m s/rad)
	fmVec3 com0 = fmBody_GetStats(cushion.id).centerOfMass;
	int status = 1;
	{
		Coupling coupling(world, btVector3(0, btScalar(-kGravity), 0));
		Link* plank = AddSeesawPlank(coupling, 0.5);
		if (plank == nullptr)
			return 1;
		// The cushion's top face, glued where it touches the plank's underside.
		std::vector<double> x(3 * size_t(fmBody_GetVertexCount(cushion.id)));
		fmBody_CopyPositions(cushion.id, x.data(), fmBody_GetVertexCount(cushion.id));
		std::vector<int> top;
		for (int i = 0; i < fmBody_GetVertexCount(cushion.id); ++i)
			if (std::fabs(x[3 * size_t(i) + 1] - underside) < 1e-9)
				top.push_back(i);
		if (fmBody_AttachToCollider(cushion.id, top.data(), int(top.size()), plank->collider,
		                            nullptr) != fm_ok)
			return 1;
		double worstLaw, lowest;
		if (!SwingSeesaw(coupling, plank, cushion, k, c, 600, &worstLaw, &lowest))
			return 1;
		double theta = StaticTilt(k, cushion.mass * kGravity, com0.x, com0.y - 1.0);
		double tilt = TiltOf(plank->rigid);
		std::printf("glued: the cushion (%.2f kg, implicit) swung the plank down to %.3f degrees "
		            "and it settled at %.3f; the rigid lever's static solve says %.3f degrees "
		            "(off by %.2f%%); Newton's third law across the engines held to %.2e of m g "
		            "dt in every frame\n",
		            cushion.mass, lowest * 180 / M_PI, tilt * 180 / M_PI, theta * 180 / M_PI,
		            100 * std::fabs(tilt / theta - 1), worstLaw);
		bool ok = Check(worstLaw < 1e-5, "the cushion's momentum change minus gravity's impulse "
		                                 "is minus the plank's impulse, every frame");
		ok = Check(lowest < 1.3 * theta, "the plank swung past its rest tilt (the glue held the "
		                                 "cushion through the swing)") &&
		     ok;
		ok = Check(std::fabs(tilt / theta - 1) < 0.03,
		           "the tilt is within 3% of the static solve") &&
		     ok;
		ok = Check(std::fabs(plank->rigid->getAngularVelocity().z()) < 1e-3,
		           "the plank is at rest") &&
		     ok;
		status = ok ? 0 : 1;
	}
	fmDestroyWorld(world);
	return status;
}

// A 5 kg rigid ball at 3 m/s into a free 60 kg soft pad, no gravity: the pair's momentum
// stays what it was, frame by frame, and the ball comes back.
int Ball()
{
	fmWorldDef wd = fmDefaultWorldDef();
	wd.floor.enabled = false;
	wd.gravity = fmMakeVec3(0, 0, 0);
	fmWorldId world = fmCreateWorld(&wd);
	fmTetMesh mesh;
	fmMakeBoxMesh(6, 2, 6, fmMakeVec3(-0.5, -0.1, -0.5), fmMakeVec3(0.5, 0.1, 0.5), &mesh);
	SoftBody pad;
	bool made =
	    MakeSoftBody(world, &mesh, fmMakeMaterial(fm_neoHookean, 1e5, 0.3), 300.0, true, &pad);
	fmFreeTetMesh(&mesh);
	if (!made)
		return 1;
	const double ballMass = 5.0, speed = 3.0;
	int status = 1;
	{
		Coupling coupling(world, btVector3(0, 0, 0));
		fmColliderDef def = fmDefaultColliderDef();
		def.shape = fm_shapeSphere;
		def.radius = 0.15;
		def.friction = 0.0;
		Link* ball = coupling.AddRigid(std::make_unique<btSphereShape>(0.15f), ballMass,
		                               btVector3(0.1f, 0.4f, 0), def);
		if (ball == nullptr)
			return 1;
		ball->rigid->setLinearVelocity(btVector3(0, btScalar(-speed), 0));
		int substeps = ExplicitSubsteps(world);
		auto total = [&] {
			return fmAdd(Momentum(pad),
			             fmScale(ballMass, ToFemto(ball->rigid->getLinearVelocity())));
		};
		fmVec3 p0 = total();
		double worst = 0.0, peak = 0.0;
		for (int frame = 0; frame < 90; ++frame)
		{
			if (coupling.Frame(kExchanges, substeps, [] {}) != fm_ok)
			{
				std::printf("  FAILED: femto's step: %s\n", fmWorld_GetLastError(world)->message);
				return 1;
			}
			worst = std::max(worst, fmLength(fmSub(total(), p0)) / (ballMass * speed));
			peak = std::max(peak, fmLength(ball->force));
		}
		double ballVy = ball->rigid->getLinearVelocity().y();
		double padVy = Momentum(pad).y / pad.mass;
		std::printf(
		    "ball: the ball (%.0f kg at %.1f m/s, %d explicit substeps a frame) left at %+.4f "
		    "m/s, the pad (%.1f kg) at %+.4f m/s; peak contact force %.1f N; the pair's "
		    "momentum stayed within %.2e of the ball's first momentum in every frame\n",
		    ballMass, speed, substeps, ballVy, pad.mass, padVy, peak, worst);
		// Debian's Bullet is single precision: the ball's momentum is a float's (6e-8).
		bool ok = Check(worst < 1e-6, "the pair's total momentum is conserved frame by frame");
		ok =
		    Check(ballVy > 0.0 && padVy < 0.0, "the ball bounced back and pushed the pad on") && ok;
		ok = Check(fmBody_GetStats(pad.id).invertedTets == 0, "no tet of the pad inverted") && ok;
		status = ok ? 0 : 1;
	}
	fmDestroyWorld(world);
	return status;
}

} // namespace

int main(int argc, char** argv)
{
	const char* scene = argc > 1 ? argv[1] : "";
	if (std::strcmp(scene, "cushion") == 0)
		return Cushion();
	if (std::strcmp(scene, "seesaw") == 0)
		return Seesaw();
	if (std::strcmp(scene, "ball") == 0)
		return Ball();
	if (std::strcmp(scene, "glued") == 0)
		return Glued();
	std::fprintf(stderr, "usage: bullet_coupling cushion|seesaw|ball|glued\n");
	return 2;
}
