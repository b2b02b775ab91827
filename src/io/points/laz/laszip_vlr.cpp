#include "io/points/laz/laszip_vlr.hpp"

#include <array>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/points/load_le.hpp"

namespace tincdt::io::laz {
namespace {

constexpr std::size_t kFixedPart = 34;  // up to and including the item count
constexpr std::size_t kItemSize = 6;

enum ItemType : std::uint16_t {
  kByte = 0,
  kPoint10 = 6,
  kGpsTime11 = 7,
  kRgb12 = 8,
  kWavePacket13 = 9,
  kPoint14 = 10,
  kRgb14 = 11,
  kRgbNir14 = 12,
  kWavePacket14 = 13,
  kByte14 = 14,
};

std::string item_name(std::uint16_t type) {
  switch (type) {
    case kByte:
      return "BYTE";
    case kPoint10:
      return "POINT10";
    case kGpsTime11:
      return "GPSTIME11";
    case kRgb12:
      return "RGB12";
    case kWavePacket13:
      return "WAVEPACKET13";
    case kPoint14:
      return "POINT14";
    case kRgb14:
      return "RGB14";
    case kRgbNir14:
      return "RGBNIR14";
    case kWavePacket14:
      return "WAVEPACKET14";
    case kByte14:
      return "BYTE14";
    default:
      return "item type " + std::to_string(type);
  }
}

// The items LASzip writes for each point format, before any extra bytes, with their sizes.
struct FormatItems {
  std::array<std::uint16_t, 4> types;
  unsigned count;
};
constexpr std::array<FormatItems, 11> kFormatItems = {{
    {{kPoint10}, 1},
    {{kPoint10, kGpsTime11}, 2},
    {{kPoint10, kRgb12}, 2},
    {{kPoint10, kGpsTime11, kRgb12}, 3},
    {{kPoint10, kGpsTime11, kWavePacket13}, 3},
    {{kPoint10, kGpsTime11, kRgb12, kWavePacket13}, 4},
    {{kPoint14}, 1},
    {{kPoint14, kRgb14}, 2},
    {{kPoint14, kRgbNir14}, 2},
    {{kPoint14, kWavePacket14}, 2},
    {{kPoint14, kRgbNir14, kWavePacket14}, 3},
}};

std::uint16_t item_size(std::uint16_t type) {
  switch (type) {
    case kPoint10:
      return 20;
    case kGpsTime11:
      return 8;
    case kRgb12:
    case kRgb14:
      return 6;
    case kRgbNir14:
      return 8;
    case kWavePacket13:
    case kWavePacket14:
      return 29;
    case kPoint14:
      return 30;
    default:
      return 0;
  }
}

std::string list_items(const std::vector<LaszipItem>& items) {
  std::string s;
  for (const LaszipItem& it : items) {
    if (!s.empty()) s += ", ";
    s += item_name(it.type) + " (" + count_text(it.size) + " bytes, v" +
         std::to_string(it.version) + ")";
  }
  return s.empty() ? "no items" : s;
}

}  // namespace

LaszipVlr parse_laszip_vlr(const std::string& path, const std::uint8_t* payload, std::size_t size) {
  const std::string where = "LASzip VLR";
  if (size < kFixedPart) {
    throw InputError(path, where,
                     "truncated: " + count_text(size) + " bytes, at least " +
                         count_text(kFixedPart) + " needed");
  }
  LaszipVlr vlr;
  vlr.compressor = load_le<std::uint16_t>(payload);
  vlr.coder = load_le<std::uint16_t>(payload + 2);
  vlr.chunk_size = load_le<std::uint32_t>(payload + 12);
  const std::size_t count = load_le<std::uint16_t>(payload + 32);
  if (size < kFixedPart + count * kItemSize) {
    throw InputError(path, where,
                     "lists " + count_text(count) + " items but has room for only " +
                         count_text((size - kFixedPart) / kItemSize));
  }
  vlr.items.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    const std::uint8_t* p = payload + kFixedPart + i * kItemSize;
    vlr.items[i] = {load_le<std::uint16_t>(p), load_le<std::uint16_t>(p + 2),
                    load_le<std::uint16_t>(p + 4)};
  }
  return vlr;
}

PointLayout check_layout(const std::string& path, const LaszipVlr& vlr, unsigned point_format,
                         std::size_t record_length) {
  const std::string where = "LASzip VLR";
  if (vlr.coder != 0) {
    throw InputError(
        path, where,
        "unknown coder " + std::to_string(vlr.coder) + " (only 0, arithmetic coding, exists)");
  }
  if (vlr.compressor < 1 || vlr.compressor > 3) {
    throw InputError(path, where,
                     "unknown compressor " + std::to_string(vlr.compressor) +
                         " (1 pointwise, 2 pointwise chunked, 3 layered chunked)");
  }
  if (point_format >= kFormatItems.size()) {
    throw InputError(path, "header", "unsupported point format " + std::to_string(point_format));
  }
  PointLayout layout;
  layout.layered = point_format >= 6;
  layout.record_length = record_length;
  const FormatItems& expected = kFormatItems[point_format];
  const auto mismatch = [&](const std::string& why) {
    return InputError(path, where,
                      "its items (" + list_items(vlr.items) + ") do not describe point format " +
                          std::to_string(point_format) + " records of " +
                          count_text(record_length) + " bytes: " + why);
  };
  std::size_t total = 0;
  for (std::size_t i = 0; i < vlr.items.size(); ++i) {
    const LaszipItem& item = vlr.items[i];
    if (i < expected.count) {
      if (item.type != expected.types[i]) {
        throw mismatch("item " + count_text(i + 1) + " should be " + item_name(expected.types[i]));
      }
      if (item.size != item_size(item.type)) {
        throw mismatch(item_name(item.type) + " has " + count_text(item_size(item.type)) +
                       " bytes, not " + count_text(item.size));
      }
    } else if (i == expected.count && item.type == (layout.layered ? kByte14 : kByte) &&
               item.size > 0) {
      layout.extra_bytes = item.size;
    } else {
      throw mismatch(item_name(item.type) + " is not expected in this position");
    }
    total += item.size;
  }
  if (vlr.items.size() < expected.count) throw mismatch("items are missing");
  if (total != record_length) {
    throw mismatch("they add up to " + count_text(total) + " bytes");
  }
  // One coder version for the whole record: LASzip writes point10 items as v2 (v1 before 2012)
  // and point14 items as v3 (v4 since LASzip 3.4, the same format with two context fixes).
  layout.version = vlr.items.front().version;
  for (const LaszipItem& item : vlr.items) {
    const bool known =
        layout.layered ? (item.version == 3 || item.version == 4) : item.version == 2;
    if (!known || item.version != layout.version) {
      throw InputError(path, where,
                       item_name(item.type) + " version " + std::to_string(item.version) +
                           " is not supported (LAZ point formats 0-5 need version 2, the " +
                           "default since LASzip 2.0; formats 6-10 version 3 or 4)");
    }
  }
  for (unsigned i = 1; i < expected.count; ++i) {
    switch (expected.types[i]) {
      case kGpsTime11:
        layout.gps_time = true;
        break;
      case kRgb12:
      case kRgb14:
        layout.rgb = true;
        break;
      case kRgbNir14:
        layout.rgb = layout.nir = true;
        break;
      default:
        layout.waveform = true;
        break;
    }
  }
  if (layout.layered != (vlr.compressor == 3)) {
    throw InputError(path, where,
                     "compressor " + std::to_string(vlr.compressor) + " cannot hold point format " +
                         std::to_string(point_format) +
                         (layout.layered ? " (formats 6-10 need the layered compressor 3)"
                                         : " (formats 0-5 need compressor 1 or 2)"));
  }
  layout.chunked = vlr.compressor != 1;
  // LASzip reads a chunk size of 0 as "no fixed size", like the explicit marker.
  layout.variable_chunks = vlr.chunk_size == kVariableChunks || vlr.chunk_size == 0;
  layout.chunk_size = layout.variable_chunks ? 0 : vlr.chunk_size;
  return layout;
}

}  // namespace tincdt::io::laz
