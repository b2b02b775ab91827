// COPC files read by box: the hierarchy walked from the real files and from a synthetic one whose
// hierarchy is split into pages, a box read that returns exactly the whole read's points in the
// box (in the same order), the bytes it reads, and a damaged hierarchy refused in one line that
// names the file and the page entry (or node) at fault.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/mapped_file.hpp"
#include "io/points/laz/copc_hierarchy.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/point_reader.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"

namespace {

namespace fs = std::filesystem;
using namespace tincdt;
namespace laz = io::laz;

std::string shared(const std::string& rel) {
  return (fs::path(test::shared_data()) / rel).string();
}

const char* const kSimple = "laz/simple.copc.laz";
const char* const kLoneStar = "copc/lone-star.copc.laz";

// The hierarchy of the file at PATH, walked whole or only where BOX reaches.
laz::CopcHierarchy hierarchy(const std::string& path, const BBox* box = nullptr) {
  const io::detail::MappedFile file(path);
  std::vector<std::string> warnings;
  const laz::LazSource src = laz::open_laz(path, file.data(), file.size(), warnings);
  return laz::read_hierarchy(src, box);
}

std::vector<Point3> read_all(const std::string& path, io::PointReadStats* stats = nullptr) {
  std::vector<Point3> points;
  const io::PointReadStats s = io::read_points(path, {}, points, 1);
  if (stats != nullptr) *stats = s;
  return points;
}

std::vector<Point3> read_box(const std::string& path, const BBox& box, unsigned threads,
                             io::PointReadStats* stats = nullptr) {
  io::PointFilter filter;
  filter.box = box;
  std::vector<Point3> points;
  const io::PointReadStats s = io::read_points(path, filter, points, threads);
  if (stats != nullptr) *stats = s;
  return points;
}

bool in_box(const Point3& p, const BBox& b) {
  return p.x >= b.min_x && p.x <= b.max_x && p.y >= b.min_y && p.y <= b.max_y;
}

std::vector<Point3> inside(const std::vector<Point3>& all, const BBox& box) {
  std::vector<Point3> out;
  for (const Point3& p : all)
    if (in_box(p, box)) out.push_back(p);
  return out;
}

void expect_same_points(const std::vector<Point3>& a, const std::vector<Point3>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_EQ(a[i].x, b[i].x) << i;
    ASSERT_EQ(a[i].y, b[i].y) << i;
    ASSERT_EQ(a[i].z, b[i].z) << i;
  }
}

// Boxes over the data: the sixteen cells of a 4 x 4 grid over BOUNDS grown by a buffer of a
// tenth of a cell, and one box outside it.
std::vector<BBox> boxes_over(const BBox& b) {
  std::vector<BBox> out;
  const double w = (b.max_x - b.min_x) / 4, h = (b.max_y - b.min_y) / 4;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      out.push_back({b.min_x + i * w - w / 10, b.min_y + j * h - h / 10,
                     b.min_x + (i + 1) * w + w / 10, b.min_y + (j + 1) * h + h / 10});
  out.push_back({b.max_x + w, b.max_y + h, b.max_x + 2 * w, b.max_y + 2 * h});
  return out;
}

BBox bounds_of(const std::vector<Point3>& points) {
  BBox b;
  for (const Point3& p : points) b.add(p.x, p.y);
  return b;
}

// Every box read holds, in order, exactly the whole read's points in the box; the file's bytes
// read are fewer than its size.
void expect_box_reads_match(const std::string& path) {
  io::PointReadStats whole_stats;
  const std::vector<Point3> all = read_all(path, &whole_stats);
  const std::uint64_t size = fs::file_size(path);
  EXPECT_EQ(whole_stats.bytes_read, size);
  for (const BBox& box : boxes_over(bounds_of(all))) {
    for (const unsigned threads : {1u, 3u}) {
      io::PointReadStats s;
      const std::vector<Point3> got = read_box(path, box, threads, &s);
      SCOPED_TRACE(std::to_string(box.min_x) + " " + std::to_string(box.min_y));
      expect_same_points(got, inside(all, box));
      EXPECT_EQ(s.points_kept, got.size());
      EXPECT_LT(s.bytes_read, size);
      EXPECT_LE(s.points_read, whole_stats.points_read);
    }
  }
}

// ---- the real files ----

TEST(CopcHierarchy, LoneStarHasItsFifteenNodesOnOnePage) {
  TINCDT_REQUIRE_SHARED_DATA("copc");
  const laz::CopcHierarchy h = hierarchy(shared(kLoneStar));
  EXPECT_EQ(h.pages, 1u);
  EXPECT_EQ(h.page_bytes, 480u);  // 15 entries of 32 bytes
  ASSERT_EQ(h.nodes.size(), 15u);
  std::uint64_t points = 0;
  int deepest = 0;
  for (const laz::CopcNode& n : h.nodes) {
    points += n.points;
    deepest = std::max(deepest, n.key.level);
  }
  EXPECT_EQ(points, 518862u);
  EXPECT_EQ(deepest, 2);
  // In file order: the first chunk is node 2-0-2-0, right after the chunk table's offset.
  EXPECT_EQ(h.nodes.front().key.text(), "2-0-2-0");
  EXPECT_EQ(h.nodes.front().offset, 1268u);
  EXPECT_EQ(h.nodes.front().points, 212u);
  const auto root = std::find_if(h.nodes.begin(), h.nodes.end(),
                                 [](const laz::CopcNode& n) { return n.key.level == 0; });
  ASSERT_NE(root, h.nodes.end());
  EXPECT_EQ(root->offset, 1642789u);
  EXPECT_EQ(root->bytes, 431475u);
  EXPECT_EQ(root->points, 58393u);
  EXPECT_NEAR(h.info.halfsize, 20.379875, 1e-6);
}

TEST(CopcHierarchy, ABoxKeepsTheNodesThatMeetIt) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string path = shared(kSimple);
  const laz::CopcHierarchy all = hierarchy(path);
  std::uint64_t points = 0;
  for (const laz::CopcNode& n : all.nodes) points += n.points;
  EXPECT_EQ(points, 1065u);
  EXPECT_EQ(all.nodes.size(), 65u);  // levels 0 to 3, level 3 not full
  // The south-west level-3 cell alone: the root, one node of levels 1 and 2, and that cell.
  const laz::CopcInfo& i = all.info;
  const double side = 2 * i.halfsize / 8;
  const BBox corner{i.center_x - i.halfsize + side / 4, i.center_y - i.halfsize + side / 4,
                    i.center_x - i.halfsize + side / 2, i.center_y - i.halfsize + side / 2};
  const laz::CopcHierarchy some = hierarchy(path, &corner);
  ASSERT_EQ(some.nodes.size(), 4u);
  for (const laz::CopcNode& n : some.nodes) {
    EXPECT_EQ(n.key.x, 0);
    EXPECT_EQ(n.key.y, 0);
  }
}

TEST(CopcBoxRead, SimpleGivesTheWholeReadsPointsInEachBox) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  expect_box_reads_match(shared(kSimple));
}

TEST(CopcBoxRead, LoneStarGivesTheWholeReadsPointsInEachBox) {
  TINCDT_REQUIRE_SHARED_DATA("copc");
  expect_box_reads_match(shared(kLoneStar));
}

TEST(CopcBoxRead, LoneStarCornerReadsOnlyItsNodes) {
  TINCDT_REQUIRE_SHARED_DATA("copc");
  const std::string path = shared(kLoneStar);
  // The level-2 cell 2-0-2-0 (212 points) and its ancestors: the root and node 1-0-1-0.
  const laz::CopcInfo info = hierarchy(path).info;
  const BBox cell = laz::voxel_bounds(info, {2, 0, 2, 0});
  const double q = (cell.max_x - cell.min_x) / 4;
  const BBox box{cell.min_x + q, cell.min_y + q, cell.max_x - q, cell.max_y - q};
  io::PointReadStats s;
  read_box(path, box, 2, &s);
  EXPECT_EQ(s.points_read, 212u + 8387 + 58393);
  // Header and VLRs (1260), the hierarchy's EVLR header (60) and page (480), three chunks.
  EXPECT_EQ(s.bytes_read, 1260u + 60 + 480 + 1438 + 64716 + 431475);
}

TEST(CopcBoxRead, PlainLazIsReadWhole) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string path = shared("laz/simple.laz");
  const std::vector<Point3> all = read_all(path);
  io::PointReadStats s;
  const BBox box = boxes_over(bounds_of(all))[5];
  expect_same_points(read_box(path, box, 1, &s), inside(all, box));
  EXPECT_EQ(s.points_read, 1065u);
  EXPECT_EQ(s.bytes_read, fs::file_size(path));
}

// ---- a synthetic hierarchy: simple.copc.laz with its pages split ----

struct Entry {
  std::int32_t level, x, y, z;
  std::uint64_t offset;
  std::int32_t bytes, points;
};

std::vector<Entry> entries_of(const std::string& file, std::uint64_t offset, std::uint64_t size) {
  std::vector<Entry> out;
  for (std::uint64_t at = offset; at < offset + size; at += 32) {
    Entry e;
    std::memcpy(&e.level, file.data() + at, 16);
    std::memcpy(&e.offset, file.data() + at + 16, 8);
    std::memcpy(&e.bytes, file.data() + at + 24, 4);
    std::memcpy(&e.points, file.data() + at + 28, 4);
    out.push_back(e);
  }
  return out;
}

std::string page_bytes(const std::vector<Entry>& entries) {
  std::string out;
  for (const Entry& e : entries) {
    char b[32];
    std::memcpy(b, &e.level, 16);
    std::memcpy(b + 16, &e.offset, 8);
    std::memcpy(b + 24, &e.bytes, 4);
    std::memcpy(b + 28, &e.points, 4);
    out.append(b, 32);
  }
  return out;
}

struct Synthetic {
  std::string bytes;
  std::uint64_t root_offset = 0;  // of the new root page
  std::uint64_t root_size = 0;
  std::uint64_t child_offset = 0;  // of the first child page
};

// The file with a new root page appended: the root node and one child page per level-1 node,
// each page holding that node and its descendants. The COPC info VLR points at the new root.
Synthetic split_pages(const std::string& original) {
  Synthetic s;
  s.bytes = original;
  constexpr std::size_t kInfo = 375 + 54;  // the COPC info VLR's payload, first after the header
  std::uint64_t root = 0, size = 0;
  std::memcpy(&root, original.data() + kInfo + 40, 8);
  std::memcpy(&size, original.data() + kInfo + 48, 8);
  const std::vector<Entry> all = entries_of(original, root, size);
  std::vector<Entry> top;
  for (const Entry& e : all)
    if (e.level == 0) top.push_back(e);
  for (const Entry& e : all) {
    if (e.level != 1) continue;
    std::vector<Entry> page;
    for (const Entry& d : all)
      if (d.level >= 1 && (d.x >> (d.level - 1)) == e.x && (d.y >> (d.level - 1)) == e.y &&
          (d.z >> (d.level - 1)) == e.z)
        page.push_back(d);
    const std::string bytes = page_bytes(page);
    if (s.child_offset == 0) s.child_offset = s.bytes.size();
    top.push_back(
        {e.level, e.x, e.y, e.z, s.bytes.size(), static_cast<std::int32_t>(bytes.size()), -1});
    s.bytes += bytes;
  }
  s.root_offset = s.bytes.size();
  const std::string root_page = page_bytes(top);
  s.root_size = root_page.size();
  s.bytes += root_page;
  std::memcpy(s.bytes.data() + kInfo + 40, &s.root_offset, 8);
  std::memcpy(s.bytes.data() + kInfo + 48, &s.root_size, 8);
  return s;
}

fs::path scratch() {
  return test::scratch_dir("copc_box");
}

TEST(CopcSynthetic, PagesSplitGiveTheSameNodesAndPoints) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string original = shared(kSimple);
  const Synthetic s = split_pages(test::slurp(original));
  const fs::path path = scratch() / "paged.copc.laz";
  test::spit(path, s.bytes);
  const laz::CopcHierarchy a = hierarchy(original), b = hierarchy(path.string());
  EXPECT_EQ(a.pages, 1u);
  EXPECT_EQ(b.pages, 5u);  // the root page and four child pages
  ASSERT_EQ(a.nodes.size(), b.nodes.size());
  for (std::size_t i = 0; i < a.nodes.size(); ++i) {
    EXPECT_EQ(a.nodes[i].offset, b.nodes[i].offset);
    EXPECT_EQ(a.nodes[i].key.text(), b.nodes[i].key.text());
  }
  // A box in one quarter reads the root page and that quarter's page only.
  const laz::CopcInfo& i = a.info;
  const BBox quarter{i.center_x - i.halfsize / 2, i.center_y - i.halfsize / 2,
                     i.center_x - i.halfsize / 4, i.center_y - i.halfsize / 4};
  EXPECT_EQ(hierarchy(path.string(), &quarter).pages, 2u);
  expect_box_reads_match(path.string());
  const std::vector<Point3> all = read_all(original);
  expect_same_points(read_all(path.string()), all);
}

// ---- damaged hierarchies ----

// The message of the InputError that a box read of BYTES throws ("" when none).
std::string box_read_error(const std::string& bytes, const std::string& name) {
  const fs::path path = scratch() / name;
  test::spit(path, bytes);
  try {
    read_box(path.string(), {-1e12, -1e12, 1e12, 1e12}, 1);
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find(path.string()), std::string::npos) << what;
    return what;
  }
  return "";
}

void put32(std::string& bytes, std::uint64_t at, std::int32_t v) {
  std::memcpy(bytes.data() + at, &v, 4);
}
void put64(std::string& bytes, std::uint64_t at, std::uint64_t v) {
  std::memcpy(bytes.data() + at, &v, 8);
}

TEST(CopcSynthetic, DamagedHierarchiesAreRefusedNamingThePlace) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const Synthetic s = split_pages(test::slurp(shared(kSimple)));
  const std::uint64_t root = s.root_offset;
  const std::string root_at = "hierarchy page at byte " + count_text(root);
  constexpr std::size_t kInfo = 375 + 54;
  struct Case {
    const char* name;
    std::string bytes;
    std::string expected;
  };
  std::vector<Case> cases;
  const auto add = [&](const char* name, auto&& edit, const std::string& expected) {
    Case c{name, s.bytes, expected};
    edit(c.bytes);
    cases.push_back(std::move(c));
  };
  add(
      "odd-page", [&](std::string& b) { put64(b, kInfo + 48, s.root_size - 3); },
      root_at + ": COPC hierarchy: a page of");
  add(
      "page-past-end", [&](std::string& b) { put64(b, kInfo + 40, b.size() - 32); },
      "the page ends past the");
  // Entry 1 is the first child page: made to point at the root page, a cycle.
  add(
      "cycle",
      [&](std::string& b) {
        put64(b, root + 32 + 16, root);
        put32(b, root + 32 + 24, static_cast<std::int32_t>(s.root_size));
      },
      "the page is listed twice");
  add(
      "huge-child", [&](std::string& b) { put32(b, root + 32 + 24, 0x7FFFFFE0); },
      "the page ends past the");
  add(
      "bad-level", [&](std::string& b) { put32(b, root, 99); }, root_at + ", entry 0");
  add(
      "key-outside-page", [&](std::string& b) { put32(b, s.child_offset + 4, 1); },
      "is not inside its page's node");
  add(
      "key-outside-cube", [&](std::string& b) { put32(b, root + 4, 1); },
      "lies outside the root cube");
  // Entry 0 is the root node: its chunk moved outside the point data, then its count changed.
  add(
      "node-outside", [&](std::string& b) { put64(b, root + 16, b.size() + 100); },
      "lie outside the point data");
  add(
      "node-count", [&](std::string& b) { put32(b, root + 28, 5); },
      "the hierarchy gives it 5 points, its chunk holds");
  add(
      "negative-count", [&](std::string& b) { put32(b, root + 28, -7); }, "point count -7");
  add(
      "zero-bytes", [&](std::string& b) { put32(b, root + 24, 0); }, ": 0 bytes");
  add(
      "too-many-points", [&](std::string& b) { put32(b, root + 28, 0x7FFFFFFF); },
      "more points than the header");
  add(
      "no-info", [&](std::string& b) { put64(b, kInfo + 24, 0); }, "COPC info VLR");
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string what = box_read_error(c.bytes, std::string(c.name) + ".copc.laz");
    EXPECT_NE(what.find(c.expected), std::string::npos) << what;
  }
}

TEST(CopcSynthetic, ANodeWhosePointsLeaveItsCubeIsRefused) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const Synthetic s = split_pages(test::slurp(shared(kSimple)));
  std::string bytes = s.bytes;
  // The root page's entry 0 (the root node) renamed as a level-3 corner cell: its points, spread
  // over the whole cube, now lie outside their node.
  put32(bytes, s.root_offset, 3);
  for (int k = 1; k <= 3; ++k) put32(bytes, s.root_offset + 4 * k, 0);
  const std::string what = box_read_error(bytes, "moved.copc.laz");
  EXPECT_NE(what.find("COPC node 3-0-0-0"), std::string::npos) << what;
  EXPECT_NE(what.find("lies outside the node's cube"), std::string::npos) << what;
}

}  // namespace
