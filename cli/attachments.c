// Kinematic attachments (attachments.h): rest positions turned about the box's centre by
// Rodrigues' formula and moved, handed to fmBody_SetTargets body by body.
#include "attachments.h"

#include "cli.h"
#include "welds.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

// The vertices of @p mesh in attachment @p a's box, into @p out (may be NULL) as kinematic
// attachments of @p body, or into @p vertices (may be NULL) as vertex indices; their count.
static int cliCountInBox(const fmTetMesh* mesh, const cliAttachment* a, cliAttached* out, int body,
                         int* vertices)
{
	int count = 0;
	fmVec3 centre = fmScale(0.5, fmAdd(a->min, a->max));
	for (int i = 0; i < mesh->nodeCount; ++i)
	{
		fmVec3 p = fmLoad(mesh->positions, i);
		if (p.x < a->min.x || p.x > a->max.x || p.y < a->min.y || p.y > a->max.y ||
		    p.z < a->min.z || p.z > a->max.z)
			continue;
		if (vertices != NULL)
			vertices[count] = i;
		if (out != NULL)
		{
			cliAttached* t = &out[count];
			t->body = body;
			t->vertex = i;
			t->rest = p;
			t->centre = centre;
			t->velocity = a->velocity;
			t->angularVelocity = a->angularVelocity;
			t->stiffness = a->stiffness;
		}
		count += 1;
	}
	return count;
}

// Glue the vertices in attachment @p k of body @p b to its collider.
static bool cliGlue(const cliScene* scene, cliSimulation* sim, int b, int k)
{
	const cliAttachment* a = &scene->bodies[b].attachments[k];
	if (a->collider >= sim->colliderCount)
	{
		cliError("%s: bodies[%d].attachments[%d].collider: %d, but the scene has %d colliders",
		         scene->name, b, k, a->collider, sim->colliderCount);
		return false;
	}
	int* vertices = malloc(sizeof(int) * (size_t)sim->meshes[b].nodeCount);
	if (vertices == NULL)
	{
		cliError("%s: out of memory for the attachments", scene->name);
		return false;
	}
	int count = cliCountInBox(&sim->meshes[b], a, NULL, b, vertices);
	fmAttachDef def = fmDefaultAttachDef();
	def.stiffness = a->stiffness;
	def.dampingRatio = a->dampingRatio;
	bool ok = fmBody_AttachToCollider(sim->bodies[b], vertices, count, sim->colliders[a->collider],
	                                  &def) == fm_ok;
	free(vertices);
	if (!ok)
		cliError("%s: bodies[%d].attachments[%d]: %s", scene->name, b, k,
		         fmWorld_GetLastError(sim->world)->message);
	return ok;
}

// Count the kinematic attachments' vertices (into @p total) and glue the others; false with a
// message when a box catches no vertex or a glue is refused.
static bool cliCountAndGlue(const cliScene* scene, cliSimulation* sim, int* total)
{
	*total = 0;
	for (int b = 0; b < scene->bodyCount; ++b)
		for (int k = 0; k < scene->bodies[b].attachmentCount; ++k)
		{
			const cliAttachment* a = &scene->bodies[b].attachments[k];
			int count = cliCountInBox(&sim->meshes[b], a, NULL, b, NULL);
			if (count == 0)
			{
				cliError("%s: bodies[%d].attachments[%d]: box [%g %g %g]..[%g %g %g] catches no "
				         "vertex (scene coordinates, after the transform)",
				         scene->name, b, k, a->min.x, a->min.y, a->min.z, a->max.x, a->max.y,
				         a->max.z);
				return false;
			}
			if (a->collider >= 0 && !cliGlue(scene, sim, b, k))
				return false;
			*total += a->collider >= 0 ? 0 : count;
		}
	return true;
}

bool cliAttachments_Create(const cliScene* scene, cliSimulation* sim)
{
	int total = 0;
	if (!cliCountAndGlue(scene, sim, &total) || !cliWelds_Create(scene, sim))
		return false;
	if (total == 0)
		return true;
	sim->attached = calloc((size_t)total, sizeof *sim->attached);
	if (sim->attached == NULL)
	{
		cliError("%s: out of memory for the attachments", scene->name);
		return false;
	}
	for (int b = 0; b < scene->bodyCount; ++b)
		for (int k = 0; k < scene->bodies[b].attachmentCount; ++k)
			if (scene->bodies[b].attachments[k].collider < 0)
				sim->attachedCount +=
				    cliCountInBox(&sim->meshes[b], &scene->bodies[b].attachments[k],
				                  sim->attached + sim->attachedCount, b, NULL);
	return cliAttachments_Update(sim, 0.0);
}

// @p p turned by the rotation vector @p w (Rodrigues) about @p centre.
static fmVec3 cliTurn(fmVec3 p, fmVec3 centre, fmVec3 w)
{
	double angle = fmLength(w);
	fmVec3 r = fmSub(p, centre);
	if (!(angle > 0.0))
		return p;
	fmVec3 k = fmScale(1.0 / angle, w);
	double c = cos(angle), s = sin(angle);
	fmVec3 turned =
	    fmAdd(fmAdd(fmScale(c, r), fmScale(s, fmCross(k, r))), fmScale((1.0 - c) * fmDot(k, r), k));
	return fmAdd(centre, turned);
}

bool cliAttachments_Update(cliSimulation* sim, double time)
{
	int first = 0;
	while (first < sim->attachedCount)
	{
		int body = sim->attached[first].body, last = first;
		double stiffness = 0.0;
		while (last < sim->attachedCount && sim->attached[last].body == body)
			stiffness = fmax(stiffness, sim->attached[last++].stiffness);
		int count = last - first;
		int* vertices = malloc(sizeof(int) * (size_t)count);
		fmVec3* positions = malloc(sizeof(fmVec3) * (size_t)count);
		bool ok = vertices != NULL && positions != NULL;
		for (int k = 0; ok && k < count; ++k)
		{
			const cliAttached* a = &sim->attached[first + k];
			vertices[k] = a->vertex;
			positions[k] = fmAdd(cliTurn(a->rest, a->centre, fmScale(time, a->angularVelocity)),
			                     fmScale(time, a->velocity));
		}
		ok = ok &&
		     fmBody_SetTargets(sim->bodies[body], vertices, positions, count, stiffness) == fm_ok;
		free(vertices);
		free(positions);
		if (!ok)
		{
			cliError("bodies[%d]: the attachments' targets cannot be set: %s", body,
			         fmWorld_GetLastError(sim->world)->message);
			return false;
		}
		first = last;
	}
	return true;
}
