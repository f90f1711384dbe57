// The checking kit for JSON input (see json_check.h): every member checked for type and range,
// every error named by its JSON path ("bodies[0].material.youngs_modulus") and, when it can be
// found, its line and column; syntax errors say what was found where.
#include "json_check.h"
#include "json_locate.h"

#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const cliRange cliAnyFinite = {-INFINITY, INFINITY, true, true};
const cliRange cliPositive = {0.0, INFINITY, true, true};
const cliRange cliNonNegative = {0.0, INFINITY, false, true};
const cliRange cliUnit = {0.0, 1.0, false, false};

// ---- messages -------------------------------------------------------------------------------

// 1-based line and column of byte @p offset in @p text.
static void cliLineColumn(const char* text, size_t offset, int* line, int* column)
{
	*line = 1;
	*column = 1;
	for (size_t i = 0; i < offset && text[i] != 0; ++i)
	{
		if (text[i] == '\n')
		{
			*line += 1;
			*column = 1;
		}
		else
			*column += 1;
	}
}

// The tree keeps no positions: walk the text to the path's key.
static bool cliFindKeyLine(const cliJson* j, const char* path, int* line, int* column)
{
	size_t offset = 0;
	if (!cliJsonLocate(j->text, j->size, path, &offset))
		return false;
	cliLineColumn(j->text, offset, line, column);
	return true;
}

// Print "file[:line:column]: path: message[, got VALUE]" to j->messages and return false.
bool cliJsonFail(const cliJson* j, const char* path, const cliJsonNode* got, const char* format,
                 ...)
{
	char where[CLI_MAX_PATH + 300], message[1024], value[80] = "";
	int line = 0, column = 0;
	if (path[0] != 0 && cliFindKeyLine(j, path, &line, &column))
		snprintf(where, sizeof where, "%s:%d:%d: %s: ", j->file, line, column, path);
	else if (path[0] != 0)
		snprintf(where, sizeof where, "%s: %s: ", j->file, path);
	else
		snprintf(where, sizeof where, "%s: ", j->file);
	va_list args;
	va_start(args, format);
	vsnprintf(message, sizeof message, format, args);
	va_end(args);
	if (got != NULL && got->kind == cli_jsonNumber && !isfinite(got->number))
		snprintf(value, sizeof value, ", got a number beyond a double's range (1.8e308)");
	else if (got != NULL)
	{
		char printed[64];
		size_t length = cliJsonTree_Print(got, printed, sizeof printed);
		snprintf(value, sizeof value, length > 60 ? ", got %.57s..." : ", got %s", printed);
	}
	if (j->messages != NULL)
		fprintf(j->messages, "%s%s%s\n", where, message, value);
	return false;
}

// "parent.key" (or "key" at the top); a path too long for the buffer is cut, which only
// shortens a message.
void cliJoinKey(char* out, size_t size, const char* parent, const char* key)
{
	int written =
	    parent[0] == 0 ? snprintf(out, size, "%s", key) : snprintf(out, size, "%s.%s", parent, key);
	if (written < 0)
		out[0] = 0;
}

static void cliDescribeRange(cliRange range, char* out, size_t size)
{
	bool hasLo = isfinite(range.lo), hasHi = isfinite(range.hi);
	if (!hasLo && !hasHi)
		snprintf(out, size, "a finite number");
	else if (!hasHi)
		snprintf(out, size, "a number %s %g", range.loOpen ? ">" : ">=", range.lo);
	else if (!hasLo)
		snprintf(out, size, "a number %s %g", range.hiOpen ? "<" : "<=", range.hi);
	else
		snprintf(out, size, "a number in %c%g, %g%c", range.loOpen ? '(' : '[', range.lo, range.hi,
		         range.hiOpen ? ')' : ']');
}

bool cliInRange(double value, cliRange range)
{
	if (!isfinite(value))
		return false;
	if (range.loOpen ? !(value > range.lo) : !(value >= range.lo))
		return false;
	if (range.hiOpen ? !(value < range.hi) : !(value <= range.hi))
		return false;
	return true;
}

// ---- typed readers: absent keys leave the value alone -----------------------------------------

// Reject keys not in @p allowed (NULL-terminated, at most CLI_MAX_KEYS) and repeated keys. One
// pass over the members: each is looked up in the short allowed list and marked seen there.
bool cliCheckKeys(const cliJson* j, const cliJsonNode* object, const char* parent,
                  const char* const* allowed)
{
	bool seen[CLI_MAX_KEYS] = {false};
	const cliJsonNode* item = NULL;
	for (item = (object)->child; item != NULL; item = item->next)
	{
		char path[256];
		cliJoinKey(path, sizeof path, parent, item->key);
		int known = -1;
		for (int i = 0; allowed[i] != NULL && known < 0; ++i)
			if (strcmp(item->key, allowed[i]) == 0)
				known = i;
		if (known < 0)
		{
			char list[512] = "";
			for (int i = 0; allowed[i] != NULL; ++i)
			{
				strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
				strncat(list, allowed[i], sizeof list - strlen(list) - 1);
			}
			return cliJsonFail(j, path, NULL, "unknown key (expected one of: %s)", list);
		}
		FM_ASSERT(known < CLI_MAX_KEYS);
		if (seen[known])
			return cliJsonFail(j, path, NULL, "key given twice");
		seen[known] = true;
	}
	return true;
}

// The member @p key of @p object, NULL when absent (*present says which, when asked), and its
// path in @p path when present: the start of every reader below.
static const cliJsonNode* cliMember(const cliJsonNode* object, const char* parent, const char* key,
                                    bool* present, char* path, size_t size)
{
	const cliJsonNode* item = cliJsonTree_Member(object, key);
	if (present != NULL)
		*present = item != NULL;
	if (item != NULL)
		cliJoinKey(path, size, parent, key);
	return item;
}

bool cliGetNumber(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  cliRange range, double* value, bool* present)
{
	char path[256], expected[96];
	const cliJsonNode* item = cliMember(object, parent, key, present, path, sizeof path);
	if (item == NULL)
		return true;
	cliDescribeRange(range, expected, sizeof expected);
	if (!cliJsonIs(item, cli_jsonNumber) || !cliInRange(item->number, range))
		return cliJsonFail(j, path, item, "expected %s", expected);
	*value = item->number;
	return true;
}

bool cliGetInt(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
               int lo, int hi, int* value, bool* present)
{
	char path[256];
	const cliJsonNode* item = cliMember(object, parent, key, present, path, sizeof path);
	if (item == NULL)
		return true;
	double number = cliJsonIs(item, cli_jsonNumber) ? item->number : NAN;
	if (!isfinite(number) || number != floor(number))
		return cliJsonFail(j, path, item, "expected an integer in [%d, %d]", lo, hi);
	if (number > hi)
		return cliJsonFail(j, path, item, "too large (at most %d)", hi);
	if (number < lo)
		return cliJsonFail(j, path, item, "too small (at least %d)", lo);
	*value = (int)number;
	return true;
}

bool cliGetBool(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                bool* value)
{
	char path[256];
	const cliJsonNode* item = cliMember(object, parent, key, NULL, path, sizeof path);
	if (item == NULL)
		return true;
	if (!cliJsonIs(item, cli_jsonBool))
		return cliJsonFail(j, path, item, "expected true or false");
	*value = item->boolean;
	return true;
}

bool cliGetString(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  const char** value)
{
	char path[256];
	const cliJsonNode* item = cliMember(object, parent, key, NULL, path, sizeof path);
	if (item == NULL)
		return true;
	if (!cliJsonIs(item, cli_jsonString) || item->string == NULL)
		return cliJsonFail(j, path, item, "expected a string");
	*value = item->string;
	return true;
}

bool cliGetVec3(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                fmVec3* value, bool* present)
{
	char path[256];
	const cliJsonNode* item = cliMember(object, parent, key, present, path, sizeof path);
	if (item == NULL)
		return true;
	double xyz[3];
	int count = 0;
	const cliJsonNode* element = NULL;
	if (!cliJsonIs(item, cli_jsonArray))
		return cliJsonFail(j, path, item, "expected an array of 3 numbers [x, y, z]");
	// One walk that stops at a fourth element: a long array costs no more than a short one.
	for (element = (item)->child; element != NULL; element = element->next)
	{
		if (count == 3)
			return cliJsonFail(j, path, item, "expected an array of 3 numbers [x, y, z]");
		if (!cliJsonIs(element, cli_jsonNumber) || !isfinite(element->number))
			return cliJsonFail(j, path, item, "expected an array of 3 finite numbers [x, y, z]");
		xyz[count++] = element->number;
	}
	if (count != 3)
		return cliJsonFail(j, path, item, "expected an array of 3 numbers [x, y, z]");
	*value = fmMakeVec3(xyz[0], xyz[1], xyz[2]);
	return true;
}

// An optional object member: NULL if absent; fails on a non-object.
bool cliGetObject(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  const cliJsonNode** value)
{
	*value = NULL;
	char path[256];
	const cliJsonNode* item = cliMember(object, parent, key, NULL, path, sizeof path);
	if (item == NULL)
		return true;
	if (!cliJsonIs(item, cli_jsonObject))
		return cliJsonFail(j, path, item, "expected an object {...}");
	*value = item;
	return true;
}

// The keys @p keys (NULL-terminated) must all be present; @p what says why.
bool cliRequireKeys(const cliJson* j, const cliJsonNode* object, const char* path,
                    const char* const* keys, const char* what)
{
	for (int i = 0; keys[i] != NULL; ++i)
		if (cliJsonTree_Member(object, keys[i]) == NULL)
			return cliJsonFail(j, path, NULL, "missing \"%s\" (%s)", keys[i], what);
	return true;
}

// A vector key whose coordinates must each lie in @p range (@p expected says so).
bool cliGetVec3In(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  cliRange range, const char* expected, fmVec3* value)
{
	bool present = false;
	if (!cliGetVec3(j, object, parent, key, value, &present))
		return false;
	if (!present ||
	    (cliInRange(value->x, range) && cliInRange(value->y, range) && cliInRange(value->z, range)))
		return true;
	char path[256];
	cliJoinKey(path, sizeof path, parent, key);
	return cliJsonFail(j, path, cliJsonTree_Member(object, key), "expected %s", expected);
}

// A 32-bit mask: an integer in [0, 2^32 - 1] (JSON numbers hold it exactly).
bool cliGetBits(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                uint32_t* value)
{
	char path[256];
	const cliJsonNode* item = cliMember(object, parent, key, NULL, path, sizeof path);
	if (item == NULL)
		return true;
	double number = cliJsonIs(item, cli_jsonNumber) ? item->number : NAN;
	if (!(number >= 0.0 && number <= 4294967295.0) || number != floor(number))
		return cliJsonFail(j, path, item, "expected an integer in [0, 4294967295] (32 bits)");
	*value = (uint32_t)number;
	return true;
}

// ---- files named in the text -----------------------------------------------------------------

bool cliResolveFile(const cliJson* j, const char* path, const cliJsonNode* item, const char* text,
                    char* out, size_t size)
{
	// Relative paths are relative to the file's folder, so scenes can be run from anywhere.
	int written = text[0] == '/' ? snprintf(out, size, "%s", text)
	                             : snprintf(out, size, "%s%s", j->folder, text);
	if (written < 0 || (size_t)written >= size)
		return cliJsonFail(j, path, item, "path too long");
	const char* why = cliFileUnreadable(out);
	if (why != NULL)
		return cliJsonFail(j, path, NULL,
		                   "cannot open %s: %s (\"%s\" is relative to the scene's folder)", out,
		                   why, text);
	return true;
}

// ---- lists of entries -----------------------------------------------------------------------

bool cliGetEntries(const cliJson* j, const cliJsonNode* object, const char* parent,
                   const cliEntryList* list, void** entries, int* count)
{
	char path[256];
	const cliJsonNode* array = cliMember(object, parent, list->key, NULL, path, sizeof path);
	if (array == NULL)
		return true;
	if (!cliJsonIs(array, cli_jsonArray))
		return cliJsonFail(j, path, array, "expected a list of %s", list->expected);
	int size = array->count;
	*entries = calloc((size_t)(size > 0 ? size : 1), list->size);
	if (*entries == NULL)
		return cliJsonFail(j, path, NULL, "out of memory");
	const cliJsonNode* entry = NULL;
	for (entry = array->child; entry != NULL; entry = entry->next)
	{
		char entryPath[300];
		if (snprintf(entryPath, sizeof entryPath, "%s[%d]", path, *count) < 0)
			entryPath[0] = 0;
		if (!cliJsonIs(entry, cli_jsonObject))
			return cliJsonFail(j, entryPath, entry, "expected %s", list->expected);
		void* out = (char*)*entries + (size_t)*count * list->size;
		if (!cliCheckKeys(j, entry, entryPath, list->keys) || !list->read(j, entry, entryPath, out))
			return false;
		*count += 1;
	}
	return true;
}

// ---- syntax ---------------------------------------------------------------------------------

// "file:line:column: message" for byte @p offset of the text.
static bool cliJsonFailAt(const cliJson* j, size_t offset, const char* format, ...)
    __attribute__((format(printf, 3, 4)));
static bool cliJsonFailAt(const cliJson* j, size_t offset, const char* format, ...)
{
	int line, column;
	cliLineColumn(j->text, offset, &line, &column);
	char message[512];
	va_list args;
	va_start(args, format);
	vsnprintf(message, sizeof message, format, args);
	va_end(args);
	if (j->messages != NULL)
		fprintf(j->messages, "%s:%d:%d: %s\n", j->file, line, column, message);
	return false;
}

// What the text holds at @p offset, for messages: up to 24 bytes of its line in quotes
// (other bytes than printable ASCII as '?'), or "the end of the file".
static void cliDescribeText(const cliJson* j, size_t offset, char* out, size_t size)
{
	size_t rest = offset;
	while (rest < j->size && strchr(" \t\r\n", j->text[rest]) != NULL)
		rest += 1;
	if (rest >= j->size)
	{
		snprintf(out, size, "the end of the file");
		return;
	}
	char shown[32];
	size_t n = 0;
	for (size_t i = offset; i < j->size && n < 24 && j->text[i] != '\n' && j->text[i] != '\r'; ++i)
	{
		unsigned char c = (unsigned char)j->text[i];
		shown[n++] = c >= 32 && c < 127 ? (char)c : '?';
	}
	shown[n] = 0;
	bool cut = offset + n < j->size && j->text[offset + n] != '\n' && j->text[offset + n] != '\r';
	snprintf(out, size, "'%s%s'", shown, cut ? "..." : "");
}

// Containers open at byte @p offset (strings skipped): tells a nesting limit from a syntax error.
// With @p tooDeep, the walk stops at the first bracket that opens more than CLI_JSON_MAX_DEPTH
// containers and stores its offset there (left alone when there is none).
static int cliJsonDepthAt(const cliJson* j, size_t offset, size_t* tooDeep)
{
	int depth = 0;
	bool inString = false;
	for (size_t i = 0; i < offset && i < j->size; ++i)
	{
		char c = j->text[i];
		if (inString)
		{
			if (c == '\\')
				++i;
			else if (c == '"')
				inString = false;
		}
		else if (c == '"')
			inString = true;
		else if ((c == '{' || c == '[') && tooDeep != NULL && depth >= CLI_JSON_MAX_DEPTH)
		{
			*tooDeep = i;
			return depth;
		}
		else if (c == '{' || c == '[')
			++depth;
		else if (c == '}' || c == ']')
			--depth;
	}
	return depth;
}

// Both parsers decode "\u0000" into a NUL byte that ends a C string, silently truncating the
// string (a key "mesh\u0000x" would read as "mesh"). Find the first such escape in valid JSON.
static bool cliFindNulEscape(const cliJson* j, size_t* offset)
{
	bool inString = false;
	for (size_t i = 0; i < j->size; ++i)
	{
		char c = j->text[i];
		if (!inString)
			inString = c == '"';
		else if (c == '"')
			inString = false;
		else if (c == '\\')
		{
			if (i + 5 < j->size && j->text[i + 1] == 'u' && memcmp(j->text + i + 2, "0000", 4) == 0)
			{
				*offset = i;
				return true;
			}
			++i; // the escaped character
		}
	}
	return false;
}

// The first offset at or after @p at that is not JSON whitespace (j->size at the end).
static size_t cliSkipSpace(const cliJson* j, size_t at)
{
	while (at < j->size && strchr(" \t\r\n", j->text[at]) != NULL)
		at += 1;
	return at;
}

// A failed parse as a located message: what was found where, or the nesting limit named.
static void cliJsonSyntaxError(const cliJson* j, const cliJsonParse* parse)
{
	size_t offset = parse->offset, deep = SIZE_MAX;
	if (parse->outOfMemory)
	{
		if (j->messages != NULL)
			fprintf(j->messages, "%s: out of memory\n", j->file);
		return;
	}
	if (offset == SIZE_MAX)
	{
		// The JavaScript engine did not say where: the nesting limit, or its own words.
		cliJsonDepthAt(j, j->size, &deep);
		if (deep == SIZE_MAX && j->messages != NULL)
			fprintf(j->messages, "%s: JSON syntax error (%s)\n", j->file, parse->reason);
		if (deep == SIZE_MAX)
			return;
		offset = deep;
	}
	// A parser reports a text that ends too early at its last byte: point past it instead.
	if (cliSkipSpace(j, offset) >= j->size)
		offset = j->size; // only whitespace left: the file ended too early
	char found[48];
	cliDescribeText(j, offset, found, sizeof found);
	if (offset < j->size && (j->text[offset] == '{' || j->text[offset] == '[') &&
	    cliJsonDepthAt(j, offset, NULL) >= CLI_JSON_MAX_DEPTH)
		cliJsonFailAt(j, offset,
		              "JSON nested too deeply: more than %d arrays and objects inside each other",
		              CLI_JSON_MAX_DEPTH);
	else
		cliJsonFailAt(j, offset, "JSON syntax error at %s%s%s%s", found,
		              parse->reason[0] != 0 ? " (" : "", parse->reason,
		              parse->reason[0] != 0 ? ")" : "");
}

// JSON text to a tree, or a located message: a syntax error says what it found, a nesting limit
// is named, text after the scene object and NUL escapes are errors.
static cliJsonNode* cliParseJson(const cliJson* j)
{
	cliJsonParse parse;
	cliJsonNode* root = cliJsonTree_Parse(j->text, j->size, &parse);
	if (root == NULL)
	{
		cliJsonSyntaxError(j, &parse);
		return NULL;
	}
	// Only whitespace may follow the scene (the native parser stops after the first value and
	// would ignore a second object or any trailing text).
	size_t offset = cliSkipSpace(j, parse.end);
	size_t nul = 0;
	char found[48];
	if (offset < j->size)
	{
		cliDescribeText(j, offset, found, sizeof found);
		if (j->text[offset] == '{' || j->text[offset] == '[')
			cliJsonFailAt(j, offset,
			              "a second JSON value after the scene object, found %s (a scene file "
			              "holds one object)",
			              found);
		else
			cliJsonFailAt(j, offset, "text after the end of the scene object, found %s", found);
	}
	else if (cliFindNulEscape(j, &nul))
		cliJsonFailAt(j, nul,
		              "\\u0000 (a NUL character) in a string: scene strings cannot "
		              "hold one");
	else
		return root;
	cliJsonTree_Free(root);
	return NULL;
}

cliJsonNode* cliJsonOpen(cliJson* j, const char* name, const char* text, size_t size,
                         FILE* messages)
{
	memset(j, 0, sizeof *j);
	j->file = name;
	j->text = text;
	j->size = size;
	j->messages = messages;
	if (size > CLI_MAX_FILE_BYTES)
	{
		if (messages != NULL)
			fprintf(messages, "%s: %zu bytes, more than the %zu MiB limit\n", name, size,
			        CLI_MAX_FILE_BYTES >> 20);
		return NULL;
	}
	const char* nul = memchr(text, 0, size);
	if (nul != NULL)
	{
		cliJsonFailAt(j, (size_t)(nul - text), "NUL byte in a JSON file");
		return NULL;
	}
	// The folder of the file, with its trailing slash ("" for the current directory).
	const char* slash = strrchr(name, '/');
	size_t folderLength = slash ? (size_t)(slash - name) + 1 : 0;
	if (folderLength >= sizeof j->folder)
	{
		if (messages != NULL)
			fprintf(messages, "%s: path too long\n", name);
		return NULL;
	}
	memcpy(j->folder, name, folderLength);
	j->folder[folderLength] = 0;
	// A NUL-terminated copy: the line finder searches the text with strstr.
	j->copy = malloc(size + 1);
	if (j->copy == NULL)
	{
		if (messages != NULL)
			fprintf(messages, "%s: out of memory\n", name);
		return NULL;
	}
	memcpy(j->copy, text, size);
	j->copy[size] = 0;
	j->text = j->copy;
	return cliParseJson(j);
}

void cliJsonClose(cliJson* j, cliJsonNode* root)
{
	cliJsonTree_Free(root);
	free(j->copy);
	j->copy = NULL;
}
