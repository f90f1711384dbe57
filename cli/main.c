// femto: the command-line tool. Dispatches to the commands.
#include <femto/femto.h>

#include <stdio.h>
#include <string.h>

int main(int argc, char** argv)
{
	if (argc >= 2 && strcmp(argv[1], "--version") == 0)
	{
		fmVersion v = fmGetVersion();
		printf("femto %d.%d.%d\n", v.major, v.minor, v.patch);
		return 0;
	}
	fprintf(stderr, "usage: femto <run|info|static|bench> [options]\n");
	return 2;
}
