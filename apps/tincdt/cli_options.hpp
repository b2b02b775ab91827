// The command line: every option the pipeline declares (each stage's Stage::options, then
// pipeline::job_options()) bound to CLI11 the same way, in the order of the stages, with its
// help, group, checks and default from the table; the stage list after the examples in --help
// comes from the stages' titles. Only the messages' verbosity, --help and --version are the
// command line's own.
#pragma once

#include <CLI/CLI.hpp>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/build.hpp"
#include "tiles/tile_job.hpp"

namespace tincdt::cli {

// Messages, the one setting that is not the job's.
struct Verbosity {
  bool quiet = false;
  bool verbose = false;
  bool progress = false;  // --progress: progress even with -q
};

// The help's "Usage:" lines, each ending with '\n'.
std::string usage();

// Defines every option of APP, each writing its value into OPTIONS (TILING for a tile job's, or
// VERBOSITY) as it is parsed. Each value goes through its option's check (CLI11 reports a refusal
// as a usage error); rules between options are tiles::check_options()'s.
void define_options(CLI::App& app, pipeline::BuildOptions& options, tiles::TileOptions& tiling,
                    Verbosity& verbosity);

// Appends the LAS classification codes of TEXT ("2,8") to CLASSES, for the build's and the tile
// commands' class filters; returns the first item that is not a code (0-255), if any.
std::optional<std::string> append_class_codes(const std::string& text,
                                              std::vector<std::uint8_t>& classes);

}  // namespace tincdt::cli
