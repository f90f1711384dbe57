// Where a JSON path ("bodies[1].material.mu") is in the text: cJSON keeps no positions, so
// error messages find their line by walking the text again.
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// Find @p path in the JSON @p text (@p size bytes). Components are object keys separated by
/// '.', each optionally followed by array indexes "[n]". On success *offset is the byte offset
/// of the last key's opening quote (or of the array element for a trailing index). Returns
/// false when the path is empty, malformed or absent. Safe on any text.
bool cliJsonLocate(const char* text, size_t size, const char* path, size_t* offset);
