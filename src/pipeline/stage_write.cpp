// write: the TIN (-o) and, for OBJ and PLY with a CRS, its .prj, into the job's outputs. They
// move into place with every other output at the end of the job (build()).
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <string_view>

#include "core/coordinates.hpp"
#include "core/number_text.hpp"
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

// Vertices of the kept triangles: what a writer would have written.
std::uint64_t kept_vertices(const mesh::Triangulation& tin) {
  std::vector<bool> used(tin.vertex_count(), false);
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    for (const VertexId v : c) used[v] = true;
  });
  return static_cast<std::uint64_t>(std::count(used.begin(), used.end(), true));
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
  if (job.options.output.empty()) {  // no -o: only the products
    report.vertices = kept_vertices(tin);
    return;
  }
  io::TinWriteOptions options = job.write;
  options.progress = job.stage_progress();
  options.threads = job.options.threads;
  io::TinWriteStats ws;
  const io::OutputFile& out = job.write_output(
      job.options.output, "tin", [&](io::OutputFile& f) { ws = io::write_tin(f, tin, options); });
  if (job.write_prj)
    job.write_output(io::prj_path(job.options.output), "prj",
                     [&](io::OutputFile& f) { io::write_prj(f, job.crs_wkt); });
  report.output_bytes = out.bytes_written();
  report.vertices = ws.vertices;
  if (ws.triangles != report.triangles)
    job.debug("writer reports " + count_text(ws.triangles, "triangle") + ", the TIN " +
              count_text(report.triangles));
}

void plan(const BuildOptions& o, FilePlan& files) {
  if (!o.output.empty()) files.outputs.push_back({o.output, "the TIN (-o)"});
}

// ---- options: the TIN's, and --overwrite for every output -------------------------------------

// "auto", or three numbers X,Y,Z.
std::optional<Point3> parse_offset(std::string_view text) {
  double v[3];
  for (int i = 0; i < 3; ++i) {
    const std::size_t comma = text.find(',');
    if ((i < 2) == (comma == std::string_view::npos)) return std::nullopt;
    const auto d = parse_number(text.substr(0, comma));
    if (!d) return std::nullopt;
    v[i] = *d;
    text.remove_prefix(i < 2 ? comma + 1 : text.size());
  }
  return Point3{v[0], v[1], v[2]};
}

const std::string kOutputHelp = "The TIN file: " + io::format_extensions_text();

using Write = BuildOptions::Write;

const OptionSpec kOptions[] = {
    {.flags = "-o,--output",
     .value_name = "FILE",
     .help = kOutputHelp,
     .group = option_groups::output,
     .set = set_text<&BuildOptions::output>},
    {.flags = "-f,--format",
     .help = "Output format, overriding the extension",
     .group = option_groups::output,
     .kind = OptionKind::choice,
     .words = io::tin_format_names(),
     .set = [](BuildOptions& o, std::string_view v) { o.write.format = io::format_from_name(v); }},
    flag_option("--overwrite", option_groups::output,
                set_true<&BuildOptions::write, &Write::overwrite>,
                "Replace existing outputs (TIN, stats, lines, diagnostics);\n"
                "never an input, nor a file that belongs to one"),
    flag_option("--ply-ascii", option_groups::output,
                set_true<&BuildOptions::write, &Write::ply_ascii>,
                "Write PLY as text instead of binary"),
    flag_option("--gpkg-tin", option_groups::output,
                set_true<&BuildOptions::write, &Write::gpkg_tin>,
                "GeoPackage: TIN Z features instead of POLYGON Z (not every GIS reads them)"),
    {.flags = "--offset",
     .value_name = "auto|X,Y,Z",
     .help = "Subtract X,Y,Z from written coordinates (recorded in the file);\n"
             "auto = the data's min corner, rounded down to 1000",
     .group = option_groups::output,
     .check =
         [](std::string_view v) {
           if (lower(v) == "auto") return std::string();
           const std::optional<Point3> d = parse_offset(v);
           if (!d) return in_quotes(v) + " is neither 'auto' nor three numbers X,Y,Z";
           // An offset beyond the coordinates' range would replace them, not shift them.
           for (const double c : {d->x, d->y, d->z}) {
             if (!(std::abs(c) <= kMaxCoordinate))
               return in_quotes(v) + ": each of X,Y,Z must lie within +-" +
                      std::string(kMaxCoordinateText) + ", the range of coordinates";
           }
           return std::string();
         },
     .set =
         [](BuildOptions& o, std::string_view v) {
           o.write.offset_auto = lower(v) == "auto";
           if (!o.write.offset_auto) o.write.offset = *parse_offset(v);
         }},
};

}  // namespace

constexpr StageProgress kWriteProgress{"writing the TIN", "triangles", stage_items::triangles};
extern const Stage write_stage{"write",
                               "write",
                               wanted,
                               run,
                               plan,
                               "the outputs (the TIN, then --dem and --contour-lines from it):\n"
                               "all of them are written, or none",
                               kOptions,
                               kWriteProgress};

}  // namespace tincdt::pipeline
