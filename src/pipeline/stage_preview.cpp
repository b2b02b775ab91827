// preview: --preview, a PNG to look the final TIN over (products::render_preview): a hillshade
// with the constrained edges and the outline drawn, transparent where there is no surface.
#include <string>
#include <string_view>

#include "core/number_text.hpp"
#include "io/crs.hpp"
#include "io/raster/png_writer.hpp"
#include "pipeline/stage.hpp"
#include "products/preview.hpp"

namespace tincdt::pipeline {
namespace {

// Metres on the ground per degree of latitude, as gdaldem's -s 111120.
constexpr double kMetresPerDegree = 111120;
constexpr std::uint32_t kLargestPreview = 16384;

bool wanted(const BuildOptions& o) {
  return !o.preview.path.empty();
}

void run(Job& job) {
  const BuildOptions::Preview& o = job.options.preview;
  products::PreviewOptions p;
  p.size = o.size_or_default();
  p.threads = job.options.threads;
  p.frame = job.preview_frame;
  p.progress = job.stage_progress();
  // Heights in metres over longitude and latitude: shade as gdaldem -s 111120 does.
  if (io::is_geographic(job.crs_wkt)) p.z_factor = 1 / kMetresPerDegree;
  products::PreviewImage image;
  // The job's extra triangles (final ones of its neighbours, set by a caller) are drawn inside
  // the frame too, as the DEM fills cells from them: adjacent pictures then join without gaps.
  job.with_extra_triangles([&] {
    try {
      image = products::render_preview(job.tin(), p);
    } catch (const Cancelled&) {
      throw;  // a request to stop, not a fault of the picture
    } catch (const Error& e) {
      throw OutputError(o.path, "", e.detail());
    }
  });
  io::OutputFile& out = job.add_output(o.path, "preview");
  io::write_png(out, image.grid.width, image.grid.height, image.rgba, job.stage_progress());
  job.finish_output(out);
  job.info("preview: " + count_text(image.grid.width) + " x " + count_text(image.grid.height) +
           " pixels");
}

void plan(const BuildOptions& o, FilePlan& files) {
  files.outputs.push_back({o.preview.path, "the preview (--preview)"});
}

std::string check_size(std::string_view text) {
  const auto n = parse_count(text);
  return n && *n >= 2 && *n <= kLargestPreview
             ? std::string()
             : in_quotes(text) + " is not a size in pixels (2-" + count_text(kLargestPreview) + ")";
}

void set_size(BuildOptions& o, std::string_view text) {
  o.preview.size = static_cast<std::uint32_t>(*parse_count(text));
}

using Preview = BuildOptions::Preview;

constexpr OptionSpec kOptions[] = {
    text_option("--preview", "FILE.png", option_groups::products,
                set_text<&BuildOptions::preview, &Preview::path>,
                "Draw the TIN as a PNG: a hillshade with the constrained edges (blue)\n"
                "and the outline (red), transparent where there is no surface"),
    with_default(checked_option("--preview-size", "PX", option_groups::products, check_size,
                                set_size, "The preview's size in pixels on its longer side"),
                 "1024",
                 [](const BuildOptions& o) { return std::to_string(o.preview.size_or_default()); }),
};

}  // namespace

// The library calls that report progress under this stage, in order.
constexpr std::string_view kProgressPhases[] = {"dem", "preview", "write preview"};

constexpr StageProgress kPreviewProgress{"drawing the preview", "", nullptr, kProgressPhases};
extern const Stage preview_stage{"preview", "preview", wanted,   run,
                                 plan,      "",        kOptions, kPreviewProgress};

}  // namespace tincdt::pipeline
