// libFuzzer target for the LAZ decoder: the input is a whole LAZ file, decoded from memory the
// way the reader does (header, VLRs, LASzip VLR, chunk table, chunks). Whole records exercise
// every layer and item; the filtered coordinates exercise the layer skipping. Anything but an
// InputError is a bug: a crash, a sanitizer report, another exception, a hang or an allocation
// beyond what the input's size justifies.
// Seed corpus: ../shared/data/laz/*.laz.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/point_reader.hpp"

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
  } catch (const tincdt::InputError&) {
  }
  return 0;
}
