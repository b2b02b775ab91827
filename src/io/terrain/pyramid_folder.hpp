// The folder a quantized-mesh pyramid is written into, as it is before and after the run: before,
// it may hold only an earlier pyramid (so that replacing it loses nothing of the user's); after,
// the earlier pyramid's tiles that the new one did not write go, so that the folder is the
// pyramid its layer.json describes.
//
// A pyramid's entries: DIR/layer.json, level folders DIR/{z}, column folders DIR/{z}/{x} and tiles
// DIR/{z}/{x}/{y}.terrain, each of {z}, {x}, {y} a decimal number as the writer spells it (no
// sign, no leading zero). Anything else, a symbolic link among them too, is a stranger.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "io/terrain/geographic_tiling.hpp"

namespace tincdt::io::terrain {

// Refuses DIR, when it is a folder that is not empty, with an OutputError: naming the first
// entry (in name order) that is not part of a pyramid; without OVERWRITE, naming the first file
// of a pyramid it holds (layer.json first), which the run would replace. A missing DIR, or one
// that is not a folder, is left to the checks of an output file.
void check_pyramid_folder(const std::string& dir, bool overwrite);

struct TileRemoval {
  std::uint64_t removed = 0;  // tiles removed
  std::uint64_t failed = 0;   // tiles or folders that could not be read or removed
  std::string first_failure;  // "PATH: reason" of the first of them
};

// Removes the tiles under DIR that KEEP refuses, then the column and level folders they leave
// empty; never any other entry. Failures are counted, not thrown.
TileRemoval remove_tiles(const std::string& dir, const std::function<bool(const TileKey&)>& keep);

}  // namespace tincdt::io::terrain
