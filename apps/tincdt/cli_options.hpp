// The command line, bound directly to pipeline::BuildOptions: one CLI11 option per field, word
// choices mapped to the library's enums, help groups in the order of the stages.
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
};

// Defines every option of APP, each writing its value into OPTIONS (TILING for a tile job's, or
// VERBOSITY) as it is parsed. Values that a single option can check are checked here (CLI11
// reports them as usage errors); rules between options are tiles::check_options()'s.
void define_options(CLI::App& app, pipeline::BuildOptions& options, tiles::TileOptions& tiling,
                    Verbosity& verbosity);

// Appends the LAS classification codes of TEXT ("2,8") to CLASSES, for the build's and the tile
// commands' class filters; returns the first item that is not a code (0-255), if any.
std::optional<std::string> append_class_codes(const std::string& text,
                                              std::vector<std::uint8_t>& classes);

}  // namespace tincdt::cli
