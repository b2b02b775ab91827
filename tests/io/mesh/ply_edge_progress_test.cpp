// The PLY writer's `edge` element (the constrained edges) is polled for a request to stop, as its
// faces are: a stop asked once the faces are written, before the edges are, ends the write with
// Cancelled and no file.
#include <gtest/gtest.h>

#include <cstdint>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "io/mesh/tin_writer.hpp"
#include "io/output_file.hpp"
#include "support/files.hpp"
#include "support/meshes.hpp"

namespace tincdt::io {
namespace {

// One binary PLY edge record: two uint32 vertex numbers.
constexpr std::size_t kEdgeBytes = 8;

TEST(PlyEdgeProgress, TheEdgeElementReportsBeforeTheEnd) {
  const std::string dir = test::scratch_dir("ply_edge_progress");
  const mesh::Triangulation tin = test::unit_square(/*constrain_diagonal=*/true);
  std::vector<double> fractions;
  const ProgressFn record = [&](std::string_view stage, double fraction) {
    EXPECT_EQ(stage, "write");
    fractions.push_back(fraction);
    return true;
  };
  TinWriteOptions o;
  o.progress = &record;
  write_tin(dir + "/tin.ply", tin, o);
  const std::size_t size = test::slurp(dir + "/tin.ply").size();
  ASSERT_FALSE(fractions.empty());
  EXPECT_EQ(fractions.back(), 1.0);
  for (std::size_t i = 1; i < fractions.size(); ++i) EXPECT_LE(fractions[i - 1], fractions[i]);

  // Stopped at the first report that comes once the faces are on disk and the edge is not.
  double stopped_at = -1;
  {
    OutputFile out(dir + "/stopped.ply", false);
    const ProgressFn stop = [&](std::string_view, double fraction) {
      if (out.bytes_written() + kEdgeBytes < size) return true;
      stopped_at = fraction;
      return false;
    };
    o.progress = &stop;
    EXPECT_THROW(write_tin(out, tin, o), Cancelled);
    EXPECT_EQ(out.bytes_written() + kEdgeBytes, size);
  }
  EXPECT_GT(stopped_at, 0.0);
  EXPECT_LT(stopped_at, 1.0);
  EXPECT_EQ(test::names_in(dir), std::set<std::string>{"tin.ply"});
}

}  // namespace
}  // namespace tincdt::io
