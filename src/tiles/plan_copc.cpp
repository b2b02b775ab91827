// The plan's rim from a COPC file without reading it whole: the octree's levels are read one at a
// time, coarse to fine, and a node that lies deep inside the hull of what was read so far (the
// root's sample of the whole file already outlines it) can hold no point of the hull or the rim.
#include <algorithm>
#include <map>

#include "tiles/plan_rim.hpp"
#include "tiles/tile_rules.hpp"

namespace tincdt::tiles::detail {

namespace {

// The points one node gave.
struct NodePoints {
  std::uint64_t offset = 0;  // of the node's chunk: the file order
  std::size_t first = 0;     // into the points read
  std::size_t count = 0;
};

// POINTS regrouped node by node in file order: the order a read of all the nodes at once gives.
std::vector<Point3> in_file_order(const std::vector<Point3>& points,
                                  std::vector<NodePoints> nodes) {
  std::sort(nodes.begin(), nodes.end(),
            [](const NodePoints& a, const NodePoints& b) { return a.offset < b.offset; });
  std::vector<Point3> out;
  out.reserve(points.size());
  for (const NodePoints& n : nodes)
    out.insert(out.end(), points.begin() + n.first, points.begin() + n.first + n.count);
  return out;
}

}  // namespace

PointScan scan_copc(const io::CopcNodes& copc, const io::PointFilter& filter, double width,
                    unsigned threads, std::vector<Point2> hull) {
  const std::vector<io::CopcNodeSummary>& nodes = copc.nodes();
  std::map<int, std::vector<std::size_t>> levels;
  for (std::size_t i = 0; i < nodes.size(); ++i) levels[nodes[i].level].push_back(i);
  std::vector<Point3> points;
  std::vector<NodePoints> read_nodes;
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
    // CopcNodes::read gives the nodes' points in file order.
    std::sort(read.begin(), read.end(),
              [&](std::size_t a, std::size_t b) { return nodes[a].offset < nodes[b].offset; });
    const std::size_t first = points.size();
    const std::vector<std::uint64_t> kept = copc.read(read, filter, points, threads);
    for (std::size_t k = 0, at = first; k < read.size(); at += kept[k], ++k)
      read_nodes.push_back({nodes[read[k]].offset, at, static_cast<std::size_t>(kept[k])});
    for (std::size_t i = first; i < points.size(); ++i) hull.push_back({points[i].x, points[i].y});
    hull = tiles::convex_hull(std::move(hull));
  }
  // The points near the hull in the order a whole read gives them, so that the rim is the one
  // the whole file would give.
  const std::size_t chosen = read_nodes.size();
  PointScan s = measure_points(in_file_order(points, std::move(read_nodes)), width);
  s.nodes = nodes.size();
  s.unread_nodes = nodes.size() - chosen;
  s.unread_points = unread_points;
  return s;
}

}  // namespace tincdt::tiles::detail
