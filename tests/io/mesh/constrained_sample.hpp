// The writers' tests' sample TIN, from its points: the points POINTS with a constrained polyline
// (the 6 points from FIRST on) and a constrained ring (the 8 points from RING on), and with HOLES
// every 7th triangle removed, so that writers compact their vertices; and writing one alone.
#pragma once

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"
#include "io/crs.hpp"
#include "io/mesh/tin_writer.hpp"
#include "support/files.hpp"

namespace tincdt::test {

inline mesh::Triangulation constrained_sample(std::vector<Point3>&& points, std::uint32_t first,
                                              std::uint32_t ring, bool holes) {
  delaunay::DelaunayResult dt = delaunay::triangulate(std::move(points), {.keep_point_map = true});
  std::vector<constraints::Segment> segs;
  for (std::uint32_t i = 0; i + 1 < 6; ++i)
    segs.push_back({dt.vertex_of_point[first + i], dt.vertex_of_point[first + i + 1], 0});
  for (std::uint32_t i = 0; i < 8; ++i)
    segs.push_back({dt.vertex_of_point[ring + i], dt.vertex_of_point[ring + (i + 1) % 8], 1});
  constraints::insert_constraints(dt.tin, segs);
  if (holes) {
    for (TriangleId t = 0; t < dt.tin.triangle_slots(); t += 7)
      if (!dt.tin.is_ghost(t)) dt.tin.set_removed(t, true);
    dt.tin.recount();
  }
  return std::move(dt.tin);
}

// TIN written to DIR/NAME in EPSG:32611 by a format that holds its CRS, checked to be the only
// file in DIR (no sidecar) and as long as its stats say.
inline io::TinWriteStats write_alone_with_crs(const std::string& dir, const std::string& name,
                                              const mesh::Triangulation& tin) {
  io::TinWriteOptions o;
  o.crs_wkt = io::crs_from_user("EPSG:32611");
  const io::TinWriteStats stats = io::write_tin(dir + "/" + name, tin, o);
  EXPECT_EQ(stats.bytes, std::filesystem::file_size(dir + "/" + name));
  EXPECT_EQ(names_in(dir), std::set<std::string>{name});
  return stats;
}

}  // namespace tincdt::test
