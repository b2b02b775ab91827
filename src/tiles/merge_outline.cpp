#include "tiles/merge_outline.hpp"

#include <algorithm>
#include <charconv>
#include <sstream>
#include <string>
#include <vector>

namespace tincdt::tiles::detail {

std::string mark_text(const TileMark& mark) {
  std::string s = "tiles of ";
  s += std::to_string(mark.count);
  s += ':';
  for (const std::uint32_t t : mark.tiles) {
    s += ' ';
    s += std::to_string(t);
  }
  return s;
}

std::optional<TileMark> parse_mark(const std::string& text) {
  std::istringstream in(text);
  std::string tiles, of, count;
  TileMark mark;
  if (!(in >> tiles >> of >> count) || tiles != "tiles" || of != "of" || count.empty() ||
      count.back() != ':')
    return std::nullopt;
  count.pop_back();
  const auto whole = [](const std::string& s, std::uint32_t& v) {
    const char* end = s.data() + s.size();
    return !s.empty() && std::from_chars(s.data(), end, v).ptr == end;
  };
  if (!whole(count, mark.count)) return std::nullopt;
  for (std::string t; in >> t;) {
    std::uint32_t v = 0;
    if (!whole(t, v) || v >= mark.count) return std::nullopt;
    mark.tiles.push_back(v);
  }
  if (mark.tiles.empty()) return std::nullopt;
  return mark;
}

void write_outline(io::OutputFile& file, const std::vector<Border>& edges, const std::string& crs,
                   const std::string& trimmed) {
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
  if (!trimmed.empty()) out += "comment trimmed " + trimmed + "\n";
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
