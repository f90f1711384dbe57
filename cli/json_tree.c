// The JSON tree (see json_tree.h): the builder both parsers fill, the two parsers (cJSON natively,
// the JavaScript engine's JSON.parse in WebAssembly), look-ups and the compact printer.
#include "json_tree.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__EMSCRIPTEN__)
#include <emscripten/emscripten.h>
#else
#include <cjson/cJSON.h>
_Static_assert(CLI_JSON_MAX_DEPTH == CJSON_NESTING_LIMIT, "the tree's nesting limit is cJSON's");
#endif

// ---- building -------------------------------------------------------------------------------

static char* cliJsonCopyText(const char* text)
{
	size_t length = strlen(text);
	char* copy = malloc(length + 1);
	if (copy != NULL)
		memcpy(copy, text, length + 1);
	return copy;
}

static bool cliJsonBuildFail(cliJsonBuilder* b)
{
	b->failed = true;
	return false;
}

// A new node of @p kind for cliJsonBuild_Add, NULL when memory runs out.
static cliJsonNode* cliJsonNewNode(const char* key, cliJsonKind kind, double number,
                                   const char* text)
{
	cliJsonNode* node = calloc(1, sizeof *node);
	if (node == NULL)
		return NULL;
	node->kind = kind;
	node->boolean = kind == cli_jsonBool && number != 0.0;
	node->number = kind == cli_jsonNumber ? number : 0.0;
	node->string = kind == cli_jsonString ? cliJsonCopyText(text != NULL ? text : "") : NULL;
	node->key = key != NULL ? cliJsonCopyText(key) : NULL;
	if ((kind == cli_jsonString && node->string == NULL) || (key != NULL && node->key == NULL))
	{
		cliJsonTree_Free(node);
		return NULL;
	}
	return node;
}

bool cliJsonBuild_Add(cliJsonBuilder* b, const char* key, cliJsonKind kind, double number,
                      const char* text)
{
	bool inObject = b->open != NULL && b->open->kind == cli_jsonObject;
	bool container = kind == cli_jsonArray || kind == cli_jsonObject;
	if (b->failed || (b->open == NULL && b->root != NULL) || inObject != (key != NULL) ||
	    (container && b->depth >= CLI_JSON_MAX_DEPTH))
		return cliJsonBuildFail(b);
	cliJsonNode* node = cliJsonNewNode(key, kind, number, text);
	if (node == NULL)
		return cliJsonBuildFail(b);
	if (b->open == NULL)
		b->root = node;
	else
	{
		node->parent = b->open;
		if (b->open->last != NULL)
			b->open->last->next = node;
		else
			b->open->child = node;
		b->open->last = node;
		b->open->count += 1;
	}
	if (container)
	{
		b->open = node;
		b->depth += 1;
	}
	return true;
}

bool cliJsonBuild_Close(cliJsonBuilder* b)
{
	if (b->failed || b->open == NULL)
		return cliJsonBuildFail(b);
	b->open = b->open->parent;
	b->depth -= 1;
	return true;
}

// The tree of a builder that has taken one whole value, else NULL (what it built freed).
static cliJsonNode* cliJsonBuildFinish(cliJsonBuilder* b)
{
	free(b->scratch);
	if (!b->failed && b->root != NULL && b->open == NULL)
		return b->root;
	cliJsonTree_Free(b->root);
	return NULL;
}

// ---- parsing --------------------------------------------------------------------------------

#if defined(__EMSCRIPTEN__)

void* cliJsonBuild_Scratch(cliJsonBuilder* b, int size)
{
	if (size <= 0 || (size_t)size > b->scratchSize)
	{
		char* grown = realloc(b->scratch, size > 0 ? (size_t)size : 1);
		if (grown == NULL)
			return NULL;
		b->scratch = grown;
		b->scratchSize = size > 0 ? (size_t)size : 1;
	}
	return b->scratch;
}

int cliJsonBuild_AddFromJs(cliJsonBuilder* b, const char* key, int kind, double number,
                           const char* text)
{
	return cliJsonBuild_Add(b, key, (cliJsonKind)kind, number, text);
}

int cliJsonBuild_CloseFromJs(cliJsonBuilder* b)
{
	return cliJsonBuild_Close(b);
}

// JSON.parse the text and hand its values to the builder in document order (an object's keys in
// the engine's order). Returns -1 when parsed (*end: the bytes the value takes), else the byte
// offset of the error with the engine's message in @p reason. The engine does not always say
// where (nor in bytes): the offset is found as the first character whose prefix of the text is
// no longer the start of a JSON text, as cJSON finds it; when the text before that character is
// one whole value, it is parsed and the caller finds the text after it.
EM_JS(int, cliJsonParseInJs, (const char* text, int size, cliJsonBuilder* b, char* reason,
                              int* end), {
	const source = UTF8ToString(text, size);
	const fails = (k) => {
		try {
			JSON.parse(source.slice(0, k));
			return false;
		} catch (error) {
			const at = /position ([0-9]+)/.exec(error.message);
			return !/end of JSON input/.test(error.message) && !(at && Number(at[1]) >= k);
		}
	};
	let value;
	let used = source.length;
	try {
		value = JSON.parse(source);
	} catch (error) {
		stringToUTF8(String(error.message).split("\n")[0], reason, 160);
		let lo = 0;
		let hi = source.length;
		while (hi - lo > 1) {
			const mid = (lo + hi) >> 1;
			if (fails(mid)) hi = mid; else lo = mid;
		}
		used = hi - 1;
		try {
			value = JSON.parse(source.slice(0, used));
		} catch (ignored) {
			return lengthBytesUTF8(source.slice(0, used));
		}
	}
	HEAP32[end >> 2] = lengthBytesUTF8(source.slice(0, used));
	const add = (key, v) => {
		const kind = v === null ? 0 : typeof v === "boolean" ? 1 : typeof v === "number" ? 2 :
			typeof v === "string" ? 3 : Array.isArray(v) ? 4 : 5;
		const string = kind === 3 ? v : "";
		const keyBytes = key === null ? 0 : lengthBytesUTF8(key) + 1;
		const stringBytes = lengthBytesUTF8(string) + 1;
		const scratch = _cliJsonBuild_Scratch(b, keyBytes + stringBytes);
		if (!scratch) return false;
		if (key !== null) stringToUTF8(key, scratch, keyBytes);
		stringToUTF8(string, scratch + keyBytes, stringBytes);
		const number = kind === 1 ? Number(v) : kind === 2 ? v : 0;
		if (!_cliJsonBuild_AddFromJs(b, key === null ? 0 : scratch, kind, number, scratch + keyBytes))
			return false;
		if (kind < 4) return true;
		const keys = kind === 4 ? null : Object.keys(v);
		const items = kind === 4 ? v : keys.map((k) => v[k]);
		for (let i = 0; i < items.length; ++i)
			if (!add(keys === null ? null : keys[i], items[i])) return false;
		return _cliJsonBuild_CloseFromJs(b) !== 0;
	};
	add(null, value);
	return -1;
});

cliJsonNode* cliJsonTree_Parse(const char* text, size_t size, cliJsonParse* result)
{
	memset(result, 0, sizeof *result);
	cliJsonBuilder b;
	memset(&b, 0, sizeof b);
	int end = 0;
	int at = cliJsonParseInJs(text, (int)size, &b, result->reason, &end);
	if (at >= 0)
	{
		result->offset = (size_t)at;
		return NULL;
	}
	result->reason[0] = 0;
	result->end = (size_t)end;
	result->outOfMemory = b.failed && b.depth < CLI_JSON_MAX_DEPTH;
	result->offset = SIZE_MAX;
	if (b.failed && !result->outOfMemory)
		snprintf(result->reason, sizeof result->reason, "nested too deeply");
	return cliJsonBuildFinish(&b);
}

#else

// Add @p item (an object member when @p key is not NULL) and what it holds to the builder.
static bool cliJsonFromCjson(cliJsonBuilder* b, const cJSON* item, const char* key)
{
	cliJsonKind kind = cJSON_IsBool(item)     ? cli_jsonBool
	                   : cJSON_IsNumber(item) ? cli_jsonNumber
	                   : cJSON_IsString(item) ? cli_jsonString
	                   : cJSON_IsArray(item)  ? cli_jsonArray
	                   : cJSON_IsObject(item) ? cli_jsonObject
	                                          : cli_jsonNull;
	double number = kind == cli_jsonBool ? (cJSON_IsTrue(item) ? 1.0 : 0.0) : item->valuedouble;
	if (!cliJsonBuild_Add(b, key, kind, number, item->valuestring))
		return false;
	if (kind != cli_jsonArray && kind != cli_jsonObject)
		return true;
	const cJSON* child = NULL;
	cJSON_ArrayForEach(child, item)
	{
		if (!cliJsonFromCjson(b, child, kind == cli_jsonObject ? child->string : NULL))
			return false;
	}
	return cliJsonBuild_Close(b);
}

cliJsonNode* cliJsonTree_Parse(const char* text, size_t size, cliJsonParse* result)
{
	memset(result, 0, sizeof *result);
	const char* end = NULL;
	cJSON* root = cJSON_ParseWithLengthOpts(text, size, &end, false);
	size_t offset = end != NULL && end >= text ? (size_t)(end - text) : 0;
	if (root == NULL)
	{
		result->offset = offset;
		return NULL;
	}
	cliJsonBuilder b;
	memset(&b, 0, sizeof b);
	cliJsonFromCjson(&b, root, NULL);
	cJSON_Delete(root);
	result->end = offset;
	result->offset = SIZE_MAX;
	result->outOfMemory = b.failed;
	return cliJsonBuildFinish(&b);
}

#endif

// ---- reading --------------------------------------------------------------------------------

void cliJsonTree_Free(cliJsonNode* root)
{
	if (root == NULL)
		return;
	cliJsonNode* child = root->child;
	while (child != NULL)
	{
		cliJsonNode* next = child->next;
		cliJsonTree_Free(child);
		child = next;
	}
	free(root->string);
	free(root->key);
	free(root);
}

const cliJsonNode* cliJsonTree_Member(const cliJsonNode* object, const char* key)
{
	if (object == NULL || object->kind != cli_jsonObject)
		return NULL;
	for (const cliJsonNode* c = object->child; c != NULL; c = c->next)
		if (strcmp(c->key, key) == 0)
			return c;
	return NULL;
}

// ---- printing -------------------------------------------------------------------------------

// Text appended to a fixed buffer: cut to fit, counted whole.
typedef struct cliJsonSink
{
	char* out;
	size_t size;
	size_t length;
} cliJsonSink;

static void cliJsonPut(cliJsonSink* s, const char* text, size_t length)
{
	for (size_t i = 0; i < length; ++i, ++s->length)
		if (s->length + 1 < s->size)
			s->out[s->length] = text[i];
	if (s->size > 0)
		s->out[s->length < s->size ? s->length : s->size - 1] = 0;
}

// A number as cJSON prints one: an int's digits, else 15 significant digits when they read back,
// else 17; "null" for what JSON cannot hold.
static void cliJsonPutNumber(cliJsonSink* s, double d)
{
	char text[32];
	int whole = d >= (double)INT_MAX ? INT_MAX : d <= (double)INT_MIN ? INT_MIN : (int)d;
	if (!isfinite(d))
		snprintf(text, sizeof text, "null");
	else if (d == (double)whole)
		snprintf(text, sizeof text, "%d", whole);
	else
	{
		snprintf(text, sizeof text, "%1.15g", d);
		double back = strtod(text, NULL);
		if (!(fabs(back - d) <= fmax(fabs(back), fabs(d)) * 2.220446049250313e-16))
			snprintf(text, sizeof text, "%1.17g", d);
	}
	cliJsonPut(s, text, strlen(text));
}

// A string in quotes with cJSON's escapes.
static void cliJsonPutString(cliJsonSink* s, const char* text)
{
	cliJsonPut(s, "\"", 1);
	for (const unsigned char* c = (const unsigned char*)text; *c != 0; ++c)
	{
		const char* escape = *c == '"'    ? "\\\""
		                     : *c == '\\' ? "\\\\"
		                     : *c == '\b' ? "\\b"
		                     : *c == '\f' ? "\\f"
		                     : *c == '\n' ? "\\n"
		                     : *c == '\r' ? "\\r"
		                     : *c == '\t' ? "\\t"
		                                  : NULL;
		char code[8];
		if (escape == NULL && *c < 32)
		{
			snprintf(code, sizeof code, "\\u%04x", *c);
			escape = code;
		}
		if (escape != NULL)
			cliJsonPut(s, escape, strlen(escape));
		else
			cliJsonPut(s, (const char*)c, 1);
	}
	cliJsonPut(s, "\"", 1);
}

static void cliJsonPutNode(cliJsonSink* s, const cliJsonNode* node)
{
	switch (node->kind)
	{
	case cli_jsonNull:
		cliJsonPut(s, "null", 4);
		return;
	case cli_jsonBool:
		cliJsonPut(s, node->boolean ? "true" : "false", node->boolean ? 4 : 5);
		return;
	case cli_jsonNumber:
		cliJsonPutNumber(s, node->number);
		return;
	case cli_jsonString:
		cliJsonPutString(s, node->string);
		return;
	default:
		break;
	}
	bool object = node->kind == cli_jsonObject;
	cliJsonPut(s, object ? "{" : "[", 1);
	for (const cliJsonNode* c = node->child; c != NULL; c = c->next)
	{
		if (object)
		{
			cliJsonPutString(s, c->key);
			cliJsonPut(s, ":", 1);
		}
		cliJsonPutNode(s, c);
		if (c->next != NULL)
			cliJsonPut(s, ",", 1);
	}
	cliJsonPut(s, object ? "}" : "]", 1);
}

size_t cliJsonTree_Print(const cliJsonNode* node, char* out, size_t size)
{
	cliJsonSink s = {out, size, 0};
	if (size > 0)
		out[0] = 0;
	cliJsonPutNode(&s, node);
	return s.length;
}
