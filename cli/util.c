// Shared pieces of the femto tool: messages, argument parsing, files, clocks.
#include "cli.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

void cliError(const char* format, ...)
{
	va_list args;
	va_start(args, format);
	fputs("femto: ", stderr);
	vfprintf(stderr, format, args);
	fputc('\n', stderr);
	va_end(args);
}

void cliWarn(const char* format, ...)
{
	va_list args;
	va_start(args, format);
	fputs("femto: warning: ", stderr);
	vfprintf(stderr, format, args);
	fputc('\n', stderr);
	va_end(args);
}

int cliUsageError(const char* command, const char* format, ...)
{
	va_list args;
	va_start(args, format);
	fputs("femto: ", stderr);
	vfprintf(stderr, format, args);
	fputc('\n', stderr);
	va_end(args);
	if (command != NULL)
		fprintf(stderr, "Try 'femto %s --help'.\n", command);
	else
		fprintf(stderr, "Try 'femto --help'.\n");
	return cli_exitUsage;
}

void cliPrintDiagnostic(const char* prefix, const fmDiagnostic* diag)
{
	char text[1024];
	fmDiagnostic_Format(diag, text, sizeof text);
	if (prefix != NULL)
		fprintf(stderr, "%s: %s\n", prefix, text);
	else
		fprintf(stderr, "%s\n", text);
}

bool cliParseDouble(const char* text, double* value)
{
	if (text == NULL || *text == 0)
		return false;
	char* end = NULL;
	errno = 0;
	double parsed = strtod(text, &end);
	if (errno != 0 || *end != 0 || !isfinite(parsed))
		return false;
	*value = parsed;
	return true;
}

bool cliParseInt(const char* text, int* value)
{
	if (text == NULL || *text == 0)
		return false;
	char* end = NULL;
	errno = 0;
	long parsed = strtol(text, &end, 10);
	if (errno != 0 || *end != 0 || parsed < INT_MIN || parsed > INT_MAX)
		return false;
	*value = (int)parsed;
	return true;
}

bool cliParseIntOption(const char* command, const char* option, const char* text, int lo, int hi,
                       int* value)
{
	char* end = NULL;
	errno = 0;
	long long parsed = text[0] != 0 ? strtoll(text, &end, 10) : 0;
	if (text[0] == 0 || end == NULL || *end != 0 || end == text)
	{
		cliUsageError(command, "%s: expected an integer in [%d, %d], got '%s'", option, lo, hi,
		              text);
		return false;
	}
	// strtoll saturates on overflow (ERANGE): the sign of the text says which way.
	bool tooLarge = errno == ERANGE ? strchr(text, '-') == NULL : parsed > hi;
	bool tooSmall = errno == ERANGE ? !tooLarge : parsed < lo;
	if (tooLarge)
	{
		cliUsageError(command, "%s: %s is too large (at most %d)", option, text, hi);
		return false;
	}
	if (tooSmall)
	{
		cliUsageError(command, "%s: %s is too small (at least %d)", option, text, lo);
		return false;
	}
	*value = (int)parsed;
	return true;
}

const char* cliOptionValue(const char* command, int argc, char** argv, int* index)
{
	const char* option = argv[*index];
	if (*index + 1 >= argc)
	{
		cliUsageError(command, "option %s needs a value", option);
		return NULL;
	}
	*index += 1;
	return argv[*index];
}

char* cliReadFile(const char* path, size_t* size)
{
	// Non-blocking open: a FIFO must not hang the tool until a writer appears.
	int fd = open(path, O_RDONLY | O_NONBLOCK);
	FILE* file = fd >= 0 ? fdopen(fd, "rb") : NULL;
	if (file == NULL)
	{
		fprintf(stderr, "%s: cannot open: %s\n", path, strerror(errno));
		if (fd >= 0)
			close(fd);
		return NULL;
	}
	// Only regular files (not a FIFO, a device such as /dev/zero or a folder), and not absurd
	// ones: a scene is a few kilobytes.
	struct stat info;
	if (fstat(fd, &info) != 0 || !S_ISREG(info.st_mode))
	{
		fprintf(stderr, "%s: not a regular file: expected a scene file on disk\n", path);
		fclose(file);
		return NULL;
	}
	if ((uint64_t)info.st_size > (uint64_t)CLI_MAX_FILE_BYTES)
	{
		fprintf(stderr, "%s: file is %lld bytes, more than the %zu MiB limit\n", path,
		        (long long)info.st_size, CLI_MAX_FILE_BYTES >> 20);
		fclose(file);
		return NULL;
	}
	size_t capacity = 4096, used = 0;
	char* buffer = malloc(capacity + 1);
	while (buffer != NULL)
	{
		if (used == capacity)
		{
			if (capacity >= CLI_MAX_FILE_BYTES)
			{
				fprintf(stderr, "%s: file exceeds the %zu MiB limit\n", path,
				        CLI_MAX_FILE_BYTES >> 20);
				free(buffer);
				fclose(file);
				return NULL;
			}
			capacity *= 2;
			char* grown = realloc(buffer, capacity + 1);
			if (grown == NULL)
			{
				free(buffer);
				buffer = NULL;
				break;
			}
			buffer = grown;
		}
		size_t got = fread(buffer + used, 1, capacity - used, file);
		used += got;
		if (got == 0)
			break;
	}
	if (buffer == NULL)
	{
		fprintf(stderr, "%s: out of memory\n", path);
		fclose(file);
		return NULL;
	}
	if (ferror(file))
	{
		fprintf(stderr, "%s: read error: %s\n", path, strerror(errno));
		free(buffer);
		fclose(file);
		return NULL;
	}
	fclose(file);
	buffer[used] = 0;
	*size = used;
	return buffer;
}

const char* cliFileUnreadable(const char* path)
{
	// Opened without blocking, then asked what it is: opening a FIFO for reading otherwise
	// waits for a writer that may never come.
	int fd = open(path, O_RDONLY | O_NONBLOCK);
	if (fd < 0)
		return strerror(errno);
	struct stat info;
	bool regular = fstat(fd, &info) == 0 && S_ISREG(info.st_mode);
	close(fd);
	return regular ? NULL : "not a regular file: expected a file on disk";
}

bool cliMakeDirectories(const char* path)
{
	char partial[CLI_MAX_PATH];
	size_t length = strlen(path);
	if (length == 0 || length >= sizeof partial)
	{
		fprintf(stderr, "%s: path is empty or too long\n", path);
		return false;
	}
	memcpy(partial, path, length + 1);
	// Create each prefix ending at a '/', then the whole path.
	for (size_t i = 1; i <= length; ++i)
	{
		if (partial[i] != '/' && partial[i] != 0)
			continue;
		char saved = partial[i];
		partial[i] = 0;
		if (mkdir(partial, 0777) != 0 && errno != EEXIST)
		{
			fprintf(stderr, "%s: cannot create directory: %s\n", partial, strerror(errno));
			return false;
		}
		partial[i] = saved;
	}
	struct stat info;
	if (stat(path, &info) != 0 || !S_ISDIR(info.st_mode))
	{
		fprintf(stderr, "%s: not a directory\n", path);
		return false;
	}
	return true;
}

bool cliJoinPath(char* out, size_t size, const char* directory, const char* name)
{
	size_t length = strlen(directory);
	const char* separator = (length > 0 && directory[length - 1] != '/') ? "/" : "";
	int written = snprintf(out, size, "%s%s%s", directory, separator, name);
	if (written < 0 || (size_t)written >= size)
	{
		fprintf(stderr, "%s/%s: path too long\n", directory, name);
		return false;
	}
	return true;
}

double cliNow(void)
{
	struct timespec now;
	clock_gettime(CLOCK_MONOTONIC, &now);
	return (double)now.tv_sec + 1e-9 * (double)now.tv_nsec;
}

bool cliStderrIsTty(void)
{
	return isatty(fileno(stderr)) != 0;
}

static struct
{
	int shown;
	bool muted;
	bool explicitStepWarned;
} cliLogState;

static void cliLog(fmLogLevel level, const char* message, void* context)
{
	(void)context;
	// Errors come back as result codes with a diagnostic the commands print themselves.
	if (level != fm_logWarning || cliLogState.muted)
		return;
	if (cliLogState.explicitStepWarned && strstr(message, "stability limit") != NULL)
		return;
	cliLogState.shown += 1;
	// The library's messages carry their own "file:line: warning:" prefix.
	if (cliLogState.shown <= 10)
		fprintf(stderr, "femto: %s\n", message);
	else if (cliLogState.shown == 11)
		fprintf(stderr, "femto: further library warnings not shown\n");
}

void cliInstallLogHook(void)
{
	fmSetLogFcn(cliLog, NULL);
}

void cliMuteLibraryWarnings(bool mute)
{
	cliLogState.muted = mute;
}

void cliNoteExplicitStepWarned(void)
{
	cliLogState.explicitStepWarned = true;
}

int cliCoresAvailable(void)
{
	long cores = sysconf(_SC_NPROCESSORS_ONLN);
	return cores < 1 ? 1 : cores > FM_MAX_WORKERS ? FM_MAX_WORKERS : (int)cores;
}

double* cliCopyState(fmBodyId body, bool velocities)
{
	int count = fmBody_GetVertexCount(body);
	double* state = malloc(sizeof(double) * 3 * (size_t)(count > 0 ? count : 1));
	if (state == NULL)
		return NULL;
	fmResult r = velocities ? fmBody_CopyVelocities(body, state, count)
	                        : fmBody_CopyPositions(body, state, count);
	if (r != fm_ok)
	{
		free(state);
		return NULL;
	}
	return state;
}
