// The LASzip VLR (user id "laszip encoded", record 22204): how the point records of a LAZ file
// were compressed. Written from the LAZ specification 1.4.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace tincdt::io::laz {

inline constexpr std::uint32_t kVariableChunks = 0xFFFFFFFFu;

// One entry of the VLR's item list: a run of bytes of the point record and its coder.
struct LaszipItem {
  std::uint16_t type = 0;  // see item_name()
  std::uint16_t size = 0;
  std::uint16_t version = 0;
};

struct LaszipVlr {
  std::uint16_t compressor = 0;  // 1 pointwise, 2 pointwise chunked, 3 layered chunked
  std::uint16_t coder = 0;       // 0 arithmetic
  std::uint32_t chunk_size = 0;  // points per chunk; kVariableChunks when each chunk says
  std::vector<LaszipItem> items;
};

// Parses the VLR payload; throws InputError naming PATH when it is too short for what it lists.
LaszipVlr parse_laszip_vlr(const std::string& path, const std::uint8_t* payload, std::size_t size);

// The records a chunk decoder works on: the point format's family and its optional items, as
// checked against the header's point format and record length.
struct PointLayout {
  bool layered = false;   // formats 6-10: POINT14 and its layered companions (LAZ 1.4)
  unsigned version = 0;   // coder version of every item: 2 (formats 0-5), 3 or 4 (6-10)
  bool gps_time = false;  // formats 0-5 only; formats 6-10 always carry one
  bool rgb = false;
  bool nir = false;       // formats 8 and 10
  bool waveform = false;  // formats 4, 5, 9, 10
  unsigned extra_bytes = 0;
  std::size_t record_length = 0;
  bool variable_chunks = false;
  std::uint32_t chunk_size = 0;  // points per chunk when fixed
  bool chunked = true;           // false: compressor 1, all points in one stream, no table
};

// Checks that the VLR describes POINT_FORMAT records of RECORD_LENGTH bytes with coders this
// reader knows, and says how they are laid out. Throws InputError naming PATH otherwise: an
// unknown compressor, coder or item version, or items that do not add up to the records the
// header announces (a VLR that lies).
PointLayout check_layout(const std::string& path, const LaszipVlr& vlr, unsigned point_format,
                         std::size_t record_length);

}  // namespace tincdt::io::laz
