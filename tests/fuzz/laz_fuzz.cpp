// libFuzzer target for the LAZ decoder: the input is a whole LAZ file, decoded from memory the
// way the reader does (header, VLRs, LASzip VLR, chunk table, chunks). Whole records exercise
// every layer and item; the filtered coordinates exercise the layer skipping. Anything but an
// InputError is a bug: a crash, a sanitizer report, another exception, a hang or an allocation
// beyond what the input's size justifies. A COPC file is also read by box: its hierarchy walked
// whole, then two box reads (everything, and one quarter of the root cube) that walk only the
// pages and decode only the nodes they need.
// Seed corpus: ../shared/data/laz/*.laz (simple.copc.laz among them).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/points/laz/copc_hierarchy.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/point_reader.hpp"

namespace {

void read_by_box(const tincdt::io::laz::LazSource& source, unsigned threads,
                 std::vector<std::string>& warnings) {
  namespace laz = tincdt::io::laz;
  try {
    (void)laz::read_hierarchy(source, nullptr);
  } catch (const tincdt::InputError&) {
  }
  std::vector<tincdt::BBox> boxes{{-1e300, -1e300, 1e300, 1e300}};
  try {
    const laz::CopcInfo info =
        laz::parse_copc_info(source.path, source.copc_info, source.copc_info_size);
    boxes.push_back({info.center_x - info.halfsize / 2, info.center_y - info.halfsize / 2,
                     info.center_x, info.center_y});
  } catch (const tincdt::InputError&) {
  }
  for (const tincdt::BBox& box : boxes) {
    tincdt::io::PointFilter filter;
    filter.box = box;
    std::vector<tincdt::Point3> points;
    laz::LazReadFigures figures;
    try {
      (void)laz::read_points(source, filter, threads, points, warnings, &figures);
    } catch (const tincdt::InputError&) {
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace laz = tincdt::io::laz;
  std::vector<std::string> warnings;
  try {
    const laz::LazSource source = laz::open_laz("fuzz.laz", data, size, warnings);
    try {
      (void)laz::read_records(source, 1, warnings);
    } catch (const tincdt::InputError&) {
    }
    tincdt::io::PointFilter filter;
    filter.keep_classes = {2};
    filter.last_return_only = true;
    const unsigned threads = size % 2 == 0 ? 1 : 2;  // the ordered hand-over between threads too
    std::vector<tincdt::Point3> points;
    (void)laz::read_points(source, filter, threads, points, warnings);
    if (source.copc_info != nullptr) read_by_box(source, threads, warnings);
  } catch (const tincdt::InputError&) {
  }
  return 0;
}
