// `femto mesh IN OUT`: a closed triangle surface (OBJ, STL ASCII or binary, OFF, PLY ASCII) turned
// into a tet mesh by TetGen or Gmsh, run as separate programs (posix_spawnp; never linked into
// femto), written in the format OUT names (fmWriteMesh: .node/.ele, .msh, .vtu).
#include "commands.h"

#include "cli.h"
#include "surface_check.h"
#include "surface_read.h"

#include <ctype.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <spawn.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

const char* const cliMeshHelp =
    "usage: femto mesh IN OUT [options]\n"
    "\n"
    "Fill a closed triangle surface with tets. IN: .obj, .stl (ASCII or binary), .off or\n"
    ".ply (ASCII); OUT: .node (with the .ele beside it), .msh or .vtu. Runs TetGen or Gmsh as\n"
    "a separate program (Debian packages tetgen and gmsh); docs/meshes.md says how to get a\n"
    "mesh that steps fast.\n"
    "\n"
    "options:\n"
    "  --quality Q      TetGen: largest radius-edge ratio, >= 1.1 (default 1.4; smaller\n"
    "                   is rounder tets, more of them); Gmsh optimises on its own\n"
    "  --max-volume V   largest tet volume (m^3, in the surface's units cubed); Gmsh: the\n"
    "                   edge length of a regular tet of that volume\n"
    "  --tool NAME      tetgen or gmsh (default: tetgen when installed, else gmsh)\n"
    "  --quiet          no summary\n"
    "  --help           this text\n"
    "\n"
    "Exit status: 0 ok, 1 bad input, missing tool or failed meshing, 2 usage error.\n";

static bool cliHasExtension(const char* path, const char* extension)
{
	size_t n = strlen(path), e = strlen(extension);
	if (n < e)
		return false;
	for (size_t i = 0; i < e; ++i)
		if (tolower((unsigned char)path[n - e + i]) != extension[i])
			return false;
	return true;
}

static bool cliReadSurfaceFile(const char* path, cliSurface* s)
{
	memset(s, 0, sizeof *s);
	if (cliHasExtension(path, ".obj"))
	{
		fmSurfaceMesh obj;
		fmDiagnostic diag;
		memset(&diag, 0, sizeof diag);
		if (fmLoadObj(path, &obj, &diag) != fm_ok)
		{
			cliPrintDiagnostic(NULL, &diag);
			return false;
		}
		bool ok = true;
		for (int i = 0; ok && i < obj.vertexCount; ++i)
			ok = cliSurface_AddVertex(s, obj.positions[3 * i], obj.positions[3 * i + 1],
			                          obj.positions[3 * i + 2]);
		for (int t = 0; ok && t < obj.triangleCount; ++t)
			ok = cliSurface_AddTriangle(s, obj.triangles[3 * t], obj.triangles[3 * t + 1],
			                            obj.triangles[3 * t + 2]);
		fmFreeSurfaceMesh(&obj);
		if (!ok)
			cliError("%s: out of memory", path);
		return ok;
	}
	bool stl = cliHasExtension(path, ".stl"), off = cliHasExtension(path, ".off"),
	     ply = cliHasExtension(path, ".ply");
	if (!stl && !off && !ply)
	{
		cliError("%s: expected a surface: .obj, .stl, .off or .ply", path);
		return false;
	}
	size_t size = 0;
	char* data = cliReadFile(path, &size);
	if (data == NULL)
		return false;
	bool ok = cliReadSurface(path, data, size,
	                         stl   ? cli_surfaceStl
	                         : off ? cli_surfaceOff
	                               : cli_surfacePly,
	                         stderr, s);
	free(data);
	return ok;
}

// The surface of @p path by its extension, and at least a tetrahedron's worth of it.
static bool cliLoadSurface(const char* path, cliSurface* s)
{
	if (!cliReadSurfaceFile(path, s))
		return false;
	if (s->triangleCount >= 4)
		return cliSurface_Check(path, s);
	cliError("%s: %d triangles: a closed surface has at least 4", path, s->triangleCount);
	return false;
}

// ---- the external mesher --------------------------------------------------------------------

// Whether @p program is an executable on the PATH.
static bool cliOnPath(const char* program)
{
	const char* path = getenv("PATH");
	while (path != NULL && *path != 0)
	{
		size_t length = strcspn(path, ":");
		char candidate[CLI_MAX_PATH];
		if (snprintf(candidate, sizeof candidate, "%.*s/%s", (int)length, length > 0 ? path : ".",
		             program) < (int)sizeof candidate &&
		    access(candidate, X_OK) == 0)
			return true;
		path += length + (path[length] == ':' ? 1 : 0);
	}
	return false;
}

// What a signal that ends femto mesh cleans up: the mesher running (killed: Gmsh ignores
// SIGTERM) and the scratch folder's files, their paths made before any signal can come (the
// handler only calls kill, unlink, rmdir, signal and raise: async-signal-safe).
#define CLI_SCRATCH_NAMES 11
static volatile sig_atomic_t cliMeshChild;
static char cliScratchFiles[CLI_SCRATCH_NAMES][CLI_MAX_PATH + 32];
static char cliScratchDir[CLI_MAX_PATH];

static void cliMeshInterrupted(int sig)
{
	if (cliMeshChild > 0)
		kill((pid_t)cliMeshChild, SIGKILL);
	for (int i = 0; i < CLI_SCRATCH_NAMES; ++i)
		unlink(cliScratchFiles[i]);
	rmdir(cliScratchDir);
	signal(sig, SIG_DFL);
	raise(sig);
}

// Run @p argv (argv[0] found on the PATH) with its output in @p logPath. Prints why it failed.
static bool cliRunProgram(char* const* argv, const char* logPath)
{
	posix_spawn_file_actions_t actions;
	posix_spawn_file_actions_init(&actions);
	posix_spawn_file_actions_addopen(&actions, 1, logPath, O_WRONLY | O_CREAT | O_TRUNC, 0644);
	posix_spawn_file_actions_adddup2(&actions, 1, 2);
	pid_t pid;
	int error = posix_spawnp(&pid, argv[0], &actions, NULL, argv, environ);
	posix_spawn_file_actions_destroy(&actions);
	if (error != 0)
	{
		cliError("cannot run %s: %s", argv[0], strerror(error));
		return false;
	}
	cliMeshChild = pid;
	int status = 0;
	while (waitpid(pid, &status, 0) < 0)
		if (errno != EINTR)
		{
			cliError("waiting for %s: %s", argv[0], strerror(errno));
			return false;
		}
	cliMeshChild = 0;
	if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
		return true;
	cliError("%s failed (%s %d); its output:", argv[0],
	         WIFEXITED(status) ? "exit status" : "signal",
	         WIFEXITED(status) ? WEXITSTATUS(status) : WTERMSIG(status));
	size_t size = 0;
	char* log = cliReadFile(logPath, &size);
	if (log != NULL)
	{
		// The last 2000 bytes: the error is at the end.
		fputs(size > 2000 ? log + size - 2000 : log, stderr);
		free(log);
	}
	return false;
}

static bool cliWriteOff(const char* path, const cliSurface* s)
{
	FILE* file = fopen(path, "w");
	if (file == NULL)
	{
		cliError("%s: cannot write: %s", path, strerror(errno));
		return false;
	}
	fprintf(file, "OFF\n%d %d 0\n", s->vertexCount, s->triangleCount);
	for (int i = 0; i < s->vertexCount; ++i)
		fprintf(file, "%.17g %.17g %.17g\n", s->x[3 * i], s->x[3 * i + 1], s->x[3 * i + 2]);
	for (int t = 0; t < s->triangleCount; ++t)
		fprintf(file, "3 %d %d %d\n", s->triangles[3 * t], s->triangles[3 * t + 1],
		        s->triangles[3 * t + 2]);
	return fclose(file) == 0;
}

static bool cliWriteStlAscii(const char* path, const cliSurface* s)
{
	FILE* file = fopen(path, "w");
	if (file == NULL)
	{
		cliError("%s: cannot write: %s", path, strerror(errno));
		return false;
	}
	fprintf(file, "solid femto\n");
	for (int t = 0; t < s->triangleCount; ++t)
	{
		fprintf(file, "facet normal 0 0 0\nouter loop\n");
		for (int k = 0; k < 3; ++k)
		{
			const double* p = s->x + 3 * (size_t)s->triangles[3 * t + k];
			fprintf(file, "vertex %.17g %.17g %.17g\n", p[0], p[1], p[2]);
		}
		fprintf(file, "endloop\nendfacet\n");
	}
	fprintf(file, "endsolid femto\n");
	return fclose(file) == 0;
}

// A file in the scratch folder: the folder's path (at most CLI_MAX_PATH) and a short name.
#define CLI_SCRATCH_PATH (CLI_MAX_PATH + 32)

typedef struct cliMeshOptions
{
	const char* in;
	const char* out;
	double quality;
	double maxVolume; // 0: no limit
	const char* tool; // NULL: the first installed
	bool quiet;
} cliMeshOptions;

// TetGen: -p a piecewise linear complex (the surface), -q the radius-edge bound, -a the volume
// bound, -Q quiet; it writes DIR/surface.1.node and .1.ele.
static bool cliTetGen(const cliMeshOptions* o, const char* dir, const cliSurface* s,
                      fmTetMesh* mesh, fmDiagnostic* diag)
{
	char input[CLI_SCRATCH_PATH], log[CLI_SCRATCH_PATH], node[CLI_SCRATCH_PATH],
	    ele[CLI_SCRATCH_PATH];
	char switches[128];
	snprintf(input, sizeof input, "%s/surface.off", dir);
	snprintf(log, sizeof log, "%s/tetgen.log", dir);
	snprintf(node, sizeof node, "%s/surface.1.node", dir);
	snprintf(ele, sizeof ele, "%s/surface.1.ele", dir);
	if (o->maxVolume > 0.0)
		snprintf(switches, sizeof switches, "-pq%ga%.9gQ", o->quality, o->maxVolume);
	else
		snprintf(switches, sizeof switches, "-pq%gQ", o->quality);
	char* argv[] = {"tetgen", switches, input, NULL};
	if (!cliWriteOff(input, s) || !cliRunProgram(argv, log))
		return false;
	if (fmLoadTetGen(node, ele, mesh, diag) != fm_ok)
	{
		cliPrintDiagnostic("tetgen's output", diag);
		return false;
	}
	return true;
}

// Gmsh: a .geo that merges the surface (as STL), closes it into a volume and meshes it in 3D.
static bool cliGmsh(const cliMeshOptions* o, const char* dir, const cliSurface* s, fmTetMesh* mesh,
                    fmDiagnostic* diag)
{
	char stl[CLI_SCRATCH_PATH], geo[CLI_SCRATCH_PATH], log[CLI_SCRATCH_PATH], out[CLI_SCRATCH_PATH];
	snprintf(stl, sizeof stl, "%s/surface.stl", dir);
	snprintf(geo, sizeof geo, "%s/surface.geo", dir);
	snprintf(log, sizeof log, "%s/gmsh.log", dir);
	snprintf(out, sizeof out, "%s/volume.msh", dir);
	if (!cliWriteStlAscii(stl, s))
		return false;
	FILE* file = fopen(geo, "w");
	if (file == NULL)
	{
		cliError("%s: cannot write: %s", geo, strerror(errno));
		return false;
	}
	// ClassifySurfaces splits the triangles into patches at creases sharper than 40 degrees and
	// CreateGeometry makes them surfaces Gmsh may remesh at the size asked for.
	fprintf(file, "Merge \"surface.stl\";\nClassifySurfaces{40 * Pi / 180, 1, 1, Pi};\n"
	              "CreateGeometry;\nSurface Loop(1) = Surface{:};\nVolume(1) = {1};\n"
	              "Mesh.Optimize = 1;\n");
	// The edge of a regular tet of volume V: V = a^3 / (6 sqrt 2).
	if (o->maxVolume > 0.0)
		fprintf(file, "Mesh.MeshSizeMax = %.9g;\n", cbrt(6.0 * sqrt(2.0) * o->maxVolume));
	fclose(file);
	char* argv[] = {"gmsh", "-3", "-format", "msh41", "-o", out, geo, NULL};
	if (!cliRunProgram(argv, log))
		return false;
	// Gmsh saves the surface triangles, lines and points with the tets: skipped without a note.
	cliMuteLibraryWarnings(true);
	fmResult result = fmLoadMesh(out, mesh, diag);
	cliMuteLibraryWarnings(false);
	if (result != fm_ok)
	{
		cliPrintDiagnostic("gmsh's output", diag);
		return false;
	}
	return true;
}

static int cliParseMeshOptions(int argc, char** argv, cliMeshOptions* o)
{
	memset(o, 0, sizeof *o);
	o->quality = 1.4;
	for (int i = 1; i < argc; ++i)
	{
		const char* arg = argv[i];
		const char* value;
		if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0)
		{
			fputs(cliMeshHelp, stdout);
			return cli_exitOk;
		}
		else if (strcmp(arg, "--quiet") == 0 || strcmp(arg, "-q") == 0)
			o->quiet = true;
		else if (strcmp(arg, "--quality") == 0)
		{
			if ((value = cliOptionValue("mesh", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!cliParseDouble(value, &o->quality) || o->quality < 1.1 || o->quality > 100.0)
				return cliUsageError("mesh", "--quality: expected a number in [1.1, 100], got '%s'",
				                     value);
		}
		else if (strcmp(arg, "--max-volume") == 0)
		{
			if ((value = cliOptionValue("mesh", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (!cliParseDouble(value, &o->maxVolume) || !(o->maxVolume > 0.0))
				return cliUsageError("mesh", "--max-volume: expected a volume > 0, got '%s'",
				                     value);
		}
		else if (strcmp(arg, "--tool") == 0)
		{
			if ((o->tool = cliOptionValue("mesh", argc, argv, &i)) == NULL)
				return cli_exitUsage;
			if (strcmp(o->tool, "tetgen") != 0 && strcmp(o->tool, "gmsh") != 0)
				return cliUsageError("mesh", "--tool: expected tetgen or gmsh, got '%s'", o->tool);
		}
		else if (arg[0] == '-' && arg[1] != 0)
			return cliUsageError("mesh", "unknown option '%s'", arg);
		else if (o->in == NULL)
			o->in = arg;
		else if (o->out == NULL)
			o->out = arg;
		else
			return cliUsageError("mesh", "more than two files ('%s')", arg);
	}
	if (o->out == NULL)
		return cliUsageError("mesh", "expected IN (.obj, .stl, .off, .ply) and OUT (.node, .msh, "
		                             ".vtu)");
	if (!cliHasExtension(o->out, ".node") && !cliHasExtension(o->out, ".ele") &&
	    !cliHasExtension(o->out, ".msh") && !cliHasExtension(o->out, ".vtu"))
		return cliUsageError("mesh", "%s: expected OUT to end in .node, .msh or .vtu", o->out);
	return -1;
}

// The mesher to run: the one asked for, else TetGen, else Gmsh. NULL (with the package to
// install) when none is there.
static const char* cliPickTool(const cliMeshOptions* o)
{
	if (o->tool != NULL && cliOnPath(o->tool))
		return o->tool;
	if (o->tool != NULL)
		cliError("%s is not installed (on Debian and Ubuntu: sudo apt-get install %s)", o->tool,
		         o->tool);
	else if (cliOnPath("tetgen"))
		return "tetgen";
	else if (cliOnPath("gmsh"))
		return "gmsh";
	else
		cliError("neither tetgen nor gmsh is installed: femto mesh runs one of them (on Debian "
		         "and Ubuntu: sudo apt-get install tetgen, or gmsh)");
	return NULL;
}

// The scratch folder's files (only the names this command writes), for cliRemoveScratch and a
// signal, which then removes them too (SIGINT, SIGTERM, SIGHUP while the folder exists).
static void cliNoteScratch(const char* dir)
{
	static const char* const names[CLI_SCRATCH_NAMES] = {
	    "surface.off",   "surface.stl",    "surface.geo",    "surface.1.node",
	    "surface.1.ele", "surface.1.face", "surface.1.edge", "surface.1.smesh",
	    "volume.msh",    "tetgen.log",     "gmsh.log"};
	for (int i = 0; i < CLI_SCRATCH_NAMES; ++i)
		snprintf(cliScratchFiles[i], sizeof cliScratchFiles[i], "%s/%s", dir, names[i]);
	snprintf(cliScratchDir, sizeof cliScratchDir, "%s", dir);
	signal(SIGINT, cliMeshInterrupted);
	signal(SIGTERM, cliMeshInterrupted);
	signal(SIGHUP, cliMeshInterrupted);
}

// Remove the scratch folder's files and the folder; signals are femto's default again.
static void cliRemoveScratch(void)
{
	signal(SIGINT, SIG_DFL);
	signal(SIGTERM, SIG_DFL);
	signal(SIGHUP, SIG_DFL);
	for (int i = 0; i < CLI_SCRATCH_NAMES; ++i)
		remove(cliScratchFiles[i]);
	rmdir(cliScratchDir);
}

// The volume the closed surface encloses (the divergence theorem over its triangles), m^3.
static double cliEnclosedVolume(const cliSurface* s)
{
	double six = 0.0;
	for (int t = 0; t < s->triangleCount; ++t)
	{
		const double* a = s->x + 3 * (size_t)s->triangles[3 * t];
		const double* b = s->x + 3 * (size_t)s->triangles[3 * t + 1];
		const double* c = s->x + 3 * (size_t)s->triangles[3 * t + 2];
		six += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
		       a[2] * (b[0] * c[1] - b[1] * c[0]);
	}
	return fabs(six) / 6.0;
}

// Whether --max-volume asks for no more tets than a body may have (FM_MAX_TETS): a mesher told
// to fill the surface with tets of 1e-300 m^3 would run until memory ends.
static bool cliTetCountBounded(const cliMeshOptions* o, const cliSurface* s)
{
	double volume = cliEnclosedVolume(s);
	if (!(o->maxVolume > 0.0) || volume / o->maxVolume <= (double)FM_MAX_TETS)
		return true;
	cliError("%s: --max-volume %g asks for at least %.3g tets (the surface encloses %.6g, in its "
	         "units cubed): more than the %d a body may have (FM_MAX_TETS); give a volume of at "
	         "least %.3g",
	         o->in, o->maxVolume, volume / o->maxVolume, volume, FM_MAX_TETS,
	         volume / (double)FM_MAX_TETS);
	return false;
}

int cliMesh(int argc, char** argv)
{
	cliMeshOptions o;
	int code = cliParseMeshOptions(argc, argv, &o);
	if (code >= 0)
		return code;
	cliSurface surface;
	if (!cliLoadSurface(o.in, &surface))
	{
		cliSurface_Free(&surface);
		return cli_exitInput;
	}
	const char* tool = cliTetCountBounded(&o, &surface) ? cliPickTool(&o) : NULL;
	if (tool == NULL)
	{
		cliSurface_Free(&surface);
		return cli_exitInput;
	}
	const char* tmp = getenv("TMPDIR");
	char dir[CLI_MAX_PATH];
	snprintf(dir, sizeof dir, "%s/femto-mesh-XXXXXX", tmp != NULL && tmp[0] != 0 ? tmp : "/tmp");
	if (mkdtemp(dir) == NULL)
	{
		cliError("%s: cannot make a scratch folder: %s", dir, strerror(errno));
		cliSurface_Free(&surface);
		return cli_exitInput;
	}
	cliNoteScratch(dir);
	fmTetMesh mesh;
	memset(&mesh, 0, sizeof mesh);
	fmDiagnostic diag;
	memset(&diag, 0, sizeof diag);
	double start = cliNow();
	bool ok = strcmp(tool, "tetgen") == 0 ? cliTetGen(&o, dir, &surface, &mesh, &diag)
	                                      : cliGmsh(&o, dir, &surface, &mesh, &diag);
	double seconds = cliNow() - start;
	cliRemoveScratch();
	memset(&diag, 0, sizeof diag);
	if (ok && fmWriteMesh(o.out, &mesh, NULL, &diag) != fm_ok)
	{
		cliPrintDiagnostic(o.out, &diag);
		ok = false;
	}
	fmMeshInfo info;
	if (ok && !o.quiet && fmTetMesh_GetInfo(&mesh, &info) == fm_ok)
	{
		printf("surface          %s (%d vertices, %d triangles)\n", o.in, surface.vertexCount,
		       surface.triangleCount);
		printf("mesher           %s (%.2f s)\n", tool, seconds);
		printf("tets             %d on %d nodes\n", info.tetCount, info.nodeCount);
		printf("volume           %.9g\n", info.totalVolume);
		printf("dihedral angles  %.2f to %.2f degrees\n", info.minDihedralDeg, info.maxDihedralDeg);
		printf("radius ratio     %.3f at worst (1 regular; docs/meshes.md)\n", info.minQuality);
		printf("wrote            %s\n", o.out);
	}
	fmFreeTetMesh(&mesh);
	cliSurface_Free(&surface);
	return ok ? cli_exitOk : cli_exitInput;
}
