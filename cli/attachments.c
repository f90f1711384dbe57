// Kinematic attachments (attachments.h): rest positions turned about the box's centre by
// Rodrigues' formula and moved, handed to fmBody_SetTargets body by body.
#include "attachments.h"

#include "cli.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int cliCountInBox(const fmTetMesh* mesh, const cliAttachment* a, cliAttached* out, int body)
{
	int count = 0;
	fmVec3 centre = fmScale(0.5, fmAdd(a->min, a->max));
	for (int i = 0; i < mesh->nodeCount; ++i)
	{
		fmVec3 p = fmLoad(mesh->positions, i);
		if (p.x < a->min.x || p.x > a->max.x || p.y < a->min.y || p.y > a->max.y ||
		    p.z < a->min.z || p.z > a->max.z)
			continue;
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

bool cliAttachments_Create(const cliScene* scene, cliSimulation* sim)
{
	int total = 0;
	for (int b = 0; b < scene->bodyCount; ++b)
		for (int k = 0; k < scene->bodies[b].attachmentCount; ++k)
		{
			int count = cliCountInBox(&sim->meshes[b], &scene->bodies[b].attachments[k], NULL, b);
			if (count == 0)
			{
				const cliAttachment* a = &scene->bodies[b].attachments[k];
				cliError("%s: bodies[%d].attachments[%d]: box [%g %g %g]..[%g %g %g] catches no "
				         "vertex (scene coordinates, after the transform)",
				         scene->name, b, k, a->min.x, a->min.y, a->min.z, a->max.x, a->max.y,
				         a->max.z);
				return false;
			}
			total += count;
		}
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
			sim->attachedCount += cliCountInBox(&sim->meshes[b], &scene->bodies[b].attachments[k],
			                                    sim->attached + sim->attachedCount, b);
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
