// The summary a successful run logs: what was read, what the TIN holds, times, files written.
#pragma once

#include "pipeline/build.hpp"

namespace tincdt::cli {

void log_summary(const pipeline::BuildOptions& options, const pipeline::BuildReport& report);

}  // namespace tincdt::cli
