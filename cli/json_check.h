// The checking kit for the tool's JSON input (scene files, docs/scene-format.md): a text opened
// with located syntax errors, typed readers of an object's members (numbers in ranges, integers,
// booleans, strings, vec3s, objects, lists of entries) that reject unknown and repeated keys,
// and messages "file:line:column: path: message" whose line json_locate.c finds. What the keys
// mean is the schema's business (scene.c, scene_body.c); this module only knows JSON.
#pragma once

#include "cli.h"

#include "json_tree.h"

#include <stdio.h>

/// A JSON text being read: the file name and text (for line numbers), its folder (for relative
/// paths) and where messages go (NULL: nowhere, for the fuzzer; they are still composed).
typedef struct cliJson
{
	const char* file;
	const char* text; ///< NUL-terminated once opened (a copy: the line finder uses strstr)
	size_t size;
	char folder[CLI_MAX_PATH]; ///< with its trailing slash ("" for the current directory)
	FILE* messages;
	char* copy; ///< malloc'd: the NUL-terminated copy of the text
} cliJson;

/// A numeric range; open ends exclude the bound, infinite bounds mean "unbounded".
typedef struct cliRange
{
	double lo;
	double hi;
	bool loOpen;
	bool hiOpen;
} cliRange;

extern const cliRange cliAnyFinite;   ///< any finite number
extern const cliRange cliPositive;    ///< (0, inf)
extern const cliRange cliNonNegative; ///< [0, inf)
extern const cliRange cliUnit;        ///< [0, 1]

/// Most keys one object of the format allows.
#define CLI_MAX_KEYS 32

/// Check the text @p text (@p size bytes, need not be NUL-terminated) named @p name and parse it:
/// the size limit, NUL bytes, syntax (with what was found where), nesting beyond CLI_JSON_MAX_DEPTH,
/// text after the first value and "\u0000" escapes are located errors. Returns the tree, or
/// NULL with the message printed to @p messages. Call cliJsonClose() in either case.
cliJsonNode* cliJsonOpen(cliJson* j, const char* name, const char* text, size_t size, FILE* messages);

/// Free @p root (may be NULL) and what cliJsonOpen() kept.
void cliJsonClose(cliJson* j, cliJsonNode* root);

/// Print "file[:line:column]: path: message[, got VALUE]" to j->messages and return false. The
/// line and column are the key's at @p path ("bodies[1].material.mu"; "" for the whole file).
bool cliJsonFail(const cliJson* j, const char* path, const cliJsonNode* got, const char* format, ...)
    __attribute__((format(printf, 4, 5)));

/// "parent.key" (or "key" at the top); a path too long for the buffer is cut, which only
/// shortens a message.
void cliJoinKey(char* out, size_t size, const char* parent, const char* key);

/// Whether @p value is finite and within @p range.
bool cliInRange(double value, cliRange range);

// The readers below take the object, its path (@p parent) and a key. An absent key leaves the
// value alone (and sets *present false where asked); a wrong value fails with a located message.

/// Reject keys not in @p allowed (NULL-terminated, at most CLI_MAX_KEYS) and repeated keys.
bool cliCheckKeys(const cliJson* j, const cliJsonNode* object, const char* parent,
                  const char* const* allowed);

/// The keys @p keys (NULL-terminated) must all be present; @p what says why.
bool cliRequireKeys(const cliJson* j, const cliJsonNode* object, const char* path,
                    const char* const* keys, const char* what);

/// A number in @p range.
bool cliGetNumber(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  cliRange range, double* value, bool* present);

/// An integer in [@p lo, @p hi] ("too large (at most N)", "too small (at least N)").
bool cliGetInt(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key, int lo,
               int hi, int* value, bool* present);

/// A 32-bit mask: an integer in [0, 2^32 - 1] (JSON numbers hold it exactly).
bool cliGetBits(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                uint32_t* value);

/// true or false.
bool cliGetBool(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                bool* value);

/// A string (*value points into the tree).
bool cliGetString(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  const char** value);

/// An array of 3 finite numbers [x, y, z].
bool cliGetVec3(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                fmVec3* value, bool* present);

/// A vec3 whose coordinates each lie in @p range (@p expected says so in the message).
bool cliGetVec3In(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  cliRange range, const char* expected, fmVec3* value);

/// An object member: *value NULL if absent; fails on a non-object.
bool cliGetObject(const cliJson* j, const cliJsonNode* object, const char* parent, const char* key,
                  const cliJsonNode** value);

/// The file named by @p text (the string at @p path, @p item) into @p out: relative to the
/// JSON file's folder unless absolute. Fails when the path is too long or the file cannot be
/// opened for reading.
bool cliResolveFile(const cliJson* j, const char* path, const cliJsonNode* item, const char* text,
                    char* out, size_t size);

/// Reads one entry of a list into @p out, its slot in the list's array; @p path is the entry's
/// ("bodies[0].loads[2]"). The entry is an object whose keys are already checked.
typedef bool cliEntryReader(const cliJson* j, const cliJsonNode* entry, const char* path, void* out);

/// A list of objects under one key ("loads": [{"min": ..., "max": ..., "force": ...}, ...]).
typedef struct cliEntryList
{
	const char* key;         ///< the list's key in its parent object
	const char* expected;    ///< one entry's form, for messages
	const char* const* keys; ///< the keys an entry allows, NULL-terminated
	size_t size;             ///< bytes of one read entry
	cliEntryReader* read;    ///< reads one entry
} cliEntryList;

/// Read the list @p list->key of @p object (absent: nothing read, *entries left alone). The
/// list is walked once; *entries gets a calloc'd array for all its entries before the first is
/// read (the caller frees it, on failure too) and *count (0 on entry) counts the entries read.
/// Fails on a non-array, a non-object entry, an entry's unknown or repeated key, or what @p
/// list->read rejects.
bool cliGetEntries(const cliJson* j, const cliJsonNode* object, const char* parent,
                   const cliEntryList* list, void** entries, int* count);
