// Damaged and lying LAZ files, made by editing the shared files: every case ends in a one-line
// InputError naming the file and the chunk (or point), or, for a chunk table that cannot be
// read, in the same points read another way with a warning. Never a crash, a hang or a huge
// allocation (this suite also runs under ASan+UBSan).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/types.hpp"
#include "io/points/laz/chunk_table.hpp"
#include "io/points/laz/laszip_vlr.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/laz_file_edits.hpp"
#include "io/points/laz_test_encoder.hpp"
#include "io/points/point_reader.hpp"
#include "support/files.hpp"
#include "support/shared_data.hpp"

namespace tincdt::io {
namespace {

namespace fs = std::filesystem;
using test::laz_edits::chunk_table_offset;
using test::laz_edits::chunks_of;
using test::laz_edits::get;
using test::laz_edits::laszip_payload;
using test::laz_edits::offset_to_points;
using test::laz_edits::put;
using test::laz_edits::with_table;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path kData = ::tincdt::test::shared_data();

std::string original(const std::string& name) {
  return test::slurp(kData / "laz" / (name + ".laz"));
}

// A scratch copy of BYTES for the current test.
std::string scratch(const std::string& name, const std::string& bytes) {
  const fs::path dir = fs::path(TINCDT_TEST_TMP) / "laz_bad";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  test::spit(p, bytes);
  return p.string();
}

std::vector<Point3> read_ok(const std::string& path, PointReadStats* stats = nullptr,
                            const PointFilter& filter = {}) {
  std::vector<Point3> pts;
  PointReadStats s = read_points(path, filter, pts);
  if (stats != nullptr) *stats = std::move(s);
  return pts;
}

// The InputError that reading PATH raises; a test failure if it reads or raises anything else.
std::string read_error(const std::string& path, unsigned threads = 0) {
  std::vector<Point3> pts;
  try {
    read_points(path, {}, pts, threads);
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_THAT(what, HasSubstr(path));
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line";
    return what;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return {};
  }
  ADD_FAILURE() << path << " was read without an error";
  return {};
}

std::vector<Point3> good_points(const std::string& name) {
  return read_ok((kData / "laz" / (name + ".laz")).string());
}

// ---------------------------------------------------------------------------------------------
// Truncation and chunks that end early

TEST(LazBadInput, TruncatedFileNamesTheChunkThatEndsEarly) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string b = original("autzen_trim");
  const std::vector<laz::ChunkEntry> chunks = chunks_of(b);
  ASSERT_EQ(chunks.size(), 3u);
  // Cut inside chunk 1: the table at the end is gone too, so the chunks are read in order.
  const std::string cut =
      b.substr(0, static_cast<std::size_t>(chunks[1].offset + chunks[1].size / 2));
  for (unsigned threads : {1u, 2u}) {
    EXPECT_THAT(read_error(scratch("cut_in_chunk1.laz", cut), threads),
                AllOf(HasSubstr("chunk 1, point"), HasSubstr("ends early")));
  }
  // Cut before the 8-byte table offset that starts the point data.
  EXPECT_THAT(read_error(scratch("cut_at_points.laz", b.substr(0, offset_to_points(b) + 4))),
              HasSubstr("truncated"));
}

TEST(LazBadInput, ChunkWhoseDataEndsEarly) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // autzen_trim's last chunk loses 1000 bytes; the table says so, consistently.
  const std::string b = original("autzen_trim");
  const std::vector<laz::ChunkEntry> chunks = chunks_of(b);
  std::string shorter =
      b.substr(0, static_cast<std::size_t>(chunks[2].offset + chunks[2].size - 1000));
  shorter += b.substr(chunk_table_offset(b));
  put<std::int64_t>(shorter, offset_to_points(b),
                    static_cast<std::int64_t>(chunk_table_offset(b) - 1000));
  shorter = with_table(
      shorter, {},
      {static_cast<std::uint32_t>(chunks[0].size), static_cast<std::uint32_t>(chunks[1].size),
       static_cast<std::uint32_t>(chunks[2].size - 1000)},
      false);
  EXPECT_THAT(read_error(scratch("short_chunk.laz", shorter)),
              AllOf(HasSubstr("chunk 2, point 10"), HasSubstr("ends early")));

  // A point14 chunk whose XY layer is said to be 100 bytes shorter than it is.
  std::string p14 = original("las14_pdrf6");
  const std::size_t xy_size_at = offset_to_points(p14) + 8 + 30 + 4;
  put<std::uint32_t>(p14, xy_size_at, get<std::uint32_t>(p14, xy_size_at) - 100);
  EXPECT_THAT(read_error(scratch("short_layer.laz", p14)), HasSubstr("chunk 0, point"));
  // ... or to be longer than the chunk.
  put<std::uint32_t>(p14, xy_size_at, 1u << 30);
  EXPECT_THAT(read_error(scratch("long_layer.laz", p14)),
              AllOf(HasSubstr("chunk 0"), HasSubstr("layers take more than the chunk")));
}

// ---------------------------------------------------------------------------------------------
// Chunk tables

TEST(LazBadInput, UnreadableChunkTableFallsBackToReadingInOrder) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  for (const char* name : {"autzen_trim", "simple.copc", "append-bug"}) {
    const std::string b = original(name);
    const std::vector<Point3> expected = good_points(name);
    const std::size_t table = chunk_table_offset(b);
    std::vector<std::string> damaged;
    std::string d = b;
    put<std::int64_t>(d, offset_to_points(b), static_cast<std::int64_t>(b.size()) + 5000);
    damaged.push_back(d);  // offset beyond the file
    d = b;
    put<std::int64_t>(d, offset_to_points(b), static_cast<std::int64_t>(offset_to_points(b)));
    damaged.push_back(d);  // never written: the offset points at itself
    d = b;
    put<std::uint32_t>(d, table, 5);
    damaged.push_back(d);  // unknown version
    d = b;
    put<std::uint32_t>(d, table + 4, 0x7FFFFFFF);
    damaged.push_back(d);  // more chunks than bytes
    d = b;
    for (std::size_t i = table + 8; i < table + 24 && i < d.size(); ++i)
      d[i] = static_cast<char>(0xFF);
    damaged.push_back(d);  // garbled entries
    for (std::size_t i = 0; i < damaged.size(); ++i) {
      PointReadStats stats;
      const std::string path = scratch("table_" + std::to_string(i) + ".laz", damaged[i]);
      EXPECT_EQ(read_ok(path, &stats), expected) << name << " case " << i;
      EXPECT_THAT(stats.warnings, testing::Contains(HasSubstr("the chunk table cannot be used")))
          << name << " case " << i;
    }
  }
}

TEST(LazBadInput, TableOffsetStoredAtTheEndOfTheFile) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // A streaming writer stores -1 up front and the offset in the file's last 8 bytes.
  std::string b = original("autzen_trim");
  const auto table = get<std::int64_t>(b, offset_to_points(b));
  put<std::int64_t>(b, offset_to_points(b), -1);
  b.append(8, '\0');
  put<std::int64_t>(b, b.size() - 8, table);
  PointReadStats stats;
  EXPECT_EQ(read_ok(scratch("table_at_end.laz", b), &stats), good_points("autzen_trim"));
  EXPECT_THAT(stats.warnings, testing::IsEmpty());
}

TEST(LazBadInput, VariableChunksOfFormats0To3ReadWithTheirTableOnly) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // autzen_trim re-declared with variable-size chunks: the table carries the point counts.
  std::string b = original("autzen_trim");
  const std::vector<laz::ChunkEntry> chunks = chunks_of(b);
  put<std::uint32_t>(b, laszip_payload(b) + 12, 0xFFFFFFFFu);
  std::vector<std::uint32_t> points;
  std::vector<std::uint32_t> bytes;
  for (const laz::ChunkEntry& c : chunks) {
    points.push_back(static_cast<std::uint32_t>(c.points));
    bytes.push_back(static_cast<std::uint32_t>(c.size));
  }
  const std::string variable = with_table(b, points, bytes, true);
  EXPECT_EQ(read_ok(scratch("variable.laz", variable)), good_points("autzen_trim"));
  // Without it, nothing says where one chunk ends.
  std::string no_table = variable;
  put<std::uint32_t>(no_table, chunk_table_offset(no_table), 3);
  EXPECT_THAT(read_error(scratch("variable_no_table.laz", no_table)),
              AllOf(HasSubstr("chunk table"), HasSubstr("variable sizes")));
  // A table whose counts fall short of the header's.
  points.back() -= 10;
  EXPECT_THAT(read_error(scratch("variable_short.laz", with_table(b, points, bytes, true))),
              HasSubstr("its chunks hold 109,990 points but the header announces 110,000"));
}

// ---------------------------------------------------------------------------------------------
// The LASzip VLR and the header

// The error that reading a scratch copy NAME of B raises, its T at AT set to VALUE.
template <class T>
std::string error_with(const std::string& b, std::size_t at, T value, const std::string& name) {
  std::string d = b;
  put<T>(d, at, value);
  return read_error(scratch(name, d));
}

TEST(LazBadInput, UnknownCompressorCoderOrItemVersion) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string b = original("autzen_trim");
  const std::size_t vlr = laszip_payload(b);
  EXPECT_THAT(error_with<std::uint16_t>(b, vlr, 9, "compressor.laz"),
              AllOf(HasSubstr("LASzip VLR"), HasSubstr("unknown compressor 9")));
  EXPECT_THAT(error_with<std::uint16_t>(b, vlr + 2, 1, "coder.laz"), HasSubstr("unknown coder 1"));
  // POINT10 version 1 (LASzip 1.x).
  EXPECT_THAT(error_with<std::uint16_t>(b, vlr + 34 + 4, 1, "version1.laz"),
              HasSubstr("POINT10 version 1 is not supported"));
  const std::string p14 = original("las14_pdrf6");
  EXPECT_THAT(error_with<std::uint16_t>(p14, laszip_payload(p14) + 34 + 4, 7, "version7.laz"),
              HasSubstr("POINT14 version 7 is not supported"));
}

TEST(LazBadInput, LaszipVlrThatLies) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::string b = original("autzen_trim");
  const std::size_t vlr = laszip_payload(b);
  // POINT10 is 20 bytes.
  EXPECT_THAT(error_with<std::uint16_t>(b, vlr + 34 + 2, 22, "item_size.laz"),
              AllOf(HasSubstr("do not describe point format 3"), HasSubstr("POINT10 has 20")));
  // RGB12 -> BYTE14.
  EXPECT_THAT(error_with<std::uint16_t>(b, vlr + 34 + 6 * 2, 14, "item_type.laz"),
              HasSubstr("should be RGB12"));
  // More items than the VLR holds.
  EXPECT_THAT(error_with<std::uint16_t>(b, vlr + 32, 200, "item_count.laz"),
              HasSubstr("lists 200 items"));
  // Chunk size: the table lists 3 chunks, not 110.
  EXPECT_THAT(error_with<std::uint32_t>(b, vlr + 12, 1000, "chunk_size.laz"),
              AllOf(HasSubstr("chunk table"), HasSubstr("need 110")));
  // The same lie with an unreadable table: the chunks read in order cannot end at the table.
  std::string d = b;
  put<std::uint32_t>(d, vlr + 12, 1000);
  put<std::uint32_t>(d, chunk_table_offset(d), 3);
  EXPECT_THAT(read_error(scratch("chunk_size_no_table.laz", d)), HasSubstr("chunk"));
  // Compressed records with no VLR saying how: its user id no longer matches.
  d = b;
  d[vlr - 54 + 2] = 'X';
  EXPECT_THAT(read_error(scratch("no_vlr.laz", d)), HasSubstr("no LASzip VLR"));
}

TEST(LazBadInput, HeaderAnnouncingMorePointsThanTheChunksHold) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::string b = original("autzen_trim");
  put<std::uint32_t>(b, 107, 220000);
  EXPECT_THAT(read_error(scratch("count_fixed.laz", b)),
              AllOf(HasSubstr("chunk table"), HasSubstr("need 5")));
  std::string copc = original("simple.copc");
  put<std::uint64_t>(copc, 247, 2130);
  EXPECT_THAT(read_error(scratch("count_copc.laz", copc)),
              HasSubstr("the header announces 2,130 points but the compressed data holds 1,065"));
  // A count no file this size could hold, with the table gone: refused before any allocation.
  std::string huge = original("autzen_trim");
  put<std::uint32_t>(huge, 107, 0xFFFFFFF0u);
  put<std::uint32_t>(huge, chunk_table_offset(huge), 3);
  EXPECT_THAT(read_error(scratch("count_huge.laz", huge)), HasSubstr("more than"));
}

TEST(LazBadInput, Point14ChunkHeadersThatLie) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // Without a table the chunks are found from their headers, which must add up.
  std::string b = original("simple.copc");
  put<std::int64_t>(b, offset_to_points(b), 1);  // table offset inside the header
  const std::vector<Point3> expected = good_points("simple.copc");
  EXPECT_EQ(read_ok(scratch("copc_walk.laz", b)), expected);
  const std::size_t first = offset_to_points(b) + 8;
  // Chunk 0 holds no points.
  EXPECT_THAT(error_with<std::uint32_t>(b, first + 36, 0, "copc_zero.laz"),
              AllOf(HasSubstr("chunk 0"), HasSubstr("holds no points")));
  // A layer past the data.
  EXPECT_THAT(error_with<std::uint32_t>(b, first + 40, 0x7FFFFFFF, "copc_layer.laz"),
              AllOf(HasSubstr("chunk 0"), HasSubstr("past the point data")));
}

TEST(LazBadInput, RenamedOrUnflaggedLazStillReads) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  const std::vector<Point3> expected = good_points("simple");
  EXPECT_EQ(read_ok(scratch("named.las", original("simple"))), expected);
  // The LASzip VLR gives the records away even without the point format's compressed flag.
  std::string unflagged = original("simple");
  unflagged[104] = static_cast<char>(unflagged[104] & 0x3F);
  EXPECT_EQ(read_ok(scratch("unflagged.laz", unflagged)), expected);
  // Waveform formats 4 and 5 keep their packets in the coordinates' stream: refused.
  std::string wave = original("simple");
  wave[104] = static_cast<char>(0x84);
  EXPECT_THAT(read_error(scratch("format4.laz", wave)), HasSubstr("point format 4"));
}

// ---------------------------------------------------------------------------------------------
// Crashers found by tests/fuzz/laz_fuzz.cpp, rebuilt from the shared files

TEST(LazFuzzRegression, EmptyGeoTiffKeyDirectory) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  // A 34735 record (GeoTIFF keys) of length 0 made the shared VLR parsing memcpy from a null
  // vector (UBSan: null pointer passed to memcpy). autzen_trim.laz's first VLR is that record.
  std::string b = original("autzen_trim");
  const std::size_t vlr = get<std::uint16_t>(b, 94);
  ASSERT_EQ(get<std::uint16_t>(b, vlr + 18), 34735);
  for (const int length : {0, 1, 7}) {
    put(b, vlr + 20, static_cast<std::uint16_t>(length));  // later VLRs: read from its payload
    // The shortened record misplaces the VLRs after it, the LASzip one among them: a clean
    // error naming the file, where UBSan once saw a memcpy from null.
    std::vector<Point3> pts;
    const std::string path = scratch("empty_keys.laz", b);
    try {
      read_points(path, {}, pts);
      ADD_FAILURE() << "length " << length << ": read " << pts.size() << " points";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("no LASzip VLR"), std::string::npos) << e.what();
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Random damage: an error or (rarely) garbage points, never a crash or another exception.

TEST(LazBadInput, RandomlyDamagedChunksNeverCrash) {
  TINCDT_REQUIRE_SHARED_DATA("laz");
  std::mt19937 rng(12345);
  for (const char* name :
       {"simple", "autzen_trim", "las14_pdrf6", "append-bug", "simple.copc", "1_4_w_evlr"}) {
    const std::string b = original(name);
    const std::size_t begin = offset_to_points(b);
    for (int trial = 0; trial < 12; ++trial) {
      std::string d = b;
      for (int i = 0; i < 16 << (trial % 4); ++i) {
        const std::size_t at = begin + rng() % (d.size() - begin);
        d[at] = static_cast<char>(rng());
      }
      const std::string path = scratch("random.laz", d);
      std::vector<Point3> pts;
      try {
        read_points(path, {}, pts, 1 + trial % 3);
      } catch (const InputError& e) {
        EXPECT_THAT(std::string(e.what()), HasSubstr(path));
      }
    }
  }
}

}  // namespace
}  // namespace tincdt::io
