// A job: the state the stages (stages.cpp) share, in the order they fill it. Each stage reads
// what the stages before it left here and leaves its own result here; nothing else carries
// data from one stage to the next.
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/parallel.hpp"
#include "core/progress.hpp"
#include "core/types.hpp"
#include "delaunay/delaunay.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/output_set.hpp"
#include "io/vector/line_reader.hpp"
#include "pipeline/build.hpp"
#include "pipeline/surface.hpp"
#include "products/grid.hpp"
#include "terrain/quality.hpp"

namespace tincdt::pipeline {

// CRS labels for messages, each distinct WKT identified once (identification can search the
// whole EPSG database, a noticeable fraction of a second).
class CrsNames {
 public:
  const std::string& label(const std::string& wkt);
  // The label, or "no CRS" / "an unnamed CRS".
  std::string name(const std::string& wkt);

 private:
  std::map<std::string, std::string> labels_;
};

struct Job {
  // CHECKED: check_options(job_options).
  Job(const BuildOptions& job_options, const CheckedOptions& checked, const ProgressFn* progress,
      LogFn log);
  Job(const Job&) = delete;
  Job& operator=(const Job&) = delete;

  const BuildOptions& options;
  BuildReport report;

  // ---- inputs (read) --------------------------------------------------------------------------
  const std::string assign_crs_wkt;    // --a-srs as WKT, "" when not given
  const std::string override_crs_wkt;  // --override-srs as WKT, "" when not given
  const std::string target_crs_wkt;    // --t-srs as WKT, "" when not given
  // The CRS of the TIN and every output, every input transformed into it: the target CRS, else
  // the first input's; "" when none is known.
  std::string crs_wkt;
  CrsNames crs_names;
  // The points of every point file in order, then the contour and hard-line vertices
  // (lines.vertices moved here). Consumed by delaunay, which keeps what the later stages need:
  // the mesh's vertices are these points with equal x, y merged (mesh.vertex_of_point maps
  // them when lines exist).
  std::vector<Point3> points;
  std::size_t point_count = 0;  // how many of `points` came from point files
  io::LineData lines;           // contours and hard lines; segment ends index `points` from
                                // point_count on
  detail::SourceTable sources;  // constraint source id -> input feature (lines, then surface)
  detail::SurfaceInput soft{detail::SourceKind::soft_line, {}, 0};
  detail::SurfaceInput clip{detail::SourceKind::clip, {}, 0};
  detail::SurfaceInput erase{detail::SourceKind::erase, {}, 0};
  detail::SurfaceInput replace{detail::SourceKind::replace, {}, 0};

  // ---- the mesh -------------------------------------------------------------------------------
  // delaunay: the TIN and its duplicate records; every later stage edits mesh.tin in place (a
  // stage that makes a new TIN, such as simplification, replaces it).
  delaunay::DelaunayResult mesh;
  mesh::Triangulation& tin() { return mesh.tin; }
  // simplify: where mesh.duplicates[i] was merged (its vertex may have been dropped since).
  std::vector<Point3> duplicate_at;
  // constraints, surface: every constrained piece with its source, every crossing joined, and
  // (for validate) every segment given.
  std::vector<constraints::Piece> pieces;
  std::vector<constraints::Crossing> crossings;
  std::vector<constraints::Segment> given_segments;
  // simplify, with --max-edge: 1 per triangle slot of the simplified TIN in an area the full
  // TIN's trimming removed, for the trim stage.
  std::vector<std::uint8_t> trimmed_areas;
  // flats: 1 per vertex on a contour (also for the quality stage's flat count).
  std::vector<std::uint8_t> on_contour;
  // quality: the --stats measurement of the final TIN, running beside the output stages, which
  // only read the TIN (a DEM that puts dem_extra_triangles back for a while waits first).
  // Declared after the mesh, so that a failed job waits for it before the mesh goes.
  struct MeasuredQuality {
    terrain::QualityReport quality;
    double seconds = 0;
  };
  MeasuredQuality quality_measured;
  std::unique_ptr<BackgroundJob> quality_pass;  // fills quality_measured
  // Joins quality_pass, if running, and files its result in the report.
  void wait_for_quality();
  // Runs DRAW with dem_extra_triangles back in the TIN, then removes them again (also when DRAW
  // throws). The quality pass, which reads the removed flags, is joined first.
  template <class F>
  void with_extra_triangles(F&& draw);

  // ---- set by the caller of a job over part of its data (empty: none) ------------------------
  // read: called after point file INPUT is read (EXTENT: its points'), after every point file
  // (may append points), and after every contour and hard-line source, before their vertices
  // join `points` (may drop segments and vertices of `lines`). Each may throw InputError.
  // keep_surface_feature: whether to keep a soft line, clip, erase or replace polygon (in the
  // job's CRS) read from a source; unset keeps all.
  struct ReadHooks {
    std::function<void(const Job& job, std::size_t input, const BBox& extent)> point_file_read;
    std::function<void(Job& job)> point_files_read;
    std::function<void(Job& job)> line_sources_read;
    std::function<bool(detail::SourceKind kind, const io::ShapeFeature& feature)>
        keep_surface_feature;
  } read_hooks;
  // surface: the whole data's hull and which draped heights are settled, for a job over part
  // of the data.
  detail::SurfaceScope surface_scope;
  // replace, clip, erase: the triangles (1 per slot) whose classification counts, each region of
  // triangles classified by a point of its own (empty: every triangle); a stage before them
  // sets them. A job over part of the data may then keep no triangle.
  std::vector<std::uint8_t> proven_triangles;
  // replace: the polygon of each vertex known from beyond the TIN (kNoId: none; empty: none
  // known), PolygonOptions::vertex_polygons; a stage before it sets them.
  std::vector<std::uint32_t> known_replace_polygons;
  bool may_keep_none = false;
  // dem: the grid of the DEM, instead of one over the kept triangles and the DEM options.
  std::optional<products::Grid> dem_grid;
  // dem, preview: removed triangles the rasters fill cells from all the same (removed for the
  // mesh outputs only); a stage after the polygon stages sets them. with_extra_triangles().
  std::vector<TriangleId> dem_extra_triangles;
  // preview: the picture's extent, drawn as a frame over it, instead of the kept triangles'.
  std::optional<BBox> preview_frame;

  // ---- outputs --------------------------------------------------------------------------------
  // The TIN's write options: from the options, crs_wkt (read), the automatic offset (write);
  // every output that holds coordinates uses them.
  io::TinWriteOptions write;
  // read: whether the TIN gets a .prj (a CRS, OBJ or PLY, and no .prj with that CRS there yet).
  bool write_prj = false;
  // Every file of the run. A stage adds its outputs here and writes them to their temporaries;
  // build() moves all of them into place after the last stage, or none.
  io::OutputSet outputs;
  // A new output of the set; throws OutputError as OutputSet::add().
  io::OutputFile& add_output(const std::string& path, std::string kind) {
    return outputs.add(path, std::move(kind));
  }
  // Closes OUT (complete on disk) and lists it in report.outputs, with its CRS.
  void finish_output(io::OutputFile& out);
  const std::string& crs_of_output(const std::string& kind) const;
  // The two around WRITER(io::OutputFile&), which writes the file; returns it, for its size.
  template <class Writer>
  const io::OutputFile& write_output(const std::string& path, std::string kind, Writer&& writer) {
    io::OutputFile& out = add_output(path, std::move(kind));
    writer(out);
    finish_output(out);
    return out;
  }

  // ---- messages and progress ------------------------------------------------------------------
  void debug(const std::string& message) const { emit(log_debug, message); }
  void info(const std::string& message) const { emit(log_info, message); }
  void warn(const std::string& message) const { emit(log_warn, message); }
  // Reports FRACTION of the running stage; throws Cancelled when the callback says stop.
  void progress(double fraction) const;
  // For library calls: a callback that reports under the running stage's name whatever name
  // the library uses; null when the caller gave none.
  const ProgressFn* stage_progress() const { return user_progress_ ? &stage_progress_ : nullptr; }
  std::string_view stage() const { return stage_; }
  void enter_stage(std::string_view name) { stage_ = name; }
  // Enters STAGE and tells a StageWatcher among the callbacks of it. PHASES: the names the
  // library calls of the stage report under, in the order they run, each taking an equal share
  // of the stage's fraction (so that it never goes back); empty: one call, or any.
  void start_stage(const StageStart& stage, std::span<const std::string_view> phases);
  // The inputs for messages: "a.las", "a.las, b.las and 3 more".
  std::string describe_inputs() const;

  const std::chrono::steady_clock::time_point started;

 private:
  void emit(int level, const std::string& message) const {
    if (log_) log_(level, message);
  }

  const ProgressFn* user_progress_;
  ProgressFn stage_progress_;
  LogFn log_;
  std::string_view stage_;
  std::span<const std::string_view> phases_;
};

// For the stages that remove triangles: a GeometryError when none is left.
void check_triangles_left(Job& job);

// Seconds since T0.
double seconds_since(std::chrono::steady_clock::time_point t0);

template <class F>
void Job::with_extra_triangles(F&& draw) {
  if (dem_extra_triangles.empty()) {
    draw();
    return;
  }
  wait_for_quality();
  struct PutBack {
    mesh::Triangulation& tin;
    const std::vector<TriangleId>& triangles;
    PutBack(mesh::Triangulation& m, const std::vector<TriangleId>& t) : tin(m), triangles(t) {
      for (const TriangleId id : triangles) tin.set_removed(id, false);
    }
    ~PutBack() {
      for (const TriangleId id : triangles) tin.set_removed(id, true);
    }
    PutBack(const PutBack&) = delete;
    PutBack& operator=(const PutBack&) = delete;
  } put_back(tin(), dem_extra_triangles);
  draw();
}

}  // namespace tincdt::pipeline
