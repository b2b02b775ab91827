// Chunk decoder for LAZ point formats 6-10 (LAZ specification 1.4: POINT14, RGB14, RGBNIR14 and
// BYTE14 v3/v4). A chunk is its first point stored raw, its point count, the byte size of every
// layer, then the layers: each field group is its own arithmetic-coded stream, so a layer that
// no requested field lives in is skipped unread. Every prediction is made per scanner channel:
// each of the four channels keeps its own last point and models.
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <vector>

#include "io/points/laz/arithmetic_decoder.hpp"
#include "io/points/laz/chunk.hpp"
#include "io/points/laz/integer_decompressor.hpp"
#include "io/points/laz/items.hpp"
#include "io/points/laz/laszip_vlr.hpp"
#include "io/points/laz/models.hpp"
#include "io/points/laz/predictors.hpp"

namespace tincdt::io::laz {

// Field groups a caller may ask for; the layers holding none of them are not decoded.
enum Field : unsigned {
  kCoordinates = 1u << 0,  // X, Y (always decoded), Z; return numbers come with X and Y
  kClassification = 1u << 1,
  kEveryField = 0xFFFFu,  // every layer, for whole records
};

// The 30 bytes of a format 6 record, unpacked.
struct Point14 {
  std::int32_t x = 0;
  std::int32_t y = 0;
  std::int32_t z = 0;
  std::uint16_t intensity = 0;
  std::uint8_t return_number = 0;
  std::uint8_t number_of_returns = 0;
  std::uint8_t flags = 0;    // edge of flight line (bit 5), scan direction (4), class flags (0-3)
  std::uint8_t channel = 0;  // scanner channel
  std::uint8_t classification = 0;
  std::uint8_t user_data = 0;
  std::int16_t scan_angle = 0;
  std::uint16_t point_source = 0;
  std::uint64_t gps_time = 0;     // the double's bits
  bool gps_time_changed = false;  // this point's time differs from its channel's previous one
};

class Point14Decoder {
 public:
  // FIELDS: the Field groups the sink reads (kEveryField for write_record()).
  Point14Decoder(const PointLayout& layout, unsigned fields);
  ~Point14Decoder();

  // As Point10Decoder::decode_chunk: sink(*this) per point, returns the chunk's length.
  template <class Sink>
  std::size_t decode_chunk(const ChunkInput& in, Sink&& sink) {
    const std::size_t length = begin_chunk(in);
    sink(*this);
    for (std::uint64_t i = 1; i < in.points; ++i) {
      try {
        decode_point();
      } catch (const CorruptData& e) {
        throw in.error(i, std::string("corrupt compressed data: ") + e.what());
      }
      // The XY layer is decoded for every point and takes some of its bytes each time: checking
      // it bounds the work on a chunk that claims more points than its data holds.
      if (xy_.failed()) fail(in, i);
      sink(*this);
    }
    end_chunk(in);
    return length;
  }

  // The current point.
  std::int32_t x() const { return point().x; }
  std::int32_t y() const { return point().y; }
  std::int32_t z() const { return point().z; }
  unsigned classification() const { return point().classification; }
  unsigned return_number() const { return point().return_number; }
  unsigned number_of_returns() const { return point().number_of_returns; }
  // The whole record, as the LAS file holds it (waveform packets are not decoded: formats 9
  // and 10 cannot be written back).
  void write_record(std::uint8_t* out) const;

 private:
  struct Channel;
  struct ColourChannel;
  struct BytesChannel;

  const Point14& point() const;
  std::size_t begin_chunk(const ChunkInput& in);
  void end_chunk(const ChunkInput& in) const;
  [[noreturn]] void fail(const ChunkInput& in, std::uint64_t point) const;
  void decode_point();
  void start_channel(unsigned c, const Point14& from);
  void decode_colour();
  void decode_bytes();

  PointLayout layout_;
  unsigned fields_;
  bool v4_;  // LASzip 3.4's item version 4: colour and extra bytes follow every channel switch
  unsigned layers_ = 0;

  // One decoder per layer, in chunk order: XY, Z, classification, flags, intensity, scan angle,
  // user data, point source, GPS time, [RGB], [NIR], [waveform], [one per extra byte].
  ArithmeticDecoder xy_;
  std::vector<ArithmeticDecoder> layer_;
  std::vector<bool> active_;  // layer decoded in this chunk: requested and not empty

  std::array<std::unique_ptr<Channel>, 4> channels_;
  unsigned current_ = 0;

  std::array<std::unique_ptr<ColourChannel>, 4> colour_;
  unsigned colour_current_ = 0;  // channel whose models code the colour
  unsigned colour_last_ = 0;     // channel whose last colour the current point holds
  std::array<std::unique_ptr<BytesChannel>, 4> bytes_;
  unsigned bytes_current_ = 0;
  unsigned bytes_last_ = 0;
};

}  // namespace tincdt::io::laz
