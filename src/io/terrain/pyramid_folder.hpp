// The folder a quantized-mesh pyramid is written into, as it is before the run: it may hold only
// an earlier pyramid, so that replacing it loses nothing of the user's.
//
// A pyramid's entries: DIR/layer.json, level folders DIR/{z}, column folders DIR/{z}/{x} and tiles
// DIR/{z}/{x}/{y}.terrain, each of {z}, {x}, {y} a decimal number as the writer spells it (no
// sign, no leading zero). Anything else, a symbolic link among them too, is a stranger.
#pragma once

#include <string>

#include "io/terrain/geographic_tiling.hpp"

namespace tincdt::io::terrain {

// Refuses DIR, when it is a folder that is not empty, with an OutputError: naming the first
// entry (in name order) that is not part of a pyramid; without OVERWRITE, naming the first file
// of a pyramid it holds (layer.json first), which the run would replace. A missing DIR, or one
// that is not a folder, is left to the checks of an output file.
void check_pyramid_folder(const std::string& dir, bool overwrite);

}  // namespace tincdt::io::terrain
