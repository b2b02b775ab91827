// LAS 1.0-1.4 reader, written from the ASPRS LAS specification (1.0 2003, 1.1 2005, 1.2 2008,
// 1.3 R11, 1.4 R15). Only what a TIN needs is decoded: X/Y/Z, classification, return numbers,
// and the CRS records. Compressed records (LAZ, COPC) share the header, VLR and CRS reading here
// and go to the decoder in laz/.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <new>
#include <string>
#include <vector>

#include "core/coordinates.hpp"
#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/crs_detail.hpp"
#include "io/mapped_file.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/load_le.hpp"
#include "io/points/point_reader.hpp"
#include "io/points/point_selection.hpp"

namespace tincdt::io {
namespace {

// ---- Public header block ----

constexpr std::size_t kMinHeaderSize = 227;  // LAS 1.0-1.2
constexpr std::size_t kHeaderSize14 = 375;   // 1.3 adds 8 bytes, 1.4 EVLRs and 64-bit counts
constexpr std::size_t kVlrHeaderSize = 54;
constexpr std::size_t kEvlrHeaderSize = 60;
// Bytes each point data record format needs (formats 0-10).
constexpr std::array<std::uint16_t, 11> kFormatSize = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

struct LasHeader {
  unsigned version_major = 0;
  unsigned version_minor = 0;
  std::size_t header_size = 0;
  std::uint64_t offset_to_points = 0;
  std::uint32_t vlr_count = 0;
  unsigned point_format = 0;
  std::size_t record_length = 0;
  std::uint64_t point_count = 0;
  std::array<double, 3> scale{};
  std::array<double, 3> offset{};
  std::uint64_t evlr_start = 0;
  std::uint32_t evlr_count = 0;
  std::uint64_t waveform_start = 0;  // LAS 1.3+: waveform packets inside the file, after the points
  bool compressed = false;           // LAZ: bit 7 (or 6, older writers) of the point format byte
};

std::string byte_at(std::uint64_t offset) {
  return "byte " + count_text(offset);
}

LasHeader parse_header(const std::string& path, const std::uint8_t* d, std::size_t size) {
  if (size < 4 || std::memcmp(d, "LASF", 4) != 0) {
    throw InputError(path, "", "not a LAS file (no 'LASF' signature)");
  }
  if (size < kMinHeaderSize) {
    throw InputError(path, "header",
                     "truncated: the file has " + count_text(size) +
                         " bytes, a LAS header needs at least " + count_text(kMinHeaderSize));
  }
  LasHeader h;
  h.version_major = d[24];
  h.version_minor = d[25];
  if (h.version_major != 1 || h.version_minor > 4) {
    throw InputError(path, "header",
                     "unsupported LAS version " + std::to_string(h.version_major) + "." +
                         std::to_string(h.version_minor) + " (LAS 1.0 to 1.4 are supported)");
  }
  h.header_size = load_le<std::uint16_t>(d + 94);
  h.offset_to_points = load_le<std::uint32_t>(d + 96);
  h.vlr_count = load_le<std::uint32_t>(d + 100);
  const std::uint8_t format_byte = d[104];
  h.record_length = load_le<std::uint16_t>(d + 105);
  h.point_count = load_le<std::uint32_t>(d + 107);
  for (int i = 0; i < 3; ++i) {
    h.scale[i] = load_le<double>(d + 131 + 8 * i);
    h.offset[i] = load_le<double>(d + 155 + 8 * i);
  }
  if (h.header_size < kMinHeaderSize) {
    throw InputError(path, "header",
                     "header size " + count_text(h.header_size) + " is smaller than the " +
                         count_text(kMinHeaderSize) + " bytes every LAS header has");
  }
  if (h.header_size > size) {
    throw InputError(path, "header",
                     "truncated: the header announces " + count_text(h.header_size) +
                         " bytes but the file has only " + count_text(size));
  }
  // LAS 1.3 and 1.4 fields, read only when the header is long enough to hold them (some writers
  // of 1.3 and 1.4 files leave the header at the 1.2 size).
  constexpr std::size_t kHeaderSize13 = 235;
  const bool internal_waveforms = (load_le<std::uint16_t>(d + 6) & 2u) != 0;  // global encoding
  if (h.version_minor >= 3 && h.header_size >= kHeaderSize13 && internal_waveforms) {
    h.waveform_start = load_le<std::uint64_t>(d + 227);
  }
  if (h.version_minor >= 4 && h.header_size >= kHeaderSize14) {
    h.evlr_start = load_le<std::uint64_t>(d + 235);
    h.evlr_count = load_le<std::uint32_t>(d + 243);
    const auto count64 = load_le<std::uint64_t>(d + 247);
    // The 64-bit count is the authority in 1.4; the legacy one is 0 when it does not fit or
    // the format is 6-10, and some writers fill only the legacy one.
    if (count64 != 0) h.point_count = count64;
  }
  // Bits 7 (LASzip) and 6 (older LAZ writers) of the format byte mark compressed records of the
  // format in the low bits; 255 and the like are no format at all.
  h.compressed = (format_byte & 0xC0) != 0 && (format_byte & 0x3F) < kFormatSize.size();
  h.point_format = h.compressed ? format_byte & 0x3Fu : format_byte;
  if (h.point_format >= kFormatSize.size()) {
    throw InputError(path, "header",
                     "unsupported point data record format " + std::to_string(h.point_format) +
                         " (formats 0 to 10 are supported)");
  }
  if (h.record_length < kFormatSize[h.point_format]) {
    throw InputError(path, "header",
                     "point record length " + count_text(h.record_length) +
                         " is smaller than the " + count_text(kFormatSize[h.point_format]) +
                         " bytes point format " + std::to_string(h.point_format) + " needs");
  }
  static const char* const kAxis[3] = {"X", "Y", "Z"};
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(h.scale[i]) || h.scale[i] == 0.0 || !std::isfinite(h.offset[i])) {
      throw InputError(path, "header",
                       std::string("invalid ") + kAxis[i] + " scale factor / offset (" +
                           number_text(h.scale[i]) + " / " + number_text(h.offset[i]) + ")");
    }
    h.offset[i] = without_signed_zero(h.offset[i]);  // so that no coordinate is -0
  }
  if (h.offset_to_points < h.header_size) {
    throw InputError(path, "header",
                     "the point data offset " + count_text(h.offset_to_points) +
                         " lies inside the " + count_text(h.header_size) + "-byte header");
  }
  if (h.offset_to_points > size) {
    throw InputError(path, "header",
                     "truncated: the point data should start at byte " +
                         count_text(h.offset_to_points) + " but the file has only " +
                         count_text(size) + " bytes");
  }
  return h;
}

// Where the point data ends at the latest: at the waveform packets or extended VLRs that follow
// it, else at the file's end.
std::uint64_t point_data_limit(const LasHeader& h, std::size_t size) {
  std::uint64_t limit = size;
  if (h.evlr_count > 0 && h.evlr_start > h.offset_to_points && h.evlr_start <= size) {
    limit = h.evlr_start;
  }
  if (h.waveform_start > h.offset_to_points && h.waveform_start < limit) limit = h.waveform_start;
  return limit;
}

// Every announced record must be in the file, before its waveform packets and extended VLRs
// (which would otherwise be read as points).
void check_point_count(const std::string& path, const LasHeader& h, std::size_t size) {
  const std::uint64_t limit = point_data_limit(h, size);
  const std::uint64_t available = limit - h.offset_to_points;
  const std::uint64_t whole = available / h.record_length;
  if (whole < h.point_count) {
    const bool followed = limit < size;  // by waveform packets or extended VLRs
    const std::string before = !followed                   ? ""
                               : limit == h.waveform_start ? " before its waveform packets"
                                                           : " before its extended VLRs";
    const std::string tail = "the file holds " + count_text(whole) + " records" + before +
                             " but the header announces " + count_text(h.point_count);
    if (available % h.record_length != 0 && !followed) {
      throw InputError(path,
                       "point record " + count_text(whole) + ", " +
                           byte_at(h.offset_to_points + whole * h.record_length),
                       "truncated: the file ends inside this record; " + tail);
    }
    throw InputError(path, "point data", tail);
  }
}

// ---- Variable length records ----

// What the (E)VLRs hold that the reader uses.
struct VlrRecords {
  std::string wkt;
  detail::GeoTiffKeys geotiff;
  const std::uint8_t* laszip = nullptr;  // the LASzip VLR's payload
  std::size_t laszip_size = 0;
  bool copc = false;  // a COPC info VLR: the file is a cloud-optimised point cloud
  const std::uint8_t* copc_info = nullptr;
  std::size_t copc_info_size = 0;
  std::uint64_t evlr_bytes = 0;  // of the extended VLRs' headers and the payloads taken
};

std::string user_id(const std::uint8_t* vlr) {
  const char* s = reinterpret_cast<const char*>(vlr + 2);
  return std::string(s, strnlen(s, 16));
}

// Records one (E)VLR's payload if it is a CRS record or says how the points are compressed.
void take_record(const std::string& uid, unsigned record_id, const std::uint8_t* payload,
                 std::size_t length, VlrRecords& crs) {
  if (uid == "laszip encoded" && record_id == 22204) {
    crs.laszip = payload;
    crs.laszip_size = length;
    return;
  }
  if (uid == "copc" && record_id == 1) {
    crs.copc = true;
    crs.copc_info = payload;
    crs.copc_info_size = length;
  }
  if (uid != "LASF_Projection") return;
  switch (record_id) {
    case 2112: {
      const char* s = reinterpret_cast<const char*>(payload);
      std::string wkt(s, strnlen(s, length));
      const auto last = wkt.find_last_not_of(" \t\r\n");
      wkt.erase(last == std::string::npos ? 0 : last + 1);
      if (!wkt.empty()) crs.wkt = std::move(wkt);
      break;
    }
    case 34735:  // (a record too short for one value leaves data() null: no memcpy)
      crs.geotiff.directory.resize(length / 2);
      if (length >= 2) std::memcpy(crs.geotiff.directory.data(), payload, length / 2 * 2);
      break;
    case 34736:
      crs.geotiff.doubles.resize(length / 8);
      if (length >= 8) std::memcpy(crs.geotiff.doubles.data(), payload, length / 8 * 8);
      break;
    case 34737:
      crs.geotiff.ascii.assign(reinterpret_cast<const char*>(payload), length);
      break;
    default:
      break;
  }
}

// A user id for a message: printable ASCII only, the rest as '?' (a damaged chain reads text
// from anywhere).
std::string printable(const std::string& text) {
  std::string out;
  for (const char c : text) out.push_back(c >= 0x20 && c < 0x7F ? c : '?');
  return out;
}

// VLRs sit between the header and the point data. A record that runs past the point data offset
// is read as far as it goes, with a warning: its payload may be whole (a wrong length) and the
// records before it are sound; the chain ends there.
void read_vlrs(const std::string& path, const LasHeader& h, const std::uint8_t* d, VlrRecords& crs,
               std::vector<std::string>& warnings) {
  const auto rest = [&](std::uint32_t after) {
    const std::uint32_t left = h.vlr_count - after;
    return left == 0 ? std::string()
                     : "; the " + count_text(left) + " record" + (left == 1 ? "" : "s") +
                           " after it " + (left == 1 ? "is" : "are") + " ignored";
  };
  std::size_t pos = h.header_size;
  for (std::uint32_t i = 0; i < h.vlr_count; ++i) {
    if (pos + kVlrHeaderSize > h.offset_to_points) {
      warnings.push_back(path + ": the header announces " + count_text(h.vlr_count) +
                         " variable length records but only " + count_text(i) +
                         " fit before the point data at " + byte_at(h.offset_to_points) +
                         "; the rest are ignored");
      return;
    }
    const std::string uid = user_id(d + pos);
    const unsigned record_id = load_le<std::uint16_t>(d + pos + 18);
    const std::size_t length = load_le<std::uint16_t>(d + pos + 20);
    const std::size_t room = h.offset_to_points - pos - kVlrHeaderSize;
    if (length > room) {
      warnings.push_back(path + ": variable length record " + count_text(i) + " ('" +
                         printable(uid) + "' " + std::to_string(record_id) + ", " + byte_at(pos) +
                         ") announces " + count_text(length) + " bytes but only " +
                         count_text(room) + " lie before the point data at " +
                         byte_at(h.offset_to_points) + "; reading those" + rest(i + 1));
      take_record(uid, record_id, d + pos + kVlrHeaderSize, room, crs);
      return;
    }
    take_record(uid, record_id, d + pos + kVlrHeaderSize, length, crs);
    pos += kVlrHeaderSize + length;
  }
}

// LAS 1.4 extended VLRs, after the point data.
void read_evlrs(const std::string& path, const LasHeader& h, const std::uint8_t* d,
                std::size_t size, VlrRecords& crs) {
  if (h.evlr_count == 0 || h.evlr_start == 0) return;
  std::uint64_t pos = h.evlr_start;
  for (std::uint32_t i = 0; i < h.evlr_count; ++i) {
    const std::string where = "extended VLR " + count_text(i) + ", " + byte_at(pos);
    if (pos > size || size - pos < kEvlrHeaderSize) {
      throw InputError(
          path, where,
          "truncated: the file ends at byte " + count_text(size) + " before this record's header");
    }
    const auto length = load_le<std::uint64_t>(d + pos + 20);
    if (length > size - pos - kEvlrHeaderSize) {
      throw InputError(path, where,
                       "truncated: the record announces " + count_text(length) +
                           " bytes but the file ends at byte " + count_text(size));
    }
    const std::string uid = user_id(d + pos);
    take_record(uid, load_le<std::uint16_t>(d + pos + 18), d + pos + kEvlrHeaderSize,
                static_cast<std::size_t>(length), crs);
    // The COPC hierarchy is read page by page, and only where a box read needs it.
    crs.evlr_bytes += kEvlrHeaderSize + (uid == "copc" ? 0 : length);
    pos += kEvlrHeaderSize + length;
  }
}

// Points are decoded in chunks of about this many bytes; the pages of each chunk are handed
// back to the kernel once it is done, so a 50M-point file never sits whole in resident memory.
constexpr std::size_t kChunkBytes = std::size_t{64} << 20;

// Appends the kept points among COUNT records at P. kExtended: point formats 6-10 (4-bit return
// fields and a full classification byte at offset 16); else formats 0-5 (3-bit return fields,
// 5-bit classification at offset 15). Returns the number appended.
using detail::Selection;
using detail::Transform;

template <bool kExtended, bool kFilter>
std::size_t decode(const std::uint8_t* p, std::size_t count, std::size_t record_length,
                   const Transform& t, const Selection& sel, std::vector<Point3>& out) {
  const std::size_t before = out.size();
  for (std::size_t i = 0; i < count; ++i, p += record_length) {
    if constexpr (kFilter) {
      const std::uint8_t returns = p[14];
      unsigned cls;
      unsigned ret;
      unsigned nret;
      if constexpr (kExtended) {
        cls = p[16];
        ret = returns & 0x0Fu;
        nret = returns >> 4;
      } else {
        cls = p[15] & 0x1Fu;
        ret = returns & 0x07u;
        nret = (returns >> 3) & 0x07u;
      }
      if (!sel.keeps(cls, ret, nret)) continue;
    }
    out.push_back(t.apply(load_le<std::int32_t>(p), load_le<std::int32_t>(p + 4),
                          load_le<std::int32_t>(p + 8)));
  }
  return out.size() - before;
}

using DecodeFn = std::size_t (*)(const std::uint8_t*, std::size_t, std::size_t, const Transform&,
                                 const Selection&, std::vector<Point3>&);

DecodeFn pick_decoder(bool extended, bool filter) {
  if (extended) return filter ? decode<true, true> : decode<true, false>;
  return filter ? decode<false, true> : decode<false, false>;
}

// Refuses the first of COUNT records at P (record FIRST onwards) with a coordinate outside the
// range tincdt accepts. Needed only when the scale and offset allow one.
void check_range(const std::string& path, const std::uint8_t* p, std::size_t count,
                 std::size_t record_length, const Transform& t, std::uint64_t first) {
  for (std::size_t i = 0; i < count; ++i, p += record_length) {
    const Point3 v = t.apply(load_le<std::int32_t>(p), load_le<std::int32_t>(p + 4),
                             load_le<std::int32_t>(p + 8));
    t.check_range(v, path, "point record " + count_text(first + i));
  }
}

std::string format_label(const LasHeader& h) {
  return "las " + std::to_string(h.version_major) + "." + std::to_string(h.version_minor) +
         " pdrf " + std::to_string(h.point_format);
}

// The CRS of the file. The OGC WKT record wins over GeoTIFF keys: LAS 1.4 makes it the authority
// (formats 6-10 must carry it), and where a file has both, the WKT is the more precise of the
// two (file_with_both_wkt_and_geotiff_vlrs.las: keys for EPSG:32104 with unit overrides, a WKT
// for NAD83(2011) / Nebraska ftUS). The keys are decoded only when there is no usable WKT.
void resolve_crs(const std::string& path, const VlrRecords& rec, PointReadStats& stats) {
  const std::size_t warnings_before = stats.warnings.size();
  if (!rec.wkt.empty()) {
    const detail::CrsResult from_wkt = detail::crs_check_wkt(rec.wkt);
    if (!from_wkt.wkt.empty()) {
      stats.crs_wkt = from_wkt.wkt;
      return;
    }
    const std::string what = rec.wkt.find('[') == std::string::npos
                                 ? "holds no WKT (its text is \"" + rec.wkt.substr(0, 40) + "\")"
                                 : "cannot be read (" + from_wkt.problem + ")";
    stats.warnings.push_back(path + ": the OGC WKT CRS record " + what +
                             (rec.geotiff.empty() ? "" : "; trying the GeoTIFF keys"));
  }
  if (!rec.geotiff.empty()) {
    const detail::CrsResult from_keys = detail::crs_from_geotiff(rec.geotiff);
    stats.crs_wkt = from_keys.wkt;
    if (!from_keys.problem.empty()) stats.warnings.push_back(path + ": " + from_keys.problem);
  }
  if (stats.crs_wkt.empty() && stats.warnings.size() > warnings_before) {
    stats.warnings.back() += "; the file has no CRS";
  }
}

Transform transform_of(const LasHeader& h) {
  return {h.scale[0], h.scale[1], h.scale[2], h.offset[0], h.offset[1], h.offset[2]};
}

// Whether the records are LAZ. The format byte's flag decides; a LASzip VLR without it is taken
// at its word only when the records cannot be uncompressed ones (they would not fit the file).
bool is_laz(const std::string& path, const LasHeader& h, const VlrRecords& vlrs, std::size_t size,
            std::vector<std::string>& warnings) {
  if (h.compressed) return true;
  if (vlrs.laszip == nullptr) return false;
  if ((size - h.offset_to_points) / h.record_length < h.point_count) return true;
  warnings.push_back(path + ": a LASzip VLR, but the point format is not marked compressed and " +
                     "the records fill the file uncompressed; reading them as LAS");
  return false;
}

// The compressed records for the LAZ decoder.
laz::LazSource laz_source(const std::string& path, const LasHeader& h, const VlrRecords& vlrs,
                          const std::uint8_t* data, std::size_t size) {
  if (vlrs.laszip == nullptr) {
    throw InputError(path, "header",
                     "the point format is marked compressed (LAZ) but the file has no LASzip VLR "
                     "saying how");
  }
  laz::LazSource src;
  src.path = path;
  src.file = data;
  src.file_size = size;
  src.offset_to_points = h.offset_to_points;
  src.point_count = h.point_count;
  src.point_format = h.point_format;
  src.record_length = h.record_length;
  // EVLRs follow the point data (and the chunk table).
  src.data_limit = point_data_limit(h, size);
  src.laszip_vlr = vlrs.laszip;
  src.laszip_vlr_size = vlrs.laszip_size;
  src.copc_info = vlrs.copc_info;
  src.copc_info_size = vlrs.copc_info_size;
  src.transform = transform_of(h);
  src.check_range = !src.transform.in_range_by_header();
  return src;
}

}  // namespace

namespace laz {

LazSource open_laz(const std::string& path, const std::uint8_t* data, std::size_t size,
                   std::vector<std::string>& warnings) {
  if (size == 0) throw InputError(path, "", "empty file");
  const LasHeader h = parse_header(path, data, size);
  VlrRecords vlrs;
  read_vlrs(path, h, data, vlrs, warnings);
  read_evlrs(path, h, data, size, vlrs);
  if (!is_laz(path, h, vlrs, size, warnings)) {
    throw InputError(path, "", "not LAZ: the point records are not compressed");
  }
  return laz_source(path, h, vlrs, data, size);
}

}  // namespace laz

std::string read_las_crs(const std::string& path) {
  const detail::MappedFile file(path);
  if (file.size() == 0) throw InputError(path, "", "empty file");
  const LasHeader h = parse_header(path, file.data(), file.size());
  PointReadStats stats;
  VlrRecords vlrs;
  read_vlrs(path, h, file.data(), vlrs, stats.warnings);
  read_evlrs(path, h, file.data(), file.size(), vlrs);
  resolve_crs(path, vlrs, stats);
  return stats.crs_wkt;
}

PointReadStats read_las(const std::string& path, const PointFilter& filter,
                        std::vector<Point3>& out, unsigned threads) {
  const detail::MappedFile file(path);
  if (file.size() == 0) throw InputError(path, "", "empty file");
  const LasHeader h = parse_header(path, file.data(), file.size());
  PointReadStats stats;
  VlrRecords vlrs;
  read_vlrs(path, h, file.data(), vlrs, stats.warnings);  // first: it finds LASzip data
  const bool laz = is_laz(path, h, vlrs, file.size(), stats.warnings);
  if (!laz) check_point_count(path, h, file.size());
  read_evlrs(path, h, file.data(), file.size(), vlrs);
  stats.format = format_label(h);
  if (laz) stats.format.replace(0, 3, vlrs.copc ? "copc" : "laz");
  stats.points_read = h.point_count;
  resolve_crs(path, vlrs, stats);
  if (laz) {
    laz::LazSource src = laz_source(path, h, vlrs, file.data(), file.size());
    src.mapping = &file;
    laz::LazReadFigures figures;
    stats.points_kept = laz::read_points(src, filter, threads, out, stats.warnings, &figures);
    if (figures.by_box) {
      // The header and VLRs, the extended VLRs' headers, the hierarchy pages and the chunks.
      stats.points_read = figures.points_decoded;
      stats.bytes_read =
          h.offset_to_points + vlrs.evlr_bytes + figures.hierarchy_bytes + figures.chunk_bytes;
    }
    return stats;
  }

  const Selection sel(filter);
  const Transform t = transform_of(h);
  const DecodeFn decode_fn = pick_decoder(h.point_format >= 6, sel.any());
  const std::size_t record_length = h.record_length;
  const std::size_t chunk_records = std::max<std::size_t>(1, kChunkBytes / record_length);
  const std::size_t first_byte = h.offset_to_points;
  const auto total = static_cast<std::size_t>(h.point_count);

  // Room for every record, even with a filter: capacity never touched costs address space only,
  // not memory.
  try {
    out.reserve(out.size() + total);
  } catch (const std::bad_alloc&) {
    throw Error(path, "", "out of memory: no room for its " + count_text(total) + " points");
  }
  const bool check = !t.in_range_by_header();
  detail::advise_huge_pages(out);
  file.advise_sequential(first_byte, first_byte + total * record_length);
  std::size_t done = 0;
  std::size_t released = 0;
  while (done < total) {
    const std::size_t n = std::min(chunk_records, total - done);
    const std::size_t begin = first_byte + done * record_length;
    if (check) check_range(path, file.data() + begin, n, record_length, t, done);
    stats.points_kept += decode_fn(file.data() + begin, n, record_length, t, sel, out);
    done += n;
    file.release(released, begin + n * record_length);
    released = begin + n * record_length;
  }
  return stats;
}

}  // namespace tincdt::io
