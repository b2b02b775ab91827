#include "tiles/merge_outline.hpp"

#include <algorithm>
#include <string>
#include <vector>

namespace tincdt::tiles::detail {

void write_outline(io::OutputFile& file, const std::vector<Border>& edges, const std::string& crs,
                   bool trimmed) {
  std::vector<Point3> points;
  for (const Border& b : edges) points.insert(points.end(), {b.a, b.b, b.apex});
  const auto less = [](const Point3& p, const Point3& q) {
    return p.x < q.x || (p.x == q.x && (p.y < q.y || (p.y == q.y && p.z < q.z)));
  };
  std::sort(points.begin(), points.end(), less);
  points.erase(std::unique(points.begin(), points.end()), points.end());
  const auto id = [&](const Point3& p) {
    return static_cast<std::uint32_t>(std::lower_bound(points.begin(), points.end(), p, less) -
                                      points.begin());
  };
  std::string out = "ply\nformat binary_little_endian 1.0\ncomment tincdt tile outline\n";
  if (!crs.empty()) out += "comment crs " + crs + "\n";
  if (trimmed) out += "comment trimmed\n";
  out += "element vertex " + std::to_string(points.size()) +
         "\nproperty double x\nproperty double y\nproperty double z\n";
  out += "element edge " + std::to_string(edges.size()) +
         "\nproperty uint vertex1\nproperty uint vertex2\nproperty uint apex\n"
         "property uchar constrained\nend_header\n";
  const auto put = [&out](const auto& v) {
    out.append(reinterpret_cast<const char*>(&v), sizeof v);  // little-endian host
  };
  for (const Point3& p : points) {
    put(p.x);
    put(p.y);
    put(p.z);
  }
  for (const Border& b : edges) {
    put(id(b.a));
    put(id(b.b));
    put(id(b.apex));
    put(static_cast<std::uint8_t>(b.constrained ? 1 : 0));
  }
  file.write(out);
}

}  // namespace tincdt::tiles::detail
