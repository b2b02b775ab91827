// trim: --max-edge removes boundary triangles with a longer edge, inward from the convex hull,
// so that a concave outline is not bridged; before clip and erase open new boundaries.
#include <string>

#include "pipeline/stage.hpp"
#include "terrain/trim.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return o.max_edge > 0;
}

void run(Job& job) {
  job.report.trimmed_triangles = terrain::trim_long_edges(job.tin(), job.options.max_edge);
  job.debug("trim: " + std::to_string(job.report.trimmed_triangles) +
            " triangles with an edge longer than --max-edge removed");
  check_triangles_left(job);
}

constexpr OptionSpec kOptions[] = {
    {.flags = "--max-edge",
     .value_name = "LENGTH",
     .help = "Trim boundary triangles with a longer edge, inward from the hull,\n"
             "so concave outlines are not bridged",
     .group = option_groups::boundary,
     .check =
         [](std::string_view v) {
           const auto d = parse_number(v);
           return d && *d > 0 ? std::string() : in_quotes(v) + " is not a length > 0";
         },
     .set = [](BuildOptions& o, std::string_view v) { o.max_edge = *parse_number(v); }},
};

}  // namespace

extern const Stage trim_stage{"trim",  "terrain", wanted,
                              run,     nullptr,   "--max-edge: trims inward from the convex hull",
                              kOptions};

}  // namespace tincdt::pipeline
