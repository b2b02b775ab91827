// Synthetic LAS 1.2 files, written from the ASPRS LAS Specification 1.2 (2008): the public header
// block (227 bytes), an optional GeoKeyDirectoryTag VLR, point data records of format 0 (20
// bytes) or 1 (28 bytes, with GPS time); little-endian whatever the host. One writer for the
// tests, the sample generator (apps/make_sample) and the benchmarks (tests/bench/make_big_las).
// It shares no code with src/io, which reads LAS, so what it writes checks that reader
// independently. Header-only, standard library only, so that tools outside tests/ can include
// it without linking anything.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

namespace tincdt::test::las {

// One point record as stored: x, y, z are scaled integers (see quantize()).
struct Record {
  std::int32_t x = 0, y = 0, z = 0;
  std::uint16_t intensity = 0;
  std::uint8_t return_number = 1;      // 1 to 5
  std::uint8_t number_of_returns = 1;  // 1 to 5
  std::uint8_t classification = 1;     // 0 to 31
  std::int8_t scan_angle = 0;          // degrees
  std::uint16_t point_source_id = 0;
  double gps_time = 0.0;  // point format 1 only
};

// A GeoKeyDirectoryTag entry: {KeyID, TIFFTagLocation (0: the value is inline), Count, Value}.
using GeoKey = std::array<std::uint16_t, 4>;

struct Header {
  std::uint8_t point_format = 0;      // 0 or 1
  std::string_view system = "OTHER";  // system identifier; "OTHER": not from a sensor
  std::string_view software = "tincdt tests";
  std::uint16_t day = 1;  // creation day of year and year: fixed, so files are reproducible
  std::uint16_t year = 2025;
  std::array<double, 3> scale{0.01, 0.01, 0.01};
  std::array<double, 3> offset{0, 0, 0};
  std::vector<GeoKey> geokeys;  // empty: no CRS record
  // What the records hold; summarize() fills these from them.
  std::uint32_t count = 0;
  std::array<std::uint32_t, 5> by_return{};  // points by return number
  std::array<double, 3> min{0, 0, 0};
  std::array<double, 3> max{0, 0, 0};
};

inline constexpr std::uint16_t kHeaderSize = 227;
inline constexpr std::uint16_t kVlrHeaderSize = 54;

inline std::uint16_t record_length(std::uint8_t point_format) {
  return point_format == 1 ? 28 : 20;
}

// VALUE as the scaled integer stored for it, rounded half away from zero; throws
// std::range_error outside the int32 range.
inline std::int32_t quantize(double value, double scale, double offset) {
  const double scaled = std::round((value - offset) / scale);
  if (!(scaled >= -2147483648.0 && scaled <= 2147483647.0))
    throw std::range_error("coordinate out of the LAS int32 range");
  return static_cast<std::int32_t>(scaled);
}

// Appends little-endian fields to a byte string.
class Bytes {
 public:
  explicit Bytes(std::string& out) : out_(out) {}
  template <typename T>
  void put(T value) {
    static_assert(std::is_integral_v<T>);
    const auto bits = static_cast<std::make_unsigned_t<T>>(value);
    for (std::size_t i = 0; i < sizeof(T); ++i)
      out_.push_back(static_cast<char>((bits >> (8 * i)) & 0xFFu));
  }
  void put_double(double value) {
    std::uint64_t bits = 0;
    static_assert(sizeof bits == sizeof value);
    std::memcpy(&bits, &value, sizeof bits);
    put(bits);
  }
  // TEXT NUL-padded (or truncated) to WIDTH bytes.
  void put_chars(std::string_view text, std::size_t width) {
    for (std::size_t i = 0; i < width; ++i) out_.push_back(i < text.size() ? text[i] : '\0');
  }

 private:
  std::string& out_;
};

// H with the count, the points by return and the bounds of RECORDS, the bounds as a reader
// computes them (integer * scale + offset).
inline Header summarize(Header h, const std::vector<Record>& records) {
  h.count = static_cast<std::uint32_t>(records.size());
  h.by_return = {};
  h.min = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
  h.max = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const Record& r : records) {
    const std::array<std::int32_t, 3> xyz{r.x, r.y, r.z};
    for (std::size_t a = 0; a < 3; ++a) {
      const double value = xyz[a] * h.scale[a] + h.offset[a];
      h.min[a] = std::min(h.min[a], value);
      h.max[a] = std::max(h.max[a], value);
    }
    if (r.return_number >= 1 && r.return_number <= 5) ++h.by_return[r.return_number - 1u];
  }
  if (records.empty()) h.min = h.max = {0, 0, 0};
  return h;
}

// Everything before the first point record: the public header block and the GeoKey record.
inline std::string header_bytes(const Header& h) {
  std::string geokeys;  // {version 1, revision 1.0, key count}, then the keys
  if (!h.geokeys.empty()) {
    Bytes g(geokeys);
    g.put<std::uint16_t>(1);
    g.put<std::uint16_t>(1);
    g.put<std::uint16_t>(0);
    g.put(static_cast<std::uint16_t>(h.geokeys.size()));
    for (const GeoKey& key : h.geokeys)
      for (const std::uint16_t field : key) g.put(field);
  }
  const std::uint32_t vlrs = h.geokeys.empty() ? 0 : 1;
  const auto offset_to_points =
      static_cast<std::uint32_t>(kHeaderSize + vlrs * kVlrHeaderSize + geokeys.size());

  std::string out;
  Bytes w(out);
  w.put_chars("LASF", 4);                               // file signature
  w.put<std::uint16_t>(0);                              // file source ID
  w.put<std::uint16_t>(0);                              // global encoding: GPS week time
  for (int i = 0; i < 16; ++i) w.put<std::uint8_t>(0);  // project ID (GUID)
  w.put<std::uint8_t>(1);                               // version major
  w.put<std::uint8_t>(2);                               // version minor
  w.put_chars(h.system, 32);
  w.put_chars(h.software, 32);
  w.put(h.day);
  w.put(h.year);
  w.put(kHeaderSize);
  w.put(offset_to_points);
  w.put(vlrs);
  w.put(h.point_format);
  w.put(record_length(h.point_format));
  w.put(h.count);
  for (const std::uint32_t n : h.by_return) w.put(n);
  for (const double s : h.scale) w.put_double(s);
  for (const double o : h.offset) w.put_double(o);
  for (std::size_t a = 0; a < 3; ++a) {  // max X, min X, max Y, min Y, max Z, min Z
    w.put_double(h.max[a]);
    w.put_double(h.min[a]);
  }
  if (out.size() != kHeaderSize) throw std::logic_error("LAS header size mismatch");

  if (vlrs != 0) {            // LASF_Projection / 34735: GeoKeyDirectoryTag
    w.put<std::uint16_t>(0);  // reserved
    w.put_chars("LASF_Projection", 16);
    w.put<std::uint16_t>(34735);
    w.put(static_cast<std::uint16_t>(geokeys.size()));
    w.put_chars("GeoTIFF GeoKeyDirectoryTag", 32);
    out += geokeys;
  }
  if (out.size() != offset_to_points) throw std::logic_error("LAS VLR size mismatch");
  return out;
}

// Appends R to OUT as a point record of POINT_FORMAT (0 or 1).
inline void append_record(std::string& out, const Record& r, std::uint8_t point_format) {
  Bytes w(out);
  w.put(r.x);
  w.put(r.y);
  w.put(r.z);
  w.put(r.intensity);
  // return number (bits 0-2), number of returns (3-5), scan direction (6), edge of line (7)
  w.put(static_cast<std::uint8_t>(r.return_number | (r.number_of_returns << 3)));
  w.put(r.classification);  // class in bits 0-4; synthetic / key-point / withheld flags clear
  w.put(r.scan_angle);
  w.put<std::uint8_t>(0);  // user data
  w.put(r.point_source_id);
  if (point_format == 1) w.put_double(r.gps_time);
}

// A whole file: H summarized from RECORDS, then the records.
inline std::string file(const Header& h, const std::vector<Record>& records) {
  const Header summarized = summarize(h, records);
  std::string out = header_bytes(summarized);
  out.reserve(out.size() + records.size() * record_length(h.point_format));
  for (const Record& r : records) append_record(out, r, h.point_format);
  return out;
}

}  // namespace tincdt::test::las
