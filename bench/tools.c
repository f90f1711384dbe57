// Programs on PATH, shell quoting, the bench's temporary folder (tools.h).
#include "tools.h"

#include "cli.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

bool cliBenchFindProgram(const char* name, char* out, size_t size)
{
	const char* path = getenv("PATH");
	if (path == NULL || strchr(name, '/') != NULL)
		return false;
	while (*path != '\0')
	{
		size_t length = strcspn(path, ":");
		// An empty entry means the current folder, as for the shell.
		int written = length == 0 ? snprintf(out, size, "./%s", name)
		                          : snprintf(out, size, "%.*s/%s", (int)length, path, name);
		struct stat info;
		if (written > 0 && (size_t)written < size && stat(out, &info) == 0 &&
		    S_ISREG(info.st_mode) && access(out, X_OK) == 0)
			return true;
		path += length + (path[length] == ':');
	}
	return false;
}

bool cliBenchAppendQuoted(char* command, size_t size, const char* text)
{
	size_t used = strlen(command), need = 3; // a space and two quotes
	for (const char* c = text; *c != '\0'; ++c)
		need += *c == '\'' ? 4 : 1;
	if (used + need >= size)
		return false;
	char* out = command + used;
	*out++ = ' ';
	*out++ = '\'';
	for (const char* c = text; *c != '\0'; ++c)
		if (*c == '\'')
		{
			memcpy(out, "'\\''", 4); // close, an escaped quote, reopen
			out += 4;
		}
		else
			*out++ = *c;
	*out++ = '\'';
	*out = '\0';
	return true;
}

bool cliBenchAppendText(char* command, size_t size, const char* text)
{
	size_t used = strlen(command), length = strlen(text);
	if (used + length >= size)
		return false;
	memcpy(command + used, text, length + 1);
	return true;
}

int cliBenchRunCommand(const char* command)
{
	fflush(stdout);
	int status = system(command);
	if (status == -1 || !WIFEXITED(status))
		return -1;
	return WEXITSTATUS(status);
}

bool cliBenchTempDir_Make(char* out, size_t size)
{
	const char* base = getenv("TMPDIR");
	if (base == NULL || base[0] == '\0')
		base = "/tmp";
	int written = snprintf(out, size, "%s/femto-bench.XXXXXX", base);
	if (written < 0 || (size_t)written >= size)
	{
		cliError("bench: TMPDIR is too long: %s", base);
		out[0] = '\0';
		return false;
	}
	if (mkdtemp(out) == NULL)
	{
		cliError("bench: cannot make a temporary folder in %s: %s", base, strerror(errno));
		out[0] = '\0';
		return false;
	}
	return true;
}

void cliBenchTempDir_Remove(const char* path)
{
	if (path == NULL || path[0] == '\0')
		return;
	DIR* folder = opendir(path);
	if (folder != NULL)
	{
		struct dirent* entry;
		char file[CLI_MAX_PATH];
		while ((entry = readdir(folder)) != NULL)
			if (strcmp(entry->d_name, ".") != 0 && strcmp(entry->d_name, "..") != 0 &&
			    cliJoinPath(file, sizeof file, path, entry->d_name))
				remove(file);
		closedir(folder);
	}
	if (rmdir(path) != 0)
		cliWarn("bench: cannot remove the temporary folder %s: %s", path, strerror(errno));
}

bool cliBenchTempName(const char* path, char* out, size_t size)
{
	const char* slash = strrchr(path, '/');
	size_t folder = slash != NULL ? (size_t)(slash - path) + 1 : 0;
	int written =
	    snprintf(out, size, "%.*s.%s.%ld.tmp", (int)folder, path, path + folder, (long)getpid());
	if (written < 0 || (size_t)written >= size)
	{
		cliError("%s: path too long", path);
		return false;
	}
	return true;
}
