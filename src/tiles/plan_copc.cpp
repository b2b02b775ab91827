// The plan's rim from a COPC file without reading it whole: the octree's levels are read one at a
// time, coarse to fine, and a node that lies deep inside the hull of what was read so far (the
// root's sample of the whole file already outlines it) can hold no point of the hull or the rim.
#include <algorithm>
#include <map>

#include "tiles/plan_rim.hpp"
#include "tiles/tile_rules.hpp"

namespace tincdt::tiles::detail {

PointScan scan_copc(const std::string& path, const io::PointFilter& filter, double width,
                    unsigned threads, const std::vector<io::CopcNodeSummary>& nodes,
                    std::vector<Point2> hull) {
  std::map<int, std::vector<std::size_t>> levels;
  for (std::size_t i = 0; i < nodes.size(); ++i) levels[nodes[i].level].push_back(i);
  std::vector<std::size_t> chosen;
  std::uint64_t unread_points = 0;
  for (const auto& [level, members] : levels) {
    std::vector<std::size_t> read;
    for (const std::size_t i : members) {
      if (deep_inside(nodes[i].bounds, hull, width))
        unread_points += nodes[i].points;
      else
        read.push_back(i);
    }
    if (read.empty()) continue;
    std::vector<Point3> points;
    io::read_copc_nodes(path, filter, read, points, threads);
    for (const Point3& p : points) hull.push_back({p.x, p.y});
    hull = tiles::convex_hull(std::move(hull));
    chosen.insert(chosen.end(), read.begin(), read.end());
  }
  // The nodes chosen, read again together in file order: their points near the hull come out in
  // the order a whole read gives them, so the rim is the one the whole file would give.
  std::vector<Point3> points;
  io::read_copc_nodes(path, filter, chosen, points, threads);
  PointScan s = measure_points(points, width);
  s.nodes = nodes.size();
  s.unread_nodes = nodes.size() - chosen.size();
  s.unread_points = unread_points;
  return s;
}

}  // namespace tincdt::tiles::detail
