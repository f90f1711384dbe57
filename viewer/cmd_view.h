// `femto view [SCENE] [options]`: the interactive viewer (docs/viewer.md). Called by the tool
// through cli/viewer_hook.c.
#pragma once

/// Run the viewer; returns the process exit code (cli_exit*).
int fvViewMain(int argc, char** argv);
