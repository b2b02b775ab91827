// An RGBA picture (products::render_preview) as a PNG, through GDAL's PNG driver: 4 bands of
// bytes, alpha 0 where there is no surface. GDAL builds the file at the OutputFile's take_path().
#pragma once

#include <cstdint>
#include <span>

#include "core/progress.hpp"
#include "io/output_file.hpp"

namespace tincdt::io {

// RGBA: WIDTH x HEIGHT pixels, 4 bytes each, row-major from the top. Throws OutputError naming
// OUT's path; Cancelled when PROGRESS (reported under "write preview") asks to stop.
void write_png(OutputFile& out, std::uint32_t width, std::uint32_t height,
               std::span<const std::uint8_t> rgba, const ProgressFn* progress = nullptr);

}  // namespace tincdt::io
