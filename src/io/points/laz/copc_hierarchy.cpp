#include "io/points/laz/copc_hierarchy.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/load_le.hpp"

namespace tincdt::io::laz {
namespace {

// Deeper levels would make keys beyond int32 and cubes below any coordinate's precision.
constexpr std::int32_t kMaxLevel = 30;

std::string byte_at(std::uint64_t offset) {
  return "byte " + count_text(offset);
}

bool meets(const BBox& a, const BBox& b) {
  return a.min_x <= b.max_x && b.min_x <= a.max_x && a.min_y <= b.max_y && b.min_y <= a.max_y;
}

// Whether KEY is PAGE or lies inside it.
bool inside(const VoxelKey& key, const VoxelKey& page) {
  if (key.level < page.level) return false;
  const int shift = key.level - page.level;
  return (key.x >> shift) == page.x && (key.y >> shift) == page.y && (key.z >> shift) == page.z;
}

struct Page {
  std::uint64_t offset = 0;
  std::uint64_t size = 0;
  VoxelKey key;  // the node the page starts at
};

class Walker {
 public:
  Walker(const LazSource& src, const BBox* box, CopcHierarchy& h) : src_(src), box_(box), h_(h) {}

  void walk() {
    std::vector<Page> pending{{h_.info.root_offset, h_.info.root_size, VoxelKey{}}};
    while (!pending.empty()) {
      const Page page = pending.back();
      pending.pop_back();
      read_page(page, pending);
    }
    check_chunks();
  }

 private:
  [[noreturn]] void fail(const std::string& where, const std::string& what) const {
    throw InputError(src_.path, where, "COPC hierarchy: " + what);
  }

  void check_page(const Page& page, const std::string& where) {
    if (page.size == 0 || page.size % kCopcEntrySize != 0)
      fail(where, "a page of " + count_text(page.size) + " bytes, not a multiple of " +
                      count_text(kCopcEntrySize) + " bytes of entries");
    if (page.offset > src_.file_size || page.size > src_.file_size - page.offset)
      fail(where, "the page ends past the " + count_text(src_.file_size) + "-byte file");
    if (!seen_.insert(page.offset).second) fail(where, "the page is listed twice");
    // Pages that overlap could make the walk read the file many times over.
    h_.page_bytes += page.size;
    if (h_.page_bytes > src_.file_size)
      fail(where, "its pages hold more bytes than the file: they overlap");
    ++h_.pages;
  }

  VoxelKey read_key(const std::uint8_t* e, const std::string& where) const {
    const VoxelKey key{load_le<std::int32_t>(e), load_le<std::int32_t>(e + 4),
                       load_le<std::int32_t>(e + 8), load_le<std::int32_t>(e + 12)};
    if (key.level < 0 || key.level > kMaxLevel)
      fail(where, "key " + key.text() + ": level " + signed_count_text(key.level) + " (0 to " +
                      count_text(kMaxLevel) + ")");
    const std::int64_t cells = std::int64_t{1} << key.level;
    for (const std::int32_t v : {key.x, key.y, key.z})
      if (v < 0 || v >= cells)
        fail(where, "key " + key.text() + " lies outside the root cube (level " +
                        count_text(key.level) + " has " + count_text(cells) + " cells a side)");
    return key;
  }

  void read_page(const Page& page, std::vector<Page>& pending) {
    const std::string page_where = "hierarchy page at " + byte_at(page.offset);
    check_page(page, page_where);
    const std::uint64_t count = page.size / kCopcEntrySize;
    for (std::uint64_t i = 0; i < count; ++i) {
      const std::uint8_t* e = src_.file + page.offset + i * kCopcEntrySize;
      const std::string where = page_where + ", entry " + count_text(i);
      const VoxelKey key = read_key(e, where);
      if (!inside(key, page.key))
        fail(where, "key " + key.text() + " is not inside its page's node " + page.key.text());
      const auto offset = load_le<std::uint64_t>(e + 16);
      const auto bytes = load_le<std::int32_t>(e + 24);
      const auto points = load_le<std::int32_t>(e + 28);
      const BBox bounds = grown(voxel_bounds(h_.info, key));
      if (box_ != nullptr && !meets(bounds, *box_)) continue;
      if (points == -1) {
        if (bytes <= 0) fail(where, "a child page of " + signed_count_text(bytes) + " bytes");
        pending.push_back({offset, static_cast<std::uint64_t>(bytes), key});
      } else if (points > 0) {
        add_node(key, offset, bytes, static_cast<std::uint64_t>(points), bounds, where);
      } else if (points < -1) {
        fail(where, "point count " + signed_count_text(points) + " (-1: a child page, 0: empty)");
      }
    }
  }

  void add_node(const VoxelKey& key, std::uint64_t offset, std::int32_t bytes, std::uint64_t points,
                const BBox& bounds, const std::string& where) {
    const std::uint64_t begin = src_.offset_to_points + 8;  // after the chunk table's offset
    if (bytes <= 0) fail(where, "node " + key.text() + ": " + signed_count_text(bytes) + " bytes");
    const auto size = static_cast<std::uint64_t>(bytes);
    if (offset < begin || offset > src_.data_limit || size > src_.data_limit - offset)
      fail(where, "node " + key.text() + ": its " + count_text(size) + " bytes at " +
                      byte_at(offset) + " lie outside the point data (" + byte_at(begin) + " to " +
                      byte_at(src_.data_limit) + ")");
    total_points_ += points;
    if (total_points_ > src_.point_count)
      fail(where, "its nodes hold more points than the header's " + count_text(src_.point_count));
    h_.nodes.push_back({key, offset, size, points, bounds});
  }

  BBox grown(BBox b) const {
    b.min_x -= h_.tolerance;
    b.min_y -= h_.tolerance;
    b.max_x += h_.tolerance;
    b.max_y += h_.tolerance;
    return b;
  }

  // Chunks in file order, none overlapping another (the same points would be read twice).
  void check_chunks() {
    std::sort(h_.nodes.begin(), h_.nodes.end(),
              [](const CopcNode& a, const CopcNode& b) { return a.offset < b.offset; });
    for (std::size_t i = 1; i < h_.nodes.size(); ++i) {
      const CopcNode& a = h_.nodes[i - 1];
      const CopcNode& b = h_.nodes[i];
      if (a.offset + a.bytes > b.offset)
        throw InputError(src_.path, "COPC node " + b.key.text() + ", " + byte_at(b.offset),
                         "COPC hierarchy: its chunk overlaps that of node " + a.key.text() + " (" +
                             byte_at(a.offset) + ", " + count_text(a.bytes) + " bytes)");
    }
  }

  const LazSource& src_;
  const BBox* box_;
  CopcHierarchy& h_;
  std::set<std::uint64_t> seen_;
  std::uint64_t total_points_ = 0;
};

}  // namespace

std::string VoxelKey::text() const {
  return std::to_string(level) + "-" + std::to_string(x) + "-" + std::to_string(y) + "-" +
         std::to_string(z);
}

CopcInfo parse_copc_info(const std::string& path, const std::uint8_t* p, std::size_t size) {
  if (p == nullptr || size < kCopcInfoSize)
    throw InputError(path, "COPC info VLR",
                     "holds " + count_text(size) + " bytes, not the " + count_text(kCopcInfoSize) +
                         " of the COPC specification");
  CopcInfo info;
  info.center_x = load_le<double>(p);
  info.center_y = load_le<double>(p + 8);
  info.center_z = load_le<double>(p + 16);
  info.halfsize = load_le<double>(p + 24);
  info.spacing = load_le<double>(p + 32);
  info.root_offset = load_le<std::uint64_t>(p + 40);
  info.root_size = load_le<std::uint64_t>(p + 48);
  if (!std::isfinite(info.center_x) || !std::isfinite(info.center_y) ||
      !std::isfinite(info.center_z) || !(info.halfsize > 0) || !std::isfinite(info.halfsize))
    throw InputError(path, "COPC info VLR",
                     "its root cube (centre and half size) is not a finite cube of positive size");
  return info;
}

BBox voxel_bounds(const CopcInfo& info, const VoxelKey& key) {
  const double side = 2 * info.halfsize / static_cast<double>(std::int64_t{1} << key.level);
  const double x0 = info.center_x - info.halfsize;
  const double y0 = info.center_y - info.halfsize;
  return {x0 + key.x * side, y0 + key.y * side, x0 + (key.x + 1) * side, y0 + (key.y + 1) * side};
}

CopcHierarchy read_hierarchy(const LazSource& src, const BBox* box) {
  CopcHierarchy h;
  h.info = parse_copc_info(src.path, src.copc_info, src.copc_info_size);
  // A point lies in its node's cube as the writer computed it from the point's coordinates; the
  // cube as computed here may differ by rounding, and the coordinates by a scale unit.
  const double magnitude =
      std::max({std::fabs(h.info.center_x), std::fabs(h.info.center_y), h.info.halfsize, 1.0});
  h.tolerance =
      std::max(std::fabs(src.transform.sx), std::fabs(src.transform.sy)) + 0x1p-40 * magnitude;
  Walker(src, box, h).walk();
  return h;
}

}  // namespace tincdt::io::laz
