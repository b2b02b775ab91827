// Private to src/io: decoding the point records of a LAZ file (COPC included), written from the
// LAZ specification 1.4. The LAS reader parses the header, VLRs and CRS and hands the compressed
// records over as a LazSource; chunks are decoded in parallel and their points delivered in file
// order, so the result never depends on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "io/mapped_file.hpp"
#include "io/points/laz/copc_hierarchy.hpp"
#include "io/points/point_reader.hpp"
#include "io/points/point_selection.hpp"

namespace tincdt::io::laz {

// The compressed point data of a LAZ file as its LAS header and VLRs describe it.
struct LazSource {
  std::string path;
  const std::uint8_t* file = nullptr;  // the whole file, in memory
  std::size_t file_size = 0;
  std::uint64_t offset_to_points = 0;
  std::uint64_t point_count = 0;
  unsigned point_format = 0;
  std::size_t record_length = 0;
  std::uint64_t data_limit = 0;  // the point data ends here at the latest (EVLRs, file end)
  const std::uint8_t* laszip_vlr = nullptr;
  std::size_t laszip_vlr_size = 0;
  // The COPC info VLR's payload: set for a COPC file, whose hierarchy lets a box be read alone.
  const std::uint8_t* copc_info = nullptr;
  std::size_t copc_info_size = 0;
  detail::Transform transform{};
  bool check_range = false;  // the scale and offset can give coordinates beyond the range
  // When set, pages of chunks already decoded are handed back to the kernel as decoding goes.
  const detail::MappedFile* mapping = nullptr;
};

// Reads the LAS header and VLRs of the LAZ file held in [data, data + size) with the LAS
// reader's own parsing (defined in las_reader.cpp). Throws InputError naming PATH when the
// header is malformed or the records are not compressed.
LazSource open_laz(const std::string& path, const std::uint8_t* data, std::size_t size,
                   std::vector<std::string>& warnings);

// What a read decoded, and how much of the file it parsed or decoded to do so.
struct LazReadFigures {
  std::uint64_t points_decoded = 0;
  std::uint64_t chunk_bytes = 0;      // of the chunks decoded
  std::uint64_t hierarchy_bytes = 0;  // of the COPC hierarchy pages read
  bool by_box = false;                // only the COPC nodes meeting the box were read
};

// Appends the points that pass FILTER to OUT as coordinates, decoding THREADS chunks at once
// (0: one per core). Returns how many were appended. A COPC file read with a box (FILTER.box)
// decodes only the nodes whose cubes meet the box, in file order: every point of the file in
// the box is among those appended (the caller keeps the box's points; the rest come with their
// nodes), in the order a whole read gives them. Other files are decoded whole. Throws
// InputError naming the file and the chunk or COPC node (or point) at fault; OUT may then hold
// part of the points. FIGURES, when given, receives what was read.
std::uint64_t read_points(const LazSource& source, const PointFilter& filter, unsigned threads,
                          std::vector<Point3>& out, std::vector<std::string>& warnings,
                          LazReadFigures* figures = nullptr);

// Appends the points of the COPC nodes NODES (from read_hierarchy()) that pass FILTER, whose box
// is ignored, in file order; KEPT_PER_NODE, when given, receives how many each node gave, in
// file order. Throws as read_points().
std::uint64_t read_nodes(const LazSource& source, std::vector<CopcNode> nodes,
                         const PointFilter& filter, unsigned threads, std::vector<Point3>& out,
                         LazReadFigures& figures,
                         std::vector<std::uint64_t>* kept_per_node = nullptr);

// Every record in full, as the uncompressed LAS file holds them (all layers decoded): what the
// tests compare with a LAS twin, and what the fuzz target exercises.
std::vector<std::uint8_t> read_records(const LazSource& source, unsigned threads,
                                       std::vector<std::string>& warnings);

// What decoding coordinates, classification and returns of every point gives: the benchmark's
// work, with a checksum comparable to laz-perf's (the sum of the raw X, Y and Z integers).
struct LazSummary {
  std::uint64_t points = 0;
  std::int64_t xyz_sum = 0;
  std::uint64_t first_returns = 0;
  std::uint64_t last_returns = 0;
  std::uint64_t class_counts[256] = {};
};
LazSummary summarize(const LazSource& source, unsigned threads, std::vector<std::string>& warnings);

}  // namespace tincdt::io::laz
