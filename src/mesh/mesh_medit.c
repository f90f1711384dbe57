// Medit .mesh reading (ASCII), written to the format's description (Frey, "MEDIT: an interactive
// mesh visualization software", INRIA RT-0253, and the libMeshb keyword list): keywords in any
// case, '#' comments, "Vertices" (x y z ref) and "Tetrahedra" (4 vertex numbers from 1, ref; the
// ref becomes the tet's region). Other keywords are skipped with their numbers: a keyword is a
// token that starts with a letter, and numbers never do.
#include "mesh/mesh_medit.h"

#include "core/core.h"
#include "mesh/mesh_reader.h"

#include <limits.h>
#include <stdio.h>
#include <string.h>

typedef struct fmMedit
{
	fmScan s;
	int nodeCount;
	double* positions;
	fmTetList tets;
	bool haveTets;
} fmMedit;

static bool fmMeditIsKeyword(const fmScan* s)
{
	unsigned char c = s->token[0];
	return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z');
}

static fmResult fmMeditVertices(fmMedit* m)
{
	if (m->positions != NULL)
		return fmScan_Error(&m->s, fm_errSyntax, "a second Vertices section: expected one");
	long long count = 0;
	fmResult result = fmScan_Int64(&m->s, "vertex count", 1, LLONG_MAX, &count);
	// "x y z ref" is at least 8 bytes.
	if (result == fm_ok)
		result = fmScan_CheckCount(&m->s, count, FM_MAX_NODES, 8, "vertices");
	if (result != fm_ok)
		return result;
	m->nodeCount = (int)count;
	m->positions = FM_ALLOC_ARRAY(double, 3 * (size_t)count);
	if (m->positions == NULL)
		return fmScan_Error(&m->s, fm_errOutOfMemory, "out of memory for %lld vertices", count);
	long long ref = 0;
	for (int i = 0; i < m->nodeCount && result == fm_ok; ++i)
	{
		for (int k = 0; k < 3 && result == fm_ok; ++k)
			result =
			    fmScan_Double(&m->s, "vertex coordinate", &m->positions[3 * (size_t)i + (size_t)k]);
		if (result == fm_ok)
			result = fmScan_Int64(&m->s, "vertex reference", LLONG_MIN, LLONG_MAX, &ref);
	}
	return result;
}

static fmResult fmMeditTetrahedra(fmMedit* m)
{
	if (m->positions == NULL)
		return fmScan_Error(&m->s, fm_errSyntax,
		                    "Tetrahedra before Vertices: expected the vertices first");
	if (m->haveTets)
		return fmScan_Error(&m->s, fm_errSyntax, "a second Tetrahedra section: expected one");
	m->haveTets = true;
	long long count = 0;
	fmResult result = fmScan_Int64(&m->s, "tetrahedron count", 0, LLONG_MAX, &count);
	// "a b c d ref" is at least 10 bytes.
	if (result == fm_ok)
		result = fmScan_CheckCount(&m->s, count, FM_MAX_TETS, 10, "tetrahedra");
	if (result != fm_ok)
		return result;
	fmSkipped skipped = m->tets.skipped; // kinds skipped before the tets
	fmTetList_Init(&m->tets, count, true);
	m->tets.skipped = skipped;
	for (long long t = 0; t < count && result == fm_ok; ++t)
	{
		int nodes[4] = {0, 0, 0, 0};
		long long ref = 0;
		for (int k = 0; k < 4 && result == fm_ok; ++k)
		{
			char what[64];
			snprintf(what, sizeof what, "vertex number (1 to %d)", m->nodeCount);
			result = fmScan_Int(&m->s, what, 1, m->nodeCount, &nodes[k]);
			nodes[k] -= 1;
		}
		if (result == fm_ok)
			result = fmScan_Int64(&m->s, "tetrahedron reference", INT_MIN, INT_MAX, &ref);
		if (result == fm_ok)
			result = fmTetList_Add(&m->tets, nodes, m->s.tokenLine, (double)ref, &m->s);
	}
	return result;
}

// Skip the numbers of a keyword this reader does not use, counting its elements when it is one.
static void fmMeditSkip(fmMedit* m)
{
	static const char* const kinds[][2] = {
	    {"triangles", "triangles"},
	    {"quadrilaterals", "quadrilaterals"},
	    {"edges", "edges"},
	    {"hexahedra", "hexahedra"},
	    {"prisms", "prisms"},
	    {"pyramids", "pyramids"},
	    {"tetrahedraP2", "quadratic tetrahedra"},
	};
	const char* kind = NULL;
	for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; ++k)
		if (fmScan_IsNoCase(&m->s, kinds[k][0]))
			kind = kinds[k][1];
	fmScan saved = m->s;
	long long count = 0;
	if (kind && fmScan_Next(&m->s) && m->s.tokenLength < 12)
	{
		for (size_t k = 0; k < m->s.tokenLength && count >= 0; ++k)
			count = m->s.token[k] >= '0' && m->s.token[k] <= '9'
			            ? 10 * count + (m->s.token[k] - '0')
			            : -1;
		if (count > 0)
			fmSkipped_Add(&m->tets.skipped, kind, count);
	}
	m->s = saved;
	// The numbers up to the next keyword (or the end).
	while (true)
	{
		saved = m->s;
		if (!fmScan_Next(&m->s))
			return;
		if (fmMeditIsKeyword(&m->s))
		{
			m->s = saved;
			return;
		}
	}
}

static fmResult fmMeditSections(fmMedit* m)
{
	fmScan* s = &m->s;
	fmResult result = fmScan_Word(s, "MeshVersionFormatted", true);
	if (result != fm_ok)
		return s->tokenLength == 0
		           ? fmScan_Error(s, fm_errEmpty, "empty file: expected \"MeshVersionFormatted\"")
		           : result;
	long long value = 0;
	result = fmScan_Int64(s, "mesh version", 1, 4, &value);
	bool end = false;
	while (result == fm_ok && !end && fmScan_Next(s))
	{
		if (!fmMeditIsKeyword(s))
			result =
			    fmScan_Error(s, fm_errSyntax,
			                 "\"%.*s\" where a keyword was expected (Vertices, Tetrahedra, ...)",
			                 (int)(s->tokenLength < 40 ? s->tokenLength : 40), s->token);
		else if (fmScan_IsNoCase(s, "Dimension"))
			result = fmScan_Int64(s, "dimension", 3, 3, &value);
		else if (fmScan_IsNoCase(s, "Vertices"))
			result = fmMeditVertices(m);
		else if (fmScan_IsNoCase(s, "Tetrahedra"))
			result = fmMeditTetrahedra(m);
		else if (fmScan_IsNoCase(s, "End"))
			end = true;
		else
			fmMeditSkip(m);
	}
	if (result == fm_ok && m->positions == NULL)
		result = fmScan_Error(s, fm_errEmpty, "the file has no Vertices: expected a mesh");
	return result;
}

fmResult fmParseMedit(const void* data, size_t size, const char* name, fmTetMesh* mesh,
                      fmDiagnostic* diag)
{
	fmMedit m;
	memset(&m, 0, sizeof m);
	fmScan_Init(&m.s, data, size, name, diag);
	m.s.hashComments = true;
	fmResult result = fmMeditSections(&m);
	if (result != fm_ok)
	{
		fmTetList_Free(&m.tets);
		FM_FREE_ARRAY(m.positions, double, 3 * (size_t)m.nodeCount);
		return result;
	}
	return fmTetList_Finish(&m.tets, m.positions, m.nodeCount, 1, name, mesh, diag);
}
