// The subcommands of tiled jobs: `tincdt plan` and `tincdt merge` (the tile job itself is the
// main command with --plan and --tile). Each takes the arguments after its name (argv[0] is the
// subcommand) and returns the exit code: 0 ok, 1 error, 2 usage.
#pragma once

namespace tincdt::cli {

int run_plan(int argc, char** argv);
int run_merge(int argc, char** argv);

}  // namespace tincdt::cli
