// web_terrain: --terrain DIR, the final TIN as a Cesium quantized-mesh-1.0 pyramid: DIR/layer.json
// and DIR/{z}/{x}/{y}.terrain in the geographic TMS tiling (EPSG:4326, two root tiles), each tile
// within its level's geometric error of the full TIN (web_terrain/tile.hpp), neighbours sharing
// their border vertices. Every tile is an output of the job: written to a temporary beside it and
// moved into place with the other outputs, or not at all.
//
// web_terrain_crs runs right after read: a pyramid needs the data's CRS, so none stops the job
// before any work.
#include <algorithm>
#include <atomic>
#include <cassert>
#include <charconv>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <mutex>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/parallel.hpp"
#include "io/terrain/geographic_tiling.hpp"
#include "io/terrain/layer_json.hpp"
#include "io/terrain/lon_lat.hpp"
#include "io/terrain/pyramid_folder.hpp"
#include "io/terrain/quantized_mesh.hpp"
#include "io/terrain/wgs84.hpp"
#include "pipeline/stage.hpp"
#include "products/short_number.hpp"
#include "web_terrain/source.hpp"
#include "web_terrain/tile.hpp"

namespace tincdt::pipeline {
namespace {

namespace qm = io::terrain;
using products::short_number;
using web_terrain::TerrainSource;
using web_terrain::TileError;

// The deepest level a default pyramid goes to.
constexpr int kDeepestDefaultLevel = 24;

bool wanted(const BuildOptions& o) {
  return !o.terrain.path.empty();
}

// The level whose tiles, as 65 x 65 heightmaps (Cesium's model of a level's error), have
// samples no farther apart than SPACING metres.
int level_for_spacing(double spacing) {
  if (!(spacing > 0)) return 0;
  const double equator = 2 * std::numbers::pi * qm::wgs84::kSemiMajorAxis;
  const double level = std::ceil(std::log2(equator / (2 * 64 * spacing)));
  return static_cast<int>(std::clamp(level, 0.0, static_cast<double>(kDeepestDefaultLevel)));
}

std::string tile_path(const std::string& dir, const qm::TileKey& key) {
  return dir + "/" + std::to_string(key.level) + "/" + std::to_string(key.x) + "/" +
         std::to_string(key.y) + ".terrain";
}

// The tiles of LEVEL the pyramid has: those over the data, and at level 0 both roots, which
// Cesium, told by metadataAvailability to learn the tiles from their parents, takes as given.
qm::TileRange level_tiles(const qm::GeoRectangle& bounds, int level) {
  return level == 0 ? qm::TileRange{0, 0, 1, 0} : qm::tiles_covering(bounds, level);
}

// The tiles of the next level below KEY that the pyramid has, for the metadata extension.
std::vector<std::vector<qm::TileRange>> children(const qm::TileKey& key, int max_level,
                                                 const qm::GeoRectangle& bounds) {
  if (key.level >= max_level) return {};
  const qm::TileRange all = qm::tiles_covering(bounds, key.level + 1);
  qm::TileRange r{std::max(all.start_x, 2 * key.x), std::max(all.start_y, 2 * key.y),
                  std::min(all.end_x, 2 * key.x + 1), std::min(all.end_y, 2 * key.y + 1)};
  if (r.start_x > r.end_x || r.start_y > r.end_y) return {{}};
  return {{r}};
}

std::uint64_t tile_count(const qm::TileRange& r) {
  return std::uint64_t{r.end_x - r.start_x + 1} * (r.end_y - r.start_y + 1);
}

// The tiles of the pyramid's levels 0 to MAX_LEVEL over BOUNDS.
std::uint64_t pyramid_tiles(const qm::GeoRectangle& bounds, int max_level) {
  std::uint64_t total = 0;
  for (int level = 0; level <= max_level; ++level) total += tile_count(level_tiles(bounds, level));
  return total;
}

std::string box_text(const qm::GeoRectangle& bounds) {
  return short_number(bounds.east - bounds.west) + " x " +
         short_number(bounds.north - bounds.south) + " degrees";
}

// The tiles of the pyramid's levels 0 to MAX_LEVEL over BOUNDS; a UsageError when they are more
// than LIMIT (they would fill a disk before the job ends), naming the deepest level that keeps
// within it. LEVELS_TEXT says where the levels come from, for the message.
std::uint64_t checked_tile_count(const qm::GeoRectangle& bounds, int max_level, std::uint64_t limit,
                                 const std::string& levels_text) {
  const std::uint64_t total = pyramid_tiles(bounds, max_level);
  if (total <= limit) return total;
  int fits = max_level;
  while (fits > 0 && pyramid_tiles(bounds, fits) > limit) --fits;
  throw UsageError(levels_text + ": the pyramid would have " + count_text(total) +
                   " tiles over the data's " + box_text(bounds) + ", more than the limit of " +
                   count_text(limit) + " (--terrain-max-tiles): give --terrain-levels 0-" +
                   count_text(fits) + " (" + count_text(pyramid_tiles(bounds, fits)) +
                   " tiles), or a higher --terrain-max-tiles");
}

void write_file(Job& job, const std::string& path, const std::string& bytes) {
  job.outputs.make_folders(std::filesystem::path(path).parent_path().string());
  io::OutputFile& out = job.add_output(path, "terrain");
  out.defer_sync();  // thousands of small files: one flush of the file system at commit
  out.write(bytes);
  job.finish_output(out);
}

struct LevelStats {
  std::size_t tiles = 0;
  std::size_t line_segments = 0;
  std::size_t lines_dropped = 0;
  std::size_t outlines_dropped = 0;
  std::size_t chose_from_all = 0;
  std::uint64_t vertices = 0;
  TileError error;
};

// The TIN's vertices that are vertices of one level's tiles, kept while the level above is built
// from them.
class LevelVertices {
 public:
  explicit LevelVertices(const qm::TileRange& range)
      : range_(range), vertices_(static_cast<std::size_t>(tile_count(range))) {}
  void keep(const qm::TileKey& key, std::vector<std::uint32_t> vertices) {
    vertices_[slot(key.x, key.y)] = std::move(vertices);
  }
  // The vertices of the children of PARENT (a tile one level up) that the level has, ascending.
  std::vector<std::uint32_t> children_of(const qm::TileKey& parent) const {
    std::vector<std::uint32_t> out;
    for (std::uint32_t x = 2 * parent.x; x <= 2 * parent.x + 1; ++x)
      for (std::uint32_t y = 2 * parent.y; y <= 2 * parent.y + 1; ++y)
        if (x >= range_.start_x && x <= range_.end_x && y >= range_.start_y && y <= range_.end_y) {
          const std::vector<std::uint32_t>& v = vertices_[slot(x, y)];
          out.insert(out.end(), v.begin(), v.end());
        }
    // A vertex on the side between two children can be a vertex of both.
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
  }

 private:
  std::size_t slot(std::uint32_t x, std::uint32_t y) const {
    return std::size_t{x - range_.start_x} * (range_.end_y - range_.start_y + 1) +
           (y - range_.start_y);
  }
  qm::TileRange range_;
  std::vector<std::vector<std::uint32_t>> vertices_;
};

// Builds the tiles KEYS[i] (of one level) into TILES[i], each within its level's error, from
// the vertices of their children in FINER (null: from the TIN's), on WORKERS threads.
// Worker 0, on the calling thread, reports the stage's fraction AT within its tiles and, once it
// has none left, while the others finish theirs: a request to stop gets through within a tile's
// step. A tile that fails stops the tiles after it, not those before it, so the error rethrown,
// the lowest tile's, is the same on any number of threads; a stop comes after any error.
void build_tiles(Job& job, const TerrainSource& source, std::span<const qm::TileKey> keys,
                 const LevelVertices* finer, std::size_t workers, double at,
                 std::vector<web_terrain::BuiltTile>& tiles) {
  tiles.assign(keys.size(), {});
  std::vector<std::exception_ptr> errors(keys.size());
  std::exception_ptr stop;
  std::atomic<std::size_t> next{0}, finished{0}, first_failed{SIZE_MAX};
  std::atomic<bool> stopped{false};
  const bool report = job.stage_progress() != nullptr;
  const auto ask = [&] {
    try {
      if (report && !stopped) job.progress(at);
    } catch (const Cancelled&) {
      stopped = true;
      throw;
    }
  };
  std::mutex waiting;
  std::condition_variable all_done;
  const auto tile_done = [&] {
    if (++finished < keys.size()) return;
    { const std::lock_guard lock(waiting); }  // worker 0 is waiting, or will see FINISHED
    all_done.notify_all();
  };
  run_workers(std::min(workers, keys.size()), [&](std::size_t worker) {
    std::size_t i = 0;
    const ProgressFn within_tile = [&](std::string_view, double) {
      if (worker == 0) ask();
      return !stopped && i < first_failed;
    };
    for (; (i = next.fetch_add(1)) < keys.size(); tile_done()) {
      try {
        if (stopped || i > first_failed) throw Cancelled();
        const double error = qm::geometric_error_at_level(keys[i].level);
        if (finer) {
          const std::vector<std::uint32_t> children = finer->children_of(keys[i]);
          tiles[i] = web_terrain::build_tile(source, keys[i], error, &within_tile, &children);
        } else {
          tiles[i] = web_terrain::build_tile(source, keys[i], error, &within_tile);
        }
      } catch (const Cancelled&) {
        errors[i] = std::current_exception();
      } catch (...) {
        errors[i] = std::current_exception();
        for (std::size_t seen = first_failed; i < seen;)
          if (first_failed.compare_exchange_weak(seen, i)) break;
      }
    }
    if (worker != 0) return;
    std::unique_lock lock(waiting);
    while (finished < keys.size()) {
      // Woken by the last tile: a batch of small tiles does not wait out the period.
      if (all_done.wait_for(lock, std::chrono::milliseconds(20),
                            [&] { return finished == keys.size(); }))
        break;
      lock.unlock();
      try {
        ask();
      } catch (const Cancelled&) {
        stop = std::current_exception();
      }
      lock.lock();
    }
  });
  for (const std::exception_ptr& e : errors) {
    if (!e) continue;
    try {
      std::rethrow_exception(e);
    } catch (const Cancelled&) {
      if (!stop) stop = e;
    }
  }
  if (stop) std::rethrow_exception(stop);
}

// Each level's share of the stage's progress, in proportion to its work: every tile's fixed
// cost (its sides, its encoding, its file), counted as kTileWork vertices, and the measure of
// every vertex of the TIN against the tile that holds it, once per level.
constexpr double kTileWork = 1000;

std::vector<double> level_shares(const TerrainSource& source,
                                 const std::vector<qm::TileRange>& levels) {
  std::vector<double> shares;
  double total = 0;
  for (const qm::TileRange& range : levels) {
    const double work = kTileWork * static_cast<double>(tile_count(range)) +
                        static_cast<double>(source.vertices().size());
    shares.push_back(work);
    total += work;
  }
  for (double& share : shares) share /= total;
  return shares;
}

void log_level(Job& job, int level, const LevelStats& s) {
  const double rmse =
      s.error.count ? std::sqrt(s.error.sum_squares / static_cast<double>(s.error.count)) : 0;
  job.info("terrain level " + count_text(level) + ": " + count_text(s.tiles, "tile") + ", " +
           count_text(s.vertices, "vertex", "vertices") + ", max error " +
           short_number(s.error.max) + " m (allowed " +
           short_number(qm::geometric_error_at_level(level)) + "), RMSE " + short_number(rmse) +
           " m over " + count_text(s.error.count, "vertex", "vertices") +
           (s.line_segments ? ", " + count_text(s.line_segments, "line piece") + " as edges"
                            : std::string()) +
           (s.error.hidden ? ", " + count_text(s.error.hidden, "vertex", "vertices") +
                                 " under holes (their outline simplified at this level)"
                           : std::string()));
  if (s.lines_dropped)
    job.debug("terrain level " + count_text(level) + ": " + count_text(s.lines_dropped, "tile") +
              " without their lines: simplified onto the tile's grid, they overlap "
              "(coarse tiles over small data)");
  if (s.outlines_dropped)
    job.debug("terrain level " + count_text(level) + ": " + count_text(s.outlines_dropped, "tile") +
              " without their holes' outline: simplified onto the tile's grid, it "
              "overlaps the other lines; their holes follow the triangles' centres");
  if (s.chose_from_all)
    job.debug("terrain level " + count_text(level) + ": " + count_text(s.chose_from_all, "tile") +
              " chose from every vertex under them: their children's and the farthest ones " +
              "missed the level's error");
  if (s.error.max > qm::geometric_error_at_level(level))
    job.warn("terrain level " + count_text(level) + ": vertices up to " +
             short_number(s.error.max) + " m from the TIN, above the level's error: points " +
             "closer than a tile's quantization step (1/32767 of its width) differ more in " +
             "height (walls, trees; ground points alone make a smoother terrain)");
}

struct LevelRun {
  qm::TileRange range;
  std::uint64_t count;  // tiles
  double start, share;  // of the stage's progress
  LevelStats stats;
};

// Writes the tiles of RANGES (from level 0, one range of tiles each), built in batches on every
// thread from the finest level up: a coarser level's tiles choose their vertices from their
// children's (the finest level's from the TIN's), so that a level's work is its tiles', not the
// TIN's. A level is logged once its last tile is written.
void write_levels(Job& job, const TerrainSource& source, const std::vector<qm::TileRange>& ranges) {
  constexpr std::size_t kHeavyAtOnce = 2;
  const int max_level = static_cast<int>(ranges.size()) - 1;
  const std::vector<double> shares = level_shares(source, ranges);
  std::vector<LevelRun> levels(ranges.size());
  double start = 0;
  for (int level = max_level; level >= 0; --level) {
    const auto l = static_cast<std::size_t>(level);
    levels[l] = {ranges[l], tile_count(ranges[l]), start, shares[l], {}};
    start += shares[l];
  }
  const auto fraction = [&levels](const qm::TileKey& key) {
    const LevelRun& l = levels[static_cast<std::size_t>(key.level)];
    // The shares' sum can round above 1, which the stage's end would then go back from.
    return std::min(
        1.0, l.start + l.share * static_cast<double>(l.stats.tiles) / static_cast<double>(l.count));
  };
  const std::size_t workers = thread_count(job.options.threads);
  std::vector<qm::TileKey> batch;
  std::vector<web_terrain::BuiltTile> tiles;
  std::optional<LevelVertices> finer, built;
  const auto flush = [&] {
    build_tiles(job, source, batch, finer ? &*finer : nullptr, workers, fraction(batch.front()),
                tiles);
    for (std::size_t i = 0; i < batch.size(); ++i) {
      const qm::TileKey& key = batch[i];
      web_terrain::BuiltTile& tile = tiles[i];
      qm::QuantizedMeshOptions options;
      options.available = children(key, max_level, source.bounds());
      write_file(job, tile_path(job.options.terrain.path, key),
                 qm::encode_quantized_mesh(tile.mesh, options));
      LevelRun& l = levels[static_cast<std::size_t>(key.level)];
      ++l.stats.tiles;
      l.stats.vertices += tile.mesh.vertices.size();
      l.stats.line_segments += tile.line_segments;
      l.stats.lines_dropped += tile.lines_dropped;
      l.stats.outlines_dropped += tile.outline_dropped;
      l.stats.chose_from_all += tile.chose_from_all;
      l.stats.error.add(tile.error);
      if (key.level > 0) built->keep(key, std::move(tile.tin_vertices));
      job.progress(fraction(key));
      if (l.stats.tiles == l.count) log_level(job, key.level, l.stats);
    }
    batch.clear();
  };
  for (int level = max_level; level >= 0; --level) {
    const LevelRun& l = levels[static_cast<std::size_t>(level)];
    built.emplace(l.range);
    for (std::uint32_t x = l.range.start_x; x <= l.range.end_x; ++x)
      for (std::uint32_t y = l.range.start_y; y <= l.range.end_y; ++y) {
        batch.push_back({level, x, y});
        // A tile of a coarse level measures a large share of the TIN's vertices, listed for it:
        // two are built at once, so that memory does not grow with the threads.
        if (batch.size() == 8 * workers ||
            (batch.size() >= kHeavyAtOnce && l.share / static_cast<double>(l.count) > 0.01))
          flush();
      }
    if (!batch.empty()) flush();
    finer = std::move(built);
  }
}

void log_units(Job& job, const TerrainSource& source) {
  const qm::HeightUnits& u = source.units();
  if (u.to_metres != 1)
    job.info("terrain: heights in " + u.unit + ", converted to metres (x " +
             short_number(u.to_metres) + ")");
  if (!u.ellipsoidal)
    job.info("terrain: heights kept as given (" +
             (u.vertical.empty() ? std::string("no vertical CRS") : u.vertical) +
             "), not above the WGS 84 ellipsoid");
}

// Once the new pyramid is in place, the tiles of the earlier one in the folder that it did not
// write (other levels, other areas) go, so that the folder is the pyramid its layer.json
// describes; LEVELS: the new pyramid's tiles, by level. The new pyramid is complete whatever
// happens here, so a failure is a warning.
void remove_earlier_tiles_after_commit(Job& job, std::vector<qm::TileRange> levels) {
  job.outputs.after_commit([&job, levels = std::move(levels)] {
    const std::string& dir = job.options.terrain.path;
    const auto written = [&levels](const qm::TileKey& k) {
      if (static_cast<std::size_t>(k.level) >= levels.size()) return false;
      const qm::TileRange& r = levels[static_cast<std::size_t>(k.level)];
      return k.x >= r.start_x && k.x <= r.end_x && k.y >= r.start_y && k.y <= r.end_y;
    };
    try {
      const qm::TileRemoval r = qm::remove_tiles(dir, written);
      if (r.removed)
        job.info("terrain: removed " + count_text(r.removed, "tile") + " of the earlier pyramid");
      if (r.failed)
        job.warn(dir + ": the new pyramid is complete, but " +
                 count_text(r.failed, "tile or folder", "tiles or folders") +
                 " of the earlier one could not be removed (first: " + r.first_failure + ")");
    } catch (const std::exception& e) {
      job.warn(dir +
               ": the new pyramid is complete, but the earlier one's tiles could not be "
               "removed: " +
               e.what());
    }
  });
}

void run(Job& job) {
  const BuildOptions::Terrain& o = job.options.terrain;
  std::error_code ec;
  const bool replacing = job.options.write.overwrite && std::filesystem::is_directory(o.path, ec);
  const TerrainSource source(job.tin(), job.crs_wkt, job.describe_inputs(), o.fill_height,
                             job.options.threads);
  log_units(job, source);
  if (!o.fill_height)
    job.info("terrain fill height: " + short_number(source.fill_height()) +
             " m (the TIN's lowest)");
  const double spacing = source.point_spacing_metres();
  const int max_level = o.max_level ? *o.max_level : level_for_spacing(spacing);
  job.info("terrain: levels 0-" + count_text(max_level) +
           (o.max_level ? "" : " (point spacing " + short_number(spacing) + " m)"));
  // Levels given were checked right after read, over the points' extent, which holds the TIN's.
  const std::uint64_t limit = o.max_tiles_or_default();
  // Checked again over the TIN's own bounds, which the points' box checked before only samples.
  const std::uint64_t tiles = checked_tile_count(
      source.bounds(), max_level, limit,
      o.max_level
          ? "levels 0-" + count_text(max_level)
          : "the default levels 0-" + count_text(max_level) + " (the data's point spacing)");
  job.info("terrain: " + count_text(tiles, "tile") + " over the data's " +
           box_text(source.bounds()) + " (at most " + count_text(limit) + ")");
  qm::TerrainLayer layer;
  layer.bounds = source.bounds();
  layer.extensions = {"octvertexnormals", "metadata"};
  layer.metadata_availability = 1;  // every tile's metadata lists its children
  std::vector<qm::TileRange> levels;
  for (int level = 0; level <= max_level; ++level) {
    levels.push_back(level_tiles(source.bounds(), level));
    layer.available.push_back({levels.back()});
  }
  write_levels(job, source, levels);
  write_file(job, o.path + "/layer.json", qm::layer_json(layer));
  if (replacing) remove_earlier_tiles_after_commit(job, std::move(levels));
}

constexpr const char* kFolderWhat = "the web terrain (--terrain)";

// The folder is made when the tiles are written: until then, a new one is checked as a file
// would be (its parent folder exists and is writable). One that exists may hold only an earlier
// pyramid, which only --overwrite replaces, and no input or other output of the run: the
// earlier pyramid's tiles that the new one does not write are removed after the run.
void plan(const BuildOptions& o, FilePlan& files) {
  std::error_code ec;
  const bool exists = std::filesystem::exists(o.terrain.path, ec);
  files.outputs.push_back({exists ? o.terrain.path + "/layer.json" : o.terrain.path, kFolderWhat});
  files.folders.push_back({o.terrain.path, kFolderWhat, qm::check_pyramid_folder});
}

// ---- terrain_crs -------------------------------------------------------------------------------

// The longitude/latitude box of the read points' extent, its sides sampled (a projected
// rectangle's sides curve on the globe): the pyramid's bounds before there is a TIN.
qm::GeoRectangle points_lon_lat_box(const Job& job) {
  BBox extent;
  for (const Point3& p : job.points) extent.add(p.x, p.y);
  const double west = extent.min_x, east = extent.max_x, south = extent.min_y, north = extent.max_y;
  constexpr int kSteps = 16;
  std::vector<Point3> sides;
  for (int i = 0; i <= kSteps; ++i) {
    const double t = static_cast<double>(i) / kSteps;
    const double x = west + t * (east - west), y = south + t * (north - south);
    sides.insert(sides.end(), {{x, south, 0}, {x, north, 0}, {west, y, 0}, {east, y, 0}});
  }
  qm::to_lon_lat_metres(job.crs_wkt, sides, job.describe_inputs());
  qm::GeoRectangle box{sides[0].x, sides[0].y, sides[0].x, sides[0].y};
  for (const Point3& p : sides)
    box = {std::min(box.west, p.x), std::min(box.south, p.y), std::max(box.east, p.x),
           std::max(box.north, p.y)};
  return box;
}

// Right after read: the CRS, and with the levels given, the pyramid's size from the points'
// extent, so that neither stops the job after the TIN is made.
void check_crs(Job& job) {
  if (job.crs_wkt.empty())
    throw InputError(job.describe_inputs(), "",
                     "web terrain (--terrain) needs the data's CRS to place it on the globe, and "
                     "the input has none: assign one with --a-srs");
  const BuildOptions::Terrain& o = job.options.terrain;
  if (o.max_level && !job.points.empty())
    checked_tile_count(points_lon_lat_box(job), *o.max_level, o.max_tiles_or_default(),
                       "levels 0-" + count_text(*o.max_level));
}

// ---- options -----------------------------------------------------------------------------------

// "MIN-MAX", whole levels 0 <= MIN <= MAX <= kMaxTileLevel.
bool parse_levels(std::string_view text, int& min, int& max) {
  const std::size_t dash = text.find('-');
  if (dash == std::string_view::npos) return false;
  const auto whole = [](std::string_view t, int& v) {
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    return ec == std::errc() && end == t.data() + t.size() && !t.empty();
  };
  return whole(text.substr(0, dash), min) && whole(text.substr(dash + 1), max) && min >= 0 &&
         min <= max && max <= qm::kMaxTileLevel;
}

// A pyramid starts at level 0: CesiumJS (and the other clients) load a terrain from its two
// level-0 root tiles down, level by level, so a pyramid without them shows nothing.
std::string check_levels(std::string_view text) {
  int min = 0, max = 0;
  if (!parse_levels(text, min, max))
    return in_quotes(text) +
           " is not MIN-MAX, two levels 0 <= MIN <= MAX <= " + count_text(qm::kMaxTileLevel);
  if (min != 0)
    return in_quotes(text) + ": MIN must be 0: CesiumJS loads a terrain from its two level-0 " +
           "tiles down through every level, and finds nothing without them (give 0-" +
           count_text(max) + ")";
  return {};
}

void set_levels(BuildOptions& o, std::string_view text) {
  int min = 0, max = 0;
  parse_levels(text, min, max);
  assert(min == 0);  // check_levels refuses any other
  o.terrain.max_level = max;
}

std::string check_max_tiles(std::string_view text) {
  const auto n = parse_count(text);
  return n && *n >= 2 ? std::string()
                      : in_quotes(text) + " is not a whole number of tiles of at least 2";
}

void set_max_tiles(BuildOptions& o, std::string_view text) {
  o.terrain.max_tiles = *parse_count(text);
}

using Terrain = BuildOptions::Terrain;

constexpr OptionSpec kOptions[] = {
    text_option("--terrain", "DIR", option_groups::products,
                set_text<&BuildOptions::terrain, &Terrain::path>,
                "Web terrain: a Cesium quantized-mesh-1.0 pyramid, DIR/layer.json and\n"
                "DIR/{z}/{x}/{y}.terrain, each level within Cesium's geometric error\n"
                "(needs a CRS)"),
    checked_option("--terrain-levels", "MIN-MAX", option_groups::products, check_levels, set_levels,
                   "The pyramid's levels, MIN 0 (clients start from level 0; default: 0\n"
                   "to the level of the data's point spacing)"),
    checked_option("--terrain-fill-height", "H", option_groups::products, check_number,
                   set_number<&BuildOptions::terrain, &Terrain::fill_height>,
                   "Height (metres) of the tiles' surface beyond the data (default: the\n"
                   "TIN's lowest height)"),
    with_default(
        checked_option("--terrain-max-tiles", "N", option_groups::products, check_max_tiles,
                       set_max_tiles,
                       "The most tiles a pyramid may have: a larger one, which could fill\n"
                       "the disk, is refused before any tile is made"),
        "2000000",
        [](const BuildOptions& o) { return std::to_string(o.terrain.max_tiles_or_default()); }),
};

}  // namespace

constexpr StageProgress kCrsProgress{"placing the data on the globe"};
constexpr StageProgress kTerrainProgress{"making the web terrain"};

extern const Stage terrain_crs_stage{"web_terrain_crs", "", wanted, check_crs,
                                     nullptr,           "", {},     kCrsProgress};
extern const Stage terrain_stage{"web_terrain", "web_terrain",   wanted, run, plan, "",
                                 kOptions,      kTerrainProgress};

}  // namespace tincdt::pipeline
