// constraint_lines: --constraints-out, every constrained edge of the written TIN as a GeoJSON
// line with its source feature, in the TIN's coordinates (offset, target CRS).
#include <vector>

#include "io/mesh/constraint_writer.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

bool wanted(const BuildOptions& o) {
  return !o.constraints_out.empty();
}

void run(Job& job) {
  const mesh::Triangulation& tin = job.tin();
  // One feature per piece (an edge with two sources, where lines overlap, gives two), for the
  // edges of the written TIN: with a kept triangle on a side.
  const BuildReport& r = job.report;
  const bool removed = r.trimmed_triangles + r.clipped_triangles + r.erased_triangles > 0;
  std::vector<io::ConstraintEdge> edges;
  edges.reserve(job.pieces.size());
  for (const constraints::Piece& p : job.pieces) {
    if (removed) {
      const EdgeId e = tin.find_edge(p.a, p.b);
      if (e == kNoId ||
          (!tin.is_kept(mesh::triangle_of(e)) && !tin.is_kept(mesh::triangle_of(tin.twin(e)))))
        continue;
    }
    edges.push_back({p.a, p.b, p.source});
  }
  std::vector<io::ConstraintFeatureInfo> features;
  features.reserve(job.sources.size());
  for (std::uint32_t i = 0; i < job.sources.size(); ++i)
    features.push_back({job.sources.file(i), job.sources.fid(i)});
  io::TinWriteOptions write = job.write;
  write.format = io::TinFormat::geojson;
  job.write_output(job.options.constraints_out, "constraint_lines", [&](io::OutputFile& out) {
    io::write_constraint_lines(out, tin, edges, features, write);
  });
}

void plan(const BuildOptions& o, FilePlan& files) {
  files.outputs.push_back({o.constraints_out, "the constraint lines (--constraints-out)"});
}

constexpr OptionSpec kOptions[] = {
    text_option("--constraints-out", "FILE.geojson", option_groups::output,
                set_text<&BuildOptions::constraints_out>,
                "Write the TIN's constrained edges as GeoJSON lines with their\n"
                "source file and feature id")};

}  // namespace

constexpr StageProgress kConstraintLinesProgress{"writing constraint lines"};
extern const Stage constraint_lines_stage{
    "constraint_lines", "write", wanted, run, plan, "", kOptions, kConstraintLinesProgress};

}  // namespace tincdt::pipeline
