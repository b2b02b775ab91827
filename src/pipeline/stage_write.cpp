// write: the TIN (-o) and, for OBJ and PLY with a CRS, its .prj, into the job's outputs. They
// move into place with every other output at the end of the job (build()).
#include <algorithm>
#include <cmath>
#include <string>

#include "io/mesh/tin_writer.hpp"
#include "pipeline/stage.hpp"

namespace tincdt::pipeline {
namespace {

double round_down(double v, double step) {
  return std::floor(v / step) * step;
}

// --offset auto: the vertices' minimum corner rounded down to 1000.
Point3 automatic_offset(const mesh::Triangulation& tin) {
  const std::vector<Point2>& xy = tin.points();
  if (xy.empty()) return {0, 0, 0};
  double min_x = xy.front().x, min_y = xy.front().y;
  for (const Point2& p : xy) {
    min_x = std::min(min_x, p.x);
    min_y = std::min(min_y, p.y);
  }
  if (!std::isfinite(min_x) || !std::isfinite(min_y)) return {0, 0, 0};
  return {round_down(min_x, 1000.0), round_down(min_y, 1000.0), 0.0};
}

// Constrained edges of the written TIN: those with a kept triangle on a side.
std::uint64_t kept_constraints(const mesh::Triangulation& tin) {
  std::uint64_t n = 0;
  tin.for_each_constrained_edge([&](EdgeId e) {
    if (tin.is_kept(mesh::triangle_of(e)) || tin.is_kept(mesh::triangle_of(tin.twin(e)))) ++n;
  });
  return n;
}

bool wanted(const BuildOptions&) {
  return true;
}

void run(Job& job) {
  const mesh::Triangulation& tin = job.tin();
  if (job.options.write.offset_auto) job.write.offset = automatic_offset(tin);
  BuildReport& report = job.report;
  report.offset = job.write.offset;
  report.triangles = tin.triangle_count();
  report.constraints = kept_constraints(tin);

  if (job.write.format == io::TinFormat::stl) {
    const std::string warning = io::stl_precision_warning(tin, job.write.offset);
    if (!warning.empty()) job.warn(warning + "; shift them with --offset (e.g. --offset auto)");
  }
  io::TinWriteOptions options = job.write;
  options.progress = job.stage_progress();
  io::TinWriteStats ws;
  const io::OutputFile& out = job.write_output(
      job.options.output, "tin", [&](io::OutputFile& f) { ws = io::write_tin(f, tin, options); });
  if (job.write_prj)
    job.write_output(io::prj_path(job.options.output), "prj",
                     [&](io::OutputFile& f) { io::write_prj(f, job.crs_wkt); });
  report.output_bytes = out.bytes_written();
  report.vertices = ws.vertices;
  if (ws.triangles != report.triangles)
    job.debug("writer reports " + std::to_string(ws.triangles) + " triangles, the TIN " +
              std::to_string(report.triangles));
}

void plan(const BuildOptions& o, FilePlan& files) {
  files.outputs.push_back({o.output, "the TIN (-o)"});
}

}  // namespace

extern const Stage write_stage{"write", "write", wanted, run, plan};

}  // namespace tincdt::pipeline
