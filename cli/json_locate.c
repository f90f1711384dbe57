// A small JSON walker that finds a path's position in the text (see json_locate.h). It skips
// values without building them; every read is bounds-checked, so malformed text just fails.
#include "json_locate.h"

#include <stdlib.h>
#include <string.h>

typedef struct cliCursor
{
	const char* text;
	size_t size;
	size_t at;
} cliCursor;

// Deeper nesting than cJSON accepts is not a valid scene anyway.
#define CLI_LOCATE_MAX_DEPTH 1000

static void cliSkipSpace(cliCursor* c)
{
	while (c->at < c->size && strchr(" \t\r\n", c->text[c->at]) != NULL && c->text[c->at] != 0)
		c->at += 1;
}

// Skip a string starting at its opening quote; false if unterminated.
static bool cliSkipString(cliCursor* c)
{
	c->at += 1;
	while (c->at < c->size)
	{
		char ch = c->text[c->at++];
		if (ch == '\\')
			c->at += 1;
		else if (ch == '"')
			return c->at <= c->size;
	}
	return false;
}

// Skip one value (object, array, string or scalar).
static bool cliSkipValue(cliCursor* c)
{
	cliSkipSpace(c);
	if (c->at >= c->size)
		return false;
	char first = c->text[c->at];
	if (first == '"')
		return cliSkipString(c);
	if (first != '{' && first != '[')
	{
		while (c->at < c->size && strchr(",}] \t\r\n", c->text[c->at]) == NULL)
			c->at += 1;
		return true;
	}
	// Containers: count brackets outside strings.
	int depth = 0;
	while (c->at < c->size)
	{
		char ch = c->text[c->at];
		if (ch == '"')
		{
			if (!cliSkipString(c))
				return false;
			continue;
		}
		c->at += 1;
		if (ch == '{' || ch == '[')
		{
			if (++depth > CLI_LOCATE_MAX_DEPTH)
				return false;
		}
		else if ((ch == '}' || ch == ']') && --depth == 0)
			return true;
	}
	return false;
}

// In the object at the cursor, move to the value of @p key (length @p length); *keyAt gets the
// offset of the key's quote.
static bool cliEnterKey(cliCursor* c, const char* key, size_t length, size_t* keyAt)
{
	cliSkipSpace(c);
	if (c->at >= c->size || c->text[c->at] != '{')
		return false;
	c->at += 1;
	for (;;)
	{
		cliSkipSpace(c);
		if (c->at >= c->size || c->text[c->at] != '"')
			return false;
		size_t start = c->at;
		if (!cliSkipString(c))
			return false;
		// Scene keys are plain ASCII: compare the raw text between the quotes.
		bool match = c->at - start - 2 == length && memcmp(c->text + start + 1, key, length) == 0;
		cliSkipSpace(c);
		if (c->at >= c->size || c->text[c->at] != ':')
			return false;
		c->at += 1;
		if (match)
		{
			*keyAt = start;
			cliSkipSpace(c);
			return true;
		}
		if (!cliSkipValue(c))
			return false;
		cliSkipSpace(c);
		if (c->at >= c->size || c->text[c->at] != ',')
			return false; // '}' : the key is not there
		c->at += 1;
	}
}

// In the array at the cursor, move to element @p index.
static bool cliEnterIndex(cliCursor* c, long index)
{
	cliSkipSpace(c);
	if (c->at >= c->size || c->text[c->at] != '[')
		return false;
	c->at += 1;
	for (long i = 0; i < index; ++i)
	{
		if (!cliSkipValue(c))
			return false;
		cliSkipSpace(c);
		if (c->at >= c->size || c->text[c->at] != ',')
			return false;
		c->at += 1;
	}
	cliSkipSpace(c);
	return c->at < c->size && c->text[c->at] != ']';
}

bool cliJsonLocate(const char* text, size_t size, const char* path, size_t* offset)
{
	cliCursor c = {text, size, 0};
	const char* p = path;
	bool found = false;
	while (*p != 0)
	{
		size_t length = strcspn(p, ".[");
		if (length > 0)
		{
			size_t keyAt = 0;
			char key[128];
			if (length >= sizeof key)
				return false;
			memcpy(key, p, length);
			key[length] = 0;
			if (!cliEnterKey(&c, key, length, &keyAt))
				return false;
			*offset = keyAt;
			found = true;
			p += length;
		}
		while (*p == '[')
		{
			char* end = NULL;
			long index = strtol(p + 1, &end, 10);
			if (end == p + 1 || *end != ']' || index < 0 || !cliEnterIndex(&c, index))
				return false;
			*offset = c.at;
			found = true;
			p = end + 1;
		}
		if (*p == '.')
			p += 1;
		else if (*p != 0)
			return false;
	}
	return found;
}
