// Internal to the plan (plan.cpp): the convex hull of a point file and its points near the hull,
// from which the plan makes the rim of all the data (tile_rules.hpp, Rim).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/points/point_reader.hpp"

namespace tincdt::tiles::detail {

struct PointScan {
  std::uint64_t points = 0;  // kept by the filter
  BBox bounds;               // exact
  std::vector<Point2> hull;  // counter-clockwise
  // Every point within WIDTH of the hull's boundary (a superset of the file's part of the rim:
  // a point is at least as far from the whole data's hull boundary as from its file's).
  std::vector<Point3> near_outline;
  // COPC: the points of the nodes left unread, as the hierarchy counts them (before filters).
  std::uint64_t unread_points = 0;
  std::uint64_t unread_nodes = 0;
  std::uint64_t nodes = 0;
};

// Reads PATH with FILTER (XYZ text on THREADS threads, 0 = every core) and measures it. A COPC
// file is read node by node, a level of its octree at a time, leaving out the nodes that lie
// inside HULL (the data's hull so far, with this file's nodes read) farther than WIDTH from its
// boundary: they cannot hold hull or rim points (plan_copc.cpp).
PointScan scan_points(const std::string& path, const io::PointFilter& filter, double width,
                      unsigned threads, const std::vector<Point2>& hull = {});

// The measures of POINTS (scan_points() without the reading).
PointScan measure_points(const std::vector<Point3>& points, double width);

// scan_points() of the COPC file COPC, read node by node.
PointScan scan_copc(const io::CopcNodes& copc, const io::PointFilter& filter, double width,
                    unsigned threads, std::vector<Point2> hull);

// Whether the closed box B lies inside the convex polygon HULL (counter-clockwise) farther than
// WIDTH from its boundary, with room for rounding.
bool deep_inside(const BBox& b, const std::vector<Point2>& hull, double width);

}  // namespace tincdt::tiles::detail
