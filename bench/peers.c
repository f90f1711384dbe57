// The Bullet peer's rows (peers.h): write the mesh, run femto-bench-bullet, read its result.
#include "peers.h"

#include "tools.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

// FEMTO_BENCH_BULLET: the path of femto-bench-bullet, defined by bench/CMakeLists.txt when it is
// built. femto never links Bullet; it runs the program when it is there.
#ifdef FEMTO_BENCH_BULLET
static const char* const cliBulletBuilt = FEMTO_BENCH_BULLET;
#else
static const char* const cliBulletBuilt = NULL;
#endif

bool cliBenchPeer_Find(const char* given, char* program, char* why, size_t size)
{
	const char* path = given != NULL ? given : cliBulletBuilt;
	if (path == NULL)
	{
		snprintf(why, size,
		         "femto-bench-bullet was not built (CMake did not find Bullet's "
		         "deformable world; Debian: apt-get install libbullet-dev)");
		return false;
	}
	if (access(path, X_OK) != 0)
	{
		snprintf(why, size, "%s: %s", path, strerror(errno));
		return false;
	}
	snprintf(program, size, "%s", path);
	return true;
}

// The rest mesh as placed in the world, every tet positively oriented, as 0-based TetGen files
// without comments (Bullet's reader reads plain lines); each point's attribute is its mass.
static bool cliPeerWriteFiles(const fmTetMesh* mesh, const double* masses, const char* node,
                              const char* ele)
{
	FILE* files[2] = {fopen(node, "w"), fopen(ele, "w")};
	bool ok = files[0] != NULL && files[1] != NULL;
	if (ok)
	{
		fprintf(files[0], "%d 3 1 0\n", mesh->nodeCount);
		for (int i = 0; i < mesh->nodeCount; ++i)
			fprintf(files[0], "%d %.17g %.17g %.17g %.17g\n", i, mesh->positions[3 * i],
			        mesh->positions[3 * i + 1], mesh->positions[3 * i + 2], masses[i]);
		fprintf(files[1], "%d 4 0\n", mesh->tetCount);
		for (int t = 0; t < mesh->tetCount; ++t)
			fprintf(files[1], "%d %d %d %d %d\n", t, mesh->tets[4 * t], mesh->tets[4 * t + 1],
			        mesh->tets[4 * t + 2], mesh->tets[4 * t + 3]);
	}
	for (int f = 0; f < 2; ++f)
		if (files[f] != NULL)
		{
			ok = !ferror(files[f]) && ok;
			ok = fclose(files[f]) == 0 && ok;
		}
	if (!ok)
		cliError("bench: cannot write %s and %s for the Bullet peer", node, ele);
	return ok;
}

static bool cliPeerWriteMesh(const cliSimulation* sim, const char* node, const char* ele)
{
	fmTetMesh mesh;
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	if (fmCopyTetMesh(&sim->meshes[0], &mesh) != fm_ok)
	{
		cliError("bench: out of memory");
		return false;
	}
	bool ok = fmTetMesh_Orient(&mesh, NULL, &diag) == fm_ok;
	if (!ok)
		cliPrintDiagnostic("femto: bench: the peer's mesh", &diag);
	else if (fmBody_GetVertexCount(sim->bodies[0]) != mesh.nodeCount)
	{
		cliError("bench: the body has %d vertices, its mesh %d nodes: no peer file",
		         fmBody_GetVertexCount(sim->bodies[0]), mesh.nodeCount);
		ok = false;
	}
	ok = ok && cliPeerWriteFiles(&mesh, fmBody_GetMasses(sim->bodies[0]), node, ele);
	fmFreeTetMesh(&mesh);
	return ok;
}

/// What the peer said.
typedef struct cliPeerResult
{
	double msPerFrame;
	int blewUp;
	double lowestY;
	double maxCoordinate;
	int version;
} cliPeerResult;

static bool cliPeerCommand(const char* program, const char* node, const char* ele,
                           fmMaterial material, int repeats, char* command, size_t size)
{
	char numbers[256];
	snprintf(numbers, sizeof numbers, " %.17g %.17g %.17g %.17g 60 %d 2>&1", material.lambda,
	         material.mu, CLI_BENCH_FLOOR_Y, 1.0 / 60.0, repeats);
	command[0] = '\0';
	return cliBenchAppendQuoted(command, size, program) &&
	       cliBenchAppendQuoted(command, size, node) && cliBenchAppendQuoted(command, size, ele) &&
	       cliBenchAppendText(command, size, numbers);
}

// Run the peer; its "result:" line into @p result. Shows its last lines when it fails.
static bool cliPeerRun(const char* command, const char* program, cliPeerResult* result)
{
	fflush(stdout);
	FILE* pipe = popen(command, "r");
	if (pipe == NULL)
	{
		cliError("bench: cannot run %s: %s", program, strerror(errno));
		return false;
	}
	char line[512], last[512] = "";
	bool found = false;
	while (fgets(line, sizeof line, pipe) != NULL)
	{
		if (sscanf(line,
		           "result: ms_per_frame %lf blew_up %d lowest_y %lf max_coordinate %lf "
		           "bullet_version %d",
		           &result->msPerFrame, &result->blewUp, &result->lowestY, &result->maxCoordinate,
		           &result->version) == 5)
			found = true;
		else if (line[strspn(line, " \t\r\n")] != '\0')
			snprintf(last, sizeof last, "%.*s", (int)strcspn(line, "\r\n"), line);
	}
	int status = pclose(pipe);
	if (found && status == 0)
		return true;
	cliError("bench: %s failed (%s %d)%s%s", program, WIFEXITED(status) ? "exit status" : "signal",
	         WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status),
	         last[0] != '\0' ? ": " : "", last);
	return false;
}

// One mesh: write it, run the peer, print the row and keep it. False when it failed.
static bool cliPeerMesh(const char* program, const cliBenchMesh* mesh, const char* folder,
                        int repeats, cliBenchReport* report, int* version)
{
	char node[CLI_MAX_PATH], ele[CLI_MAX_PATH], command[4 * CLI_MAX_PATH];
	cliSimulation sim;
	bool ok = cliJoinPath(node, sizeof node, folder, "peer.node") &&
	          cliJoinPath(ele, sizeof ele, folder, "peer.ele") &&
	          cliBenchMesh_World(mesh,
	                             &(cliBenchWorld){fm_implicit, fm_neoHookean, 1, FM_TOLERANCE_GAME,
	                                              fm_simdAuto, false, fm_solverNewton, false, 0.0,
	                                              false, 0, 0.0, false, 0.0},
	                             &sim);
	if (ok)
	{
		ok = cliPeerWriteMesh(&sim, node, ele);
		cliSimulation_Destroy(&sim);
	}
	fmMaterial material = cliBenchMesh_Material(mesh, fm_neoHookean);
	cliPeerResult result;
	ok = ok && cliPeerCommand(program, node, ele, material, repeats, command, sizeof command) &&
	     cliPeerRun(command, program, &result);
	if (!ok)
	{
		printf("%-10s %9d %15s\n", mesh->label, mesh->tets, "failed");
		return false;
	}
	*version = result.version;
	const char* model = fmMaterialModelName(fm_neoHookean);
	const cliBenchResult* femto =
	    cliBenchReport_Find(report, mesh->label, "implicit game", model, 1);
	double ms = femto != NULL ? femto->msPerFrame : NAN;
	printf("%-10s %9d %15.2f %14.2f %13.2f  ", mesh->label, mesh->tets, result.msPerFrame, ms,
	       result.msPerFrame / ms);
	if (result.blewUp)
		printf("blew up (largest |x| %.3g m)\n", result.maxCoordinate);
	else
		printf("ok, lowest y %.3f m\n", result.lowestY);
	fflush(stdout);
	cliBenchResult row = cliBenchResult_Make(
	    mesh, result.blewUp ? "bullet implicit (blew up)" : "bullet implicit", model, 1);
	row.msPerFrame = result.msPerFrame;
	row.scene = "rest";
	return cliBenchReport_Add(report, &row);
}

bool cliBenchPeer_Rows(const char* program, const cliBenchMeshSet* set, const char* folder,
                       int repeats, cliBenchReport* report)
{
	// The peer built beside femto is named relative to the build folder: the report goes into
	// docs/ and must not carry the path of the machine it ran on.
	const char* shown = program;
	const char* inBuild = strstr(program, "/bench/peers/");
	const char* built = cliBulletBuilt;
	if (built != NULL && inBuild != NULL && strcmp(program, built) == 0)
		shown = inBuild + 1;
	printf("Bullet's deformable world (%s): implicit Neo-Hookean, same mesh, Lame constants, "
	       "masses, gravity and floor, 1/60 s frames after 1 s of settling, median of %d; "
	       "femto: implicit Neo-Hookean, game tolerance, 1 worker\n",
	       shown, repeats);
	printf("%-10s %9s %15s %14s %13s  %s\n", "mesh", "tets", "bullet ms/frame", "femto ms/frame",
	       "bullet/femto", "bullet state");
	bool ok = true;
	int version = 0;
	for (int m = 0; m < set->count; ++m)
		if (set->meshes[m].tets <= CLI_BENCH_PEER_MAX_TETS)
			ok = cliPeerMesh(program, &set->meshes[m], folder, repeats, report, &version) && ok;
	if (version > 0)
		printf("(Bullet %d.%02d, btDeformableMultiBodyDynamicsWorld, one thread)\n", version / 100,
		       version % 100);
	return ok;
}
