// Point-cloud readers: XYZ text, LAS 1.0-1.4 and LAZ (COPC included). Each call appends to a
// caller-owned vector so several inputs merge without a second copy.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace tincdt::io {

// Point filters. XYZ text is filtered by class when a header line names a classification
// column; a filter the input has nothing for (classes of a PLY, returns of XYZ text) is an
// InputError with Remedy::class_filter or Remedy::return_filter.
struct PointFilter {
  std::vector<std::uint8_t> keep_classes;  // empty = keep every class
  std::vector<std::uint8_t> drop_classes;
  bool first_return_only = false;
  bool last_return_only = false;
  // Tiled jobs: keep only the points inside this closed x, y box; unset = everywhere.
  std::optional<BBox> box;
};

struct PointReadStats {
  // Records in the file; for a COPC file read by box (PointFilter::box), in the nodes decoded.
  std::uint64_t points_read = 0;
  std::uint64_t points_kept = 0;  // appended after filtering
  // Bytes of the file read: the whole file, but for a COPC file read by box only its header,
  // VLRs, the hierarchy pages and the chunks of the nodes that meet the box. 0 for stdin.
  std::uint64_t bytes_read = 0;
  std::string crs_wkt;  // empty when the file carries no CRS
  std::string format;   // "xyz", "las 1.4 pdrf 6", "laz 1.2 pdrf 3", for the log
  BBox extent;  // with PointFilter::box: the x, y range of the points the other filters kept
  // Things the caller should log: the data was read, but something about it is odd (an
  // unreadable CRS record, more VLRs announced than present). Each names the file.
  std::vector<std::string> warnings;
};

// Reads PATH ("-" = XYZ from stdin), dispatching on content (LAS signature "LASF", PLY) and
// extension; LAS files whose records are compressed (LAZ, COPC) are decoded, and the vertices of
// a PLY mesh (a TIN tincdt wrote) are its points. Appends to `out`. Throws InputError naming the
// file and the line / byte / record (or LAZ chunk) at fault, and for a file that is recognisably
// something else (a raster, a vector file: Remedy::vector_as_points, an archive).
// THREADS: how many threads a reader that works in parallel (XYZ parsing, LAZ chunks) may use;
// 0 = every core.
PointReadStats read_points(const std::string& path, const PointFilter& filter,
                           std::vector<Point3>& out, unsigned threads = 0);

// A COPC file's octree node that holds points, for reading a file part by part.
struct CopcNodeSummary {
  BBox bounds;  // x, y of the node's cube, grown by the points' rounding: its points lie inside
  int level = 0;
  std::uint64_t points = 0;
  std::uint64_t bytes = 0;
  std::uint64_t offset = 0;  // of its chunk: the file order of the nodes
};

// A COPC file opened once to be read node by node (the tile plan's rim): the file is mapped and
// its hierarchy (every page) read once, however many times read() is called.
class CopcNodes {
 public:
  // PATH's nodes; none for a file that is not COPC or whose point format is not 6, 7 or 8 (a
  // whole read then says what is wrong). Throws InputError naming the file and the place for a
  // damaged hierarchy.
  explicit CopcNodes(const std::string& path);
  ~CopcNodes();
  CopcNodes(const CopcNodes&) = delete;
  CopcNodes& operator=(const CopcNodes&) = delete;

  const std::vector<CopcNodeSummary>& nodes() const { return nodes_; }

  // Appends the points of the nodes NODES (indices into nodes()) that pass FILTER (its box
  // ignored) in file order, and returns how many each node gave, in the same order.
  std::vector<std::uint64_t> read(const std::vector<std::size_t>& nodes, const PointFilter& filter,
                                  std::vector<Point3>& out, unsigned threads = 0) const;

 private:
  struct File;
  std::unique_ptr<File> file_;
  std::vector<CopcNodeSummary> nodes_;
};

PointReadStats read_xyz(const std::string& path, std::vector<Point3>& out, unsigned threads = 0);
PointReadStats read_xyz(const std::string& path, const PointFilter& filter,
                        std::vector<Point3>& out, unsigned threads = 0);
PointReadStats read_las(const std::string& path, const PointFilter& filter,
                        std::vector<Point3>& out, unsigned threads = 0);
// The CRS of LAS / LAZ file PATH (as read_las gives it) from its header and (E)VLRs alone, no
// point read; "" when it has none.
std::string read_las_crs(const std::string& path);

}  // namespace tincdt::io
