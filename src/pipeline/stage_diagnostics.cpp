// diagnostics: --diagnostics, what the job did to the input as GeoPackage layers: merged
// duplicates, crossings, skipped segments and dropped features.
#include "io/reports/diagnostics_writer.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

// A diagnostics crossing record for crossing x (its vertex as it is in the TIN now).
io::Diagnostics::Crossing crossing_record(const mesh::Triangulation& tin,
                                          const constraints::Crossing& x,
                                          const detail::SourceTable& sources) {
  const Point2 p = tin.point(x.vertex);
  const auto file = [&](std::uint32_t s) { return sources.known(s) ? sources.file(s) : ""; };
  const auto fid = [&](std::uint32_t s) { return sources.known(s) ? sources.fid(s) : -1; };
  return {{p.x, p.y, tin.z(x.vertex)},
          file(x.source_a),
          fid(x.source_a),
          file(x.source_b),
          fid(x.source_b),
          x.z_a,
          x.z_b};
}

bool wanted(const BuildOptions& o) {
  return !o.diagnostics.empty();
}

void run(Job& job) {
  const mesh::Triangulation& tin = job.tin();
  io::Diagnostics d;
  for (std::size_t i = 0; i < job.mesh.duplicates.size(); ++i) {
    const delaunay::DelaunayResult::Duplicate& dup = job.mesh.duplicates[i];
    // After simplify the vertex may be gone: where it was is kept in duplicate_at.
    const Point3 at =
        i < job.duplicate_at.size()
            ? job.duplicate_at[i]
            : Point3{tin.point(dup.vertex).x, tin.point(dup.vertex).y, tin.z(dup.vertex)};
    d.duplicates.push_back({at, dup.points, dup.z_min, dup.z_max});
  }
  d.crossings.reserve(job.crossings.size());
  for (const constraints::Crossing& x : job.crossings)
    d.crossings.push_back(crossing_record(tin, x, job.sources));
  io::add_line_diagnostics(job.lines, d);
  for (const detail::SurfaceInput* input : {&job.soft, &job.clip, &job.erase, &job.replace}) {
    io::LineData records;
    records.files = input->data.files;
    records.skipped = input->data.skipped;
    records.dropped = input->data.dropped;
    io::add_line_diagnostics(records, d);
  }
  job.write_output(job.options.diagnostics, "diagnostics",
                   [&](io::OutputFile& out) { io::write_diagnostics(out, d, job.crs_wkt); });
}

void plan(const BuildOptions& o, FilePlan& files) {
  files.outputs.push_back({o.diagnostics, "the diagnostics (--diagnostics)"});
}

constexpr OptionSpec kOptions[] = {text_option(
    "--diagnostics", "FILE.gpkg", option_groups::output, set_text<&BuildOptions::diagnostics>,
    "Write crossings, skipped segments and dropped features as\n"
    "GeoPackage layers with the input feature ids")};

}  // namespace

constexpr StageProgress kDiagnosticsProgress{"writing diagnostics"};
extern const Stage diagnostics_stage{"diagnostics", "write", wanted,   run,
                                     plan,          "",      kOptions, kDiagnosticsProgress};

}  // namespace tincdt::pipeline
