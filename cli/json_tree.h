// The JSON tree the scene schema reads (json_check.h, scene.c, scene_body.c): nodes of six kinds
// with their children in order and each object member's key. One parse function fills it in
// every build: natively cJSON parses the text, in WebAssembly the JavaScript engine's own
// JSON.parse does (the page and Node.js), so the tool and the web page read scenes through the
// same schema code. The tree keeps no positions: messages find a path's line in the text
// (json_locate.h).
#pragma once

#include <stdbool.h>
#include <stddef.h>

#if defined(__EMSCRIPTEN__)
#include <emscripten/emscripten.h>
#endif

/// Deepest nesting of arrays and objects a text may have (cJSON's CJSON_NESTING_LIMIT).
#define CLI_JSON_MAX_DEPTH 1000

/// What a node holds.
typedef enum cliJsonKind
{
	cli_jsonNull,
	cli_jsonBool,
	cli_jsonNumber,
	cli_jsonString,
	cli_jsonArray,
	cli_jsonObject,
} cliJsonKind;

/// One value of a JSON text. Walk an array's or object's children with
/// `for (const cliJsonNode* c = node->child; c != NULL; c = c->next)`.
typedef struct cliJsonNode
{
	cliJsonKind kind;
	bool boolean;              ///< cli_jsonBool
	double number;             ///< cli_jsonNumber
	char* string;              ///< cli_jsonString: the text, NUL-terminated (malloc'd)
	char* key;                 ///< an object member's key (malloc'd); NULL elsewhere
	int count;                 ///< arrays and objects: children
	struct cliJsonNode* child; ///< the first child
	struct cliJsonNode* last;  ///< the last child
	struct cliJsonNode* next;  ///< the next sibling
	struct cliJsonNode* parent;
} cliJsonNode;

/// Whether @p node is there and of @p kind.
static inline bool cliJsonIs(const cliJsonNode* node, cliJsonKind kind)
{
	return node != NULL && node->kind == kind;
}

/// Builds a tree value by value, in document order (the parsers' common half).
typedef struct cliJsonBuilder
{
	cliJsonNode* root;
	cliJsonNode* open; ///< the container that takes the next value, NULL at the top
	int depth;         ///< containers open
	bool failed;       ///< out of memory, a key where none goes, or nesting too deep
	char* scratch;     ///< malloc'd: where the WebAssembly parser writes a key and a string
	size_t scratchSize;
} cliJsonBuilder;

/// Add a value to the open container (or as the root): a scalar of @p kind (@p number for
/// numbers and booleans, @p text for strings), or an empty array or object that then takes the
/// values added until cliJsonBuild_Close(). @p key names an object's member (NULL elsewhere).
/// Returns false (and marks the builder failed) on a misplaced value or memory running out.
bool cliJsonBuild_Add(cliJsonBuilder* b, const char* key, cliJsonKind kind, double number,
                      const char* text);

/// Close the open array or object.
bool cliJsonBuild_Close(cliJsonBuilder* b);

/// The result of parsing a text.
typedef struct cliJsonParse
{
	size_t end;        ///< success: the byte after the value (only whitespace may follow)
	size_t offset;     ///< failure: the byte where the syntax fails, SIZE_MAX when not known
	bool outOfMemory;  ///< failure: memory ran out (not the text's fault)
	char reason[160];  ///< failure: the JavaScript engine's message ("" natively)
} cliJsonParse;

/// Parse @p size bytes of @p text (no NUL bytes in them) into a tree (cliJsonTree_Free it), or
/// NULL with @p result saying where the text is wrong. Natively the text's first value is parsed
/// and result->end says where it ends; JSON.parse in WebAssembly takes the whole text.
cliJsonNode* cliJsonTree_Parse(const char* text, size_t size, cliJsonParse* result);

/// Free a tree (NULL is fine).
void cliJsonTree_Free(cliJsonNode* root);

/// The first member of @p object named @p key, NULL when absent or @p object is no object.
const cliJsonNode* cliJsonTree_Member(const cliJsonNode* object, const char* key);

/// Print @p node as compact JSON (cJSON's unformatted form) into @p out, cut to fit @p size;
/// returns the whole text's length, as snprintf does.
size_t cliJsonTree_Print(const cliJsonNode* node, char* out, size_t size);

#if defined(__EMSCRIPTEN__)
// The WebAssembly parser's door back into C: its JavaScript (cliJsonParseInJs) writes a key and a
// string into the scratch buffer and adds them, so no JavaScript string outlives the call.

/// The builder's scratch buffer, at least @p size bytes (NULL when memory runs out).
EMSCRIPTEN_KEEPALIVE void* cliJsonBuild_Scratch(cliJsonBuilder* b, int size);

/// cliJsonBuild_Add() for JavaScript (@p key NULL outside objects).
EMSCRIPTEN_KEEPALIVE int cliJsonBuild_AddFromJs(cliJsonBuilder* b, const char* key, int kind,
                                                double number, const char* text);

/// cliJsonBuild_Close() for JavaScript.
EMSCRIPTEN_KEEPALIVE int cliJsonBuild_CloseFromJs(cliJsonBuilder* b);
#endif
