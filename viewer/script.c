// The script reader (script.h): a line-based format, every error located as "file:line:".
#include "script.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

// Hard limits: a script is a test or a demo, not a data file.
#define FV_MAX_SCRIPT_LINE 512
#define FV_MAX_ACTIONS 100000
#define FV_MAX_FRAME 10000000

const char* const fvScriptKeys[] = {"space", "p", "s", "n", "r", "i", "m", "f", NULL};
static const char* const fvSliders[] = {"youngs", "poisson",  "mass", "damping",
                                        "dt",     "substeps", NULL};
static const char* const fvToggles[] = {"surfaces",  "stress",  "tets",    "inverted",
                                        "pins",      "targets", "floor",   "contacts",
                                        "colliders", "fibres",  "plastic", NULL};

// The words of one line (at most 16), split on blanks; the line is modified.
static int fvSplit(char* line, char* words[16])
{
	int count = 0;
	for (char* word = strtok(line, " \t\r\n"); word != NULL && count < 16;
	     word = strtok(NULL, " \t\r\n"))
		words[count++] = word;
	return count;
}

static bool fvNumber(const char* text, double* value)
{
	char* end = NULL;
	errno = 0;
	*value = strtod(text, &end);
	return end != text && *end == 0 && errno == 0 && isfinite(*value);
}

static bool fvFraction(const char* text, float* value)
{
	double v = 0.0;
	if (!fvNumber(text, &v) || v < 0.0 || v > 1.0)
		return false;
	*value = (float)v;
	return true;
}

static bool fvOneOf(const char* word, const char* const* names)
{
	for (int i = 0; names[i] != NULL; ++i)
		if (strcmp(word, names[i]) == 0)
			return true;
	return false;
}

// Parse "drag X Y to X2 Y2 [over N]" from words[2...]; an error message or NULL.
static const char* fvParseDrag(char** w, int n, fvAction* a)
{
	a->kind = fv_actionDrag;
	a->over = 10;
	// at FRAME drag X Y to X2 Y2 [over N]: 8 or 10 words.
	if (n != 8 && n != 10)
		return "expected 'drag X Y to X2 Y2 [over FRAMES]'";
	if (strcmp(w[5], "to") != 0)
		return "expected 'to' between the drag's two points";
	if (!fvFraction(w[3], &a->from[0]) || !fvFraction(w[4], &a->from[1]) ||
	    !fvFraction(w[6], &a->to[0]) || !fvFraction(w[7], &a->to[1]))
		return "expected window fractions in [0, 1] after 'drag' and 'to'";
	double over = 0.0;
	if (n == 10 && (strcmp(w[8], "over") != 0 || !fvNumber(w[9], &over) || over < 1.0 ||
	                over > 100000.0 || over != floor(over)))
		return "expected 'over FRAMES' with FRAMES a whole number in [1, 100000]";
	if (n == 10)
		a->over = (int)over;
	return NULL;
}

// What follows "at FRAME": an error message or NULL.
static const char* fvParseAction(char** w, int n, fvAction* a)
{
	const char* verb = w[2];
	if (strcmp(verb, "drag") == 0)
		return fvParseDrag(w, n, a);
	if (strcmp(verb, "release") == 0)
	{
		a->kind = fv_actionRelease;
		return n == 3 ? NULL : "expected nothing after 'release'";
	}
	bool named =
	    strcmp(verb, "key") == 0 || strcmp(verb, "toggle") == 0 || strcmp(verb, "scene") == 0;
	if (n != 4 && strcmp(verb, "slider") != 0)
		return named ? "expected one name after the verb"
		             : "expected drag, release, key, slider, toggle or scene after 'at FRAME'";
	if (strcmp(verb, "key") == 0)
	{
		a->kind = fv_actionKey;
		snprintf(a->name, sizeof a->name, "%s", w[3]);
		return fvOneOf(w[3], fvScriptKeys) ? NULL : "expected a key: space, p, s, n, r, i, m, f";
	}
	if (strcmp(verb, "toggle") == 0)
	{
		a->kind = fv_actionToggle;
		snprintf(a->name, sizeof a->name, "%s", w[3]);
		return fvOneOf(w[3], fvToggles) ? NULL
		                                : "expected a view: surfaces, stress, tets, inverted, "
		                                  "pins, targets, floor, contacts, colliders, fibres, "
		                                  "plastic";
	}
	if (strcmp(verb, "scene") == 0)
	{
		a->kind = fv_actionScene;
		snprintf(a->name, sizeof a->name, "%s", w[3]);
		return NULL;
	}
	if (strcmp(verb, "slider") == 0)
	{
		a->kind = fv_actionSlider;
		if (n != 5 || !fvOneOf(w[3], fvSliders))
			return "expected 'slider NAME VALUE' with NAME youngs, poisson, mass, damping, dt "
			       "or substeps";
		snprintf(a->name, sizeof a->name, "%s", w[3]);
		if (!fvNumber(w[4], &a->value))
			return "expected a number as the slider's value";
		if (strcmp(w[3], "substeps") == 0 &&
		    !(a->value >= 1.0 && a->value <= 1000.0 && a->value == floor(a->value)))
			return "expected a whole number of substeps in [1, 1000]";
		return NULL;
	}
	return "expected drag, release, key, slider, toggle or scene after 'at FRAME'";
}

// One non-blank line; an error message or NULL.
static const char* fvParseLine(char* text, fvAction* a)
{
	char* w[16];
	int n = fvSplit(text, w);
	double frame = 0.0;
	if (n < 3 || strcmp(w[0], "at") != 0)
		return "expected 'at FRAME ACTION'";
	if (!fvNumber(w[1], &frame) || frame < 0.0 || frame > FV_MAX_FRAME || frame != floor(frame))
		return "expected a frame number in [0, 10000000] after 'at'";
	a->frame = (int)frame;
	return fvParseAction(w, n, a);
}

static int fvCompareActions(const void* a, const void* b)
{
	const fvAction* x = a;
	const fvAction* y = b;
	if (x->frame != y->frame)
		return x->frame < y->frame ? -1 : 1;
	return x->line < y->line ? -1 : (x->line > y->line);
}

static bool fvScriptError(char* error, size_t size, const char* format, ...)
    __attribute__((format(printf, 3, 4)));

// Write an error; returns false.
static bool fvScriptError(char* error, size_t size, const char* format, ...)
{
	va_list args;
	va_start(args, format);
	vsnprintf(error, size, format, args);
	va_end(args);
	return false;
}

enum
{
	fv_lineEnd = 0, // no more lines
	fv_lineOk = 1,  // a line, NUL-terminated, its newline kept
	fv_lineTooLong, // more than the buffer holds before its newline
	fv_lineNul      // a NUL byte: the line up to it is in the buffer
};

// Read one line into @p line (@p size bytes) a byte at a time, so that a NUL byte in it is
// found (fgets would end the string there and the rest would look like a line too long).
static int fvReadLine(FILE* in, char* line, size_t size)
{
	size_t n = 0;
	int c = EOF;
	while (n + 1 < size && (c = getc(in)) != EOF)
	{
		if (c == 0)
		{
			line[n] = 0;
			return fv_lineNul;
		}
		line[n++] = (char)c;
		if (c == '\n')
			break;
	}
	line[n] = 0;
	if (n == 0)
		return fv_lineEnd;
	return line[n - 1] == '\n' || c == EOF ? fv_lineOk : fv_lineTooLong;
}

// Read the lines; false with the error written.
static bool fvReadLines(FILE* in, const char* path, fvScript* script, char* error, size_t size)
{
	char line[FV_MAX_SCRIPT_LINE + 2];
	int capacity = 0;
	int status = 0;
	for (int number = 1; (status = fvReadLine(in, line, sizeof line)) > 0; ++number)
	{
		if (status == fv_lineTooLong)
			return fvScriptError(error, size, "%s:%d: expected a line of at most %d characters",
			                     path, number, FV_MAX_SCRIPT_LINE);
		if (status == fv_lineNul)
			return fvScriptError(error, size,
			                     "%s:%d:%d: a NUL byte: expected text (is this a script?)", path,
			                     number, (int)strlen(line) + 1);
		char* start = line + strspn(line, " \t\r\n");
		if (*start == 0 || *start == '#')
			continue;
		if (script->count == FV_MAX_ACTIONS)
			return fvScriptError(error, size, "%s:%d: expected at most %d actions", path, number,
			                     FV_MAX_ACTIONS);
		if (script->count == capacity)
		{
			capacity = capacity ? 2 * capacity : 64;
			fvAction* grown = realloc(script->actions, (size_t)capacity * sizeof *grown);
			if (grown == NULL)
				return fvScriptError(error, size, "%s:%d: out of memory", path, number);
			script->actions = grown;
		}
		fvAction* a = &script->actions[script->count];
		memset(a, 0, sizeof *a);
		a->line = number;
		const char* problem = fvParseLine(start, a);
		if (problem != NULL)
			return fvScriptError(error, size, "%s:%d: %s", path, number, problem);
		script->count += 1;
	}
	if (ferror(in))
		return fvScriptError(error, size, "%s: cannot read: %s", path, strerror(errno));
	return true;
}

bool fvScript_Load(const char* path, fvScript* script, char* error, size_t errorSize)
{
	memset(script, 0, sizeof *script);
	FILE* in = fopen(path, "r");
	if (in == NULL)
	{
		snprintf(error, errorSize, "%s: cannot open: %s", path, strerror(errno));
		return false;
	}
	bool ok = fvScript_Read(in, path, script, error, errorSize);
	fclose(in);
	return ok;
}

bool fvScript_Read(FILE* in, const char* name, fvScript* script, char* error, size_t errorSize)
{
	memset(script, 0, sizeof *script);
	bool ok = fvReadLines(in, name, script, error, errorSize);
	if (!ok)
	{
		fvScript_Free(script);
		return false;
	}
	if (script->count > 0)
		qsort(script->actions, (size_t)script->count, sizeof *script->actions, fvCompareActions);
	return true;
}

void fvScript_Free(fvScript* script)
{
	free(script->actions);
	memset(script, 0, sizeof *script);
}
