#include "io/raster/png_writer.hpp"

#include <gdal_priv.h>

#include <string>

#include "core/error.hpp"
#include "io/gdal_support.hpp"

namespace tincdt::io {

void write_png(OutputFile& out, std::uint32_t width, std::uint32_t height,
               std::span<const std::uint8_t> rgba, const ProgressFn* progress) {
  const std::string& path = out.path();
  if (width == 0 || height == 0 || rgba.size() != std::size_t{4} * width * height)
    throw OutputError(path, "", "no pixels to write");
  const detail::GdalQuiet quiet;
  detail::register_gdal_drivers();
  const auto fail = [&path](const char* what) {
    throw OutputError(path, "",
                      std::string(what) + ": " + detail::last_gdal_message("GDAL gave no reason"));
  };
  GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
  GDALDriver* png = GetGDALDriverManager()->GetDriverByName("PNG");
  if (mem == nullptr || png == nullptr)
    throw OutputError(path, "", "GDAL has no MEM or PNG driver");
  detail::GdalDataset image(
      mem->Create("", static_cast<int>(width), static_cast<int>(height), 4, GDT_Byte, nullptr));
  if (!image) fail("cannot set up the picture");
  // Pixel-interleaved RGBA in, one band per channel.
  int bands[] = {1, 2, 3, 4};
  if (image->RasterIO(GF_Write, 0, 0, static_cast<int>(width), static_cast<int>(height),
                      const_cast<std::uint8_t*>(rgba.data()), static_cast<int>(width),
                      static_cast<int>(height), GDT_Byte, 4, bands, 4, 4 * GSpacing{width}, 1,
                      nullptr) != CE_None)
    fail("cannot set up the picture");
  image->GetRasterBand(4)->SetColorInterpretation(GCI_AlphaBand);
  detail::GdalProgress bridge(progress, "write preview");
  detail::GdalDataset written(png->CreateCopy(out.take_path().c_str(), image.get(), FALSE, nullptr,
                                              bridge.function(), bridge.data()));
  if (bridge.cancelled()) throw Cancelled();
  if (!written) fail("cannot write the PNG");
  CPLErrorReset();
  written.reset();
  if (CPLGetLastErrorType() == CE_Failure || CPLGetLastErrorType() == CE_Fatal)
    fail("cannot complete the PNG");
  out.close();
}

}  // namespace tincdt::io
