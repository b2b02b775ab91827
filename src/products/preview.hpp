// A picture to look a TIN over, as blast2dem's PNG is for LAStools users: a hillshade of the
// surface with the constrained edges and the outline of the kept triangles drawn over it, and
// transparent where there is no surface (outside the hull, clipped, erased, trimmed).
//
// The shading is gdaldem's multidirectional hillshade with -compute_edges, grey for grey: Horn's
// slope and aspect on the TIN rasterized at the cell centres, lit from 225, 270, 315 and 360
// degrees at 45 degrees altitude, each light weighted as gdaldem weights it (cos^2 of the angle
// between it and the aspect: the light along the slope counts most), greys 1 (unlit) to 255.
// At the picture's sides a missing row or column of heights is extrapolated linearly, and a
// neighbour without a height takes the cell's own, as gdaldem does.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "core/progress.hpp"
#include "mesh/triangulation.hpp"
#include "products/grid.hpp"

namespace tincdt::products {

struct PreviewOptions {
  std::uint32_t size = 1024;  // pixels on the longer side of the kept triangles' extent (>= 2)
  // Vertical units per horizontal unit: 1 when both are metres (or both feet); about 1/111120
  // for heights in metres on longitude/latitude, as gdaldem's -s 111120.
  double z_factor = 1;
  unsigned threads = 0;  // 0 = every hardware thread (the rasterization)
  // Reports under "dem" (the rasterization, products::rasterize's name), then "preview" (the
  // shading and the edges); a request to stop throws Cancelled.
  const ProgressFn* progress = nullptr;
  // The picture's extent, drawn as a rectangle over it (a tile job's tile); unset: the kept
  // triangles' extent.
  std::optional<BBox> frame = std::nullopt;
};

using Rgba = std::array<std::uint8_t, 4>;
inline constexpr Rgba kConstraintColour = {0, 92, 230, 255};  // contours, hard and soft lines
inline constexpr Rgba kOutlineColour = {230, 40, 20, 255};    // hull, clip, erase, trim edges
inline constexpr Rgba kFrameColour = {255, 200, 0, 255};      // PreviewOptions::frame

struct PreviewImage {
  Grid grid;                       // the pixels' footprint in the TIN's coordinates
  std::vector<std::uint8_t> rgba;  // grid.cells() pixels, 4 bytes each, row-major from the top
};

// Throws Error when the TIN has no kept triangle (and no frame is given), or SIZE is below 2;
// Cancelled when the progress callback asks to stop.
PreviewImage render_preview(const mesh::Triangulation& tin, const PreviewOptions& options = {});

}  // namespace tincdt::products
