// The whole job as one library call: read -> merge -> triangulate -> constrain -> drape and
// insert the surface features -> fix flats -> replace -> trim -> clip -> erase -> write, as the
// stages of stages.cpp. apps/tincdt only turns command-line options into BuildOptions and
// reports the result.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>

#include "core/progress.hpp"
#include "io/mesh/tin_writer.hpp"
#include "pipeline/options.hpp"
#include "pipeline/report.hpp"

namespace tincdt::pipeline {

// Runs the job: check_options(), the checks on every planned output (writable, not an input),
// then every wanted stage of stages(), then moves all outputs into place together. Throws
// tincdt::Error: UsageError (options), InputError, OutputError, GeometryError, InternalError
// (a bug), Cancelled (the progress callback said stop). On any of them no existing file has
// changed and no temporary is left. Progress is reported under the running stage's name, and
// under "commit" just before the outputs move. Log lines go through `log` (may be empty) so the
// library stays free of spdlog.
enum LogLevel : int { log_debug = 0, log_info = 1, log_warn = 2 };
using LogFn = std::function<void(int level /*0 debug,1 info,2 warn*/, const std::string&)>;
BuildReport build(const BuildOptions& options, const ProgressFn* progress = nullptr,
                  const LogFn& log = {});

// For a signal handler that ends the process at once (a second Ctrl-C): removes the temporary
// files of the outputs under way; async-signal-safe. Returns false, removing nothing, while the
// outputs are being moved into place (then let the few renames finish).
bool remove_temporaries_for_exit() noexcept;

// Peak resident set size of this process (VmHWM), 0 if unknown.
std::uint64_t peak_rss_bytes();

// The project version, "X.Y.Z" (from the CMake project).
std::string_view version();

}  // namespace tincdt::pipeline
