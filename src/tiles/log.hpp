// The tiled commands log as pipeline::build() does: one function, a level and a line.
#pragma once

#include "pipeline/build.hpp"

namespace tincdt::tiles {

using pipeline::log_debug;
using pipeline::log_info;
using pipeline::log_warn;
using pipeline::LogFn;

}  // namespace tincdt::tiles
