#include "io/points/laz/point14_decoder.hpp"

#include <string>

#include "core/number_text.hpp"
#include "io/points/load_le.hpp"

namespace tincdt::io::laz {
namespace {

template <typename T>
void store(std::uint8_t* p, T v) {
  std::memcpy(p, &v, sizeof v);
}

// The layers every point14 chunk has, in chunk order; RGB, NIR, waveform and extra bytes follow.
enum Layer : unsigned {
  kXy,
  kZ,
  kClassLayer,
  kFlags,
  kIntensity,
  kScanAngle,
  kUserData,
  kPointSource,
  kGpsTime,
  kFixedLayers,
};

Point14 unpack(const std::uint8_t* raw) {
  Point14 p;
  p.x = load_le<std::int32_t>(raw);
  p.y = load_le<std::int32_t>(raw + 4);
  p.z = load_le<std::int32_t>(raw + 8);
  p.intensity = load_le<std::uint16_t>(raw + 12);
  p.return_number = raw[14] & 0x0Fu;
  p.number_of_returns = raw[14] >> 4;
  const unsigned bits = raw[15];
  p.flags = static_cast<std::uint8_t>((bits & 0x0Fu) | ((bits >> 6) & 1u) << 4 | (bits >> 7) << 5);
  p.channel = (bits >> 4) & 3u;
  p.classification = raw[16];
  p.user_data = raw[17];
  p.scan_angle = load_le<std::int16_t>(raw + 18);
  p.point_source = load_le<std::uint16_t>(raw + 20);
  p.gps_time = load_le<std::uint64_t>(raw + 22);
  return p;
}

void pack(const Point14& p, std::uint8_t* out) {
  store(out, p.x);
  store(out + 4, p.y);
  store(out + 8, p.z);
  store(out + 12, p.intensity);
  out[14] = static_cast<std::uint8_t>(p.return_number | p.number_of_returns << 4);
  out[15] = static_cast<std::uint8_t>((p.flags & 0x0Fu) | p.channel << 4 |
                                      ((p.flags >> 4) & 1u) << 6 | ((p.flags >> 5) & 1u) << 7);
  out[16] = p.classification;
  out[17] = p.user_data;
  store(out + 18, p.scan_angle);
  store(out + 20, p.point_source);
  store(out + 22, p.gps_time);
}

std::int32_t wrapping_add(std::int32_t a, std::int32_t b) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(a) + static_cast<std::uint32_t>(b));
}

}  // namespace

// A channel's models of the layers decoded only for whole records.
struct RecordOnlyModels {
  LazyModels<64> flags{64};  // context: the previous flags
  IntegerDecompressor intensity{16, 4};
  std::array<std::uint16_t, 8> last_intensity{};
  IntegerDecompressor scan_angle{16, 2};
  LazyModels<64> user_data{256};  // context: the previous user data / 4
  IntegerDecompressor point_source{16, 1};
  GpsTimeDecoder<true> gps;
};

// What one scanner channel predicts from: its last point and the models of the layers decoded.
struct Point14Decoder::Channel {
  explicit Channel(bool every_field)
      : changed(8, SymbolModel(128)),
        channel_delta(3),
        number_of_returns(16),
        return_number(16),
        return_number_same_time(13),
        dx(32, 2),
        dy(32, 22),
        z(32, 20),
        classification(256) {
    if (every_field) others.emplace();
  }

  bool used = false;
  Point14 last;
  // XY layer: which fields changed, by the previous point's return kind and time change
  std::vector<SymbolModel> changed;
  SymbolModel channel_delta;         // the next channel, 1-3 ahead
  LazyModels<16> number_of_returns;  // context: the previous count
  LazyModels<16> return_number;      // when the GPS time changed; context: previous number
  SymbolModel return_number_same_time;
  IntegerDecompressor dx;
  IntegerDecompressor dy;
  std::array<Median5, 12> x_diffs;  // by return map and time change
  std::array<Median5, 12> y_diffs;
  // Z layer
  IntegerDecompressor z;
  std::array<std::int32_t, 8> last_z{};  // by return level
  // classification layer; context: previous class (5 bits) and whether single
  LazyModels<64> classification;
  std::optional<RecordOnlyModels> others;
};

// The colour item's per-channel state (RGB14, RGBNIR14).
struct Point14Decoder::ColourChannel {
  bool used = false;
  std::uint16_t last[4] = {};  // R, G, B, NIR
  RgbDecoder rgb;
  NirDecoder nir;
};

// The extra bytes item's per-channel state (BYTE14): one model per byte.
struct Point14Decoder::BytesChannel {
  explicit BytesChannel(unsigned count) : last(count), models(count, SymbolModel(256)) {}
  bool used = false;
  std::vector<std::uint8_t> last;
  std::vector<SymbolModel> models;
};

Point14Decoder::Point14Decoder(const PointLayout& layout, unsigned fields)
    : layout_(layout), fields_(fields), v4_(layout.version >= 4) {
  layers_ = kFixedLayers + (layout.rgb ? 1 : 0) + (layout.nir ? 1 : 0) + (layout.waveform ? 1 : 0) +
            layout.extra_bytes;
  layer_.resize(layers_);
  active_.assign(layers_, 0);
}

Point14Decoder::~Point14Decoder() = default;

const Point14& Point14Decoder::point() const {
  return channels_[current_]->last;
}

void Point14Decoder::start_channel(unsigned c, const Point14& from) {
  if (!channels_[c]) channels_[c] = std::make_unique<Channel>(fields_ == kEveryField);
  Channel& ch = *channels_[c];
  ch.used = true;
  for (SymbolModel& m : ch.changed) m.reset();
  ch.channel_delta.reset();
  ch.number_of_returns.new_chunk();
  ch.return_number.new_chunk();
  ch.return_number_same_time.reset();
  ch.dx.reset();
  ch.dy.reset();
  for (Median5& m : ch.x_diffs) m.reset();
  for (Median5& m : ch.y_diffs) m.reset();
  if (active_[kZ]) ch.z.reset();
  ch.last_z.fill(from.z);
  ch.classification.new_chunk();
  if (ch.others) {
    RecordOnlyModels& o = *ch.others;
    o.flags.new_chunk();
    o.intensity.reset();
    o.last_intensity.fill(from.intensity);
    o.scan_angle.reset();
    o.user_data.new_chunk();
    o.point_source.reset();
    o.gps.reset(from.gps_time);
  }
  ch.last = from;
  ch.last.gps_time_changed = false;
}

std::size_t Point14Decoder::begin_chunk(const ChunkInput& in) {
  const std::size_t record = layout_.record_length;
  const std::size_t header = record + 4 + 4 * std::size_t{layers_};
  if (in.size < header) {
    throw in.error(0, "the chunk ends inside its header (" + count_text(in.size) +
                          " bytes, the first point and the layer sizes need " + count_text(header) +
                          ")");
  }
  // The chunk's own count: more points asked of it than it holds would be decoded from the
  // bytes after its last one.
  const std::uint64_t held = load_le<std::uint32_t>(in.data + record);
  if (held < in.points) {
    throw in.error(held, "the chunk holds " + count_text(held) + " points, not the " +
                             count_text(in.points) + " the header and chunk table give it");
  }
  const bool every = fields_ == kEveryField;
  const std::size_t bytes_layer =
      kFixedLayers + (layout_.rgb ? 1 : 0) + (layout_.nir ? 1 : 0) + (layout_.waveform ? 1 : 0);
  std::size_t offset = header;
  for (unsigned i = 0; i < layers_; ++i) {
    const std::size_t bytes = load_le<std::uint32_t>(in.data + record + 4 + 4 * i);
    if (bytes > in.size - offset) {
      throw in.error(0, "its layers take more than the chunk's " + count_text(in.size) + " bytes");
    }
    bool wanted;
    if (i == kZ) {
      wanted = (fields_ & kCoordinates) != 0;
    } else if (i == kClassLayer) {
      wanted = (fields_ & kClassification) != 0;
    } else if (layout_.waveform && i == bytes_layer - 1) {
      wanted = false;  // waveform packets are never decoded
    } else {
      wanted = every;
    }
    if (i == kXy) {
      xy_.init(in.data + offset, bytes);
    } else if (wanted && bytes > 0) {
      layer_[i].init(in.data + offset, bytes);
    }
    active_[i] = i == kXy || (wanted && bytes > 0);
    offset += bytes;
  }

  const Point14 first = unpack(in.data);
  for (auto& ch : channels_) {
    if (ch) ch->used = false;
  }
  current_ = first.channel;
  start_channel(current_, first);
  if (every && layout_.rgb) {
    for (auto& ch : colour_) {
      if (ch) ch->used = false;
    }
    colour_current_ = colour_last_ = current_;
    if (!colour_[current_]) colour_[current_] = std::make_unique<ColourChannel>();
    ColourChannel& c = *colour_[current_];
    c.used = true;
    c.rgb.reset();
    c.nir.reset();
    std::memcpy(c.last, in.data + 30, layout_.nir ? 8 : 6);
  }
  if (every && layout_.extra_bytes > 0) {
    for (auto& ch : bytes_) {
      if (ch) ch->used = false;
    }
    bytes_current_ = bytes_last_ = current_;
    if (!bytes_[current_]) bytes_[current_] = std::make_unique<BytesChannel>(layout_.extra_bytes);
    BytesChannel& b = *bytes_[current_];
    b.used = true;
    for (SymbolModel& m : b.models) m.reset();
    std::memcpy(b.last.data(), in.data + record - layout_.extra_bytes, layout_.extra_bytes);
  }
  return offset;
}

namespace {

// The layers only the whole record needs (flags, intensity, scan angle, user data, point source,
// GPS time) of point LAST, from its channel's models O. KIND, TIME_CHANGED, ANGLE_CHANGED and
// SOURCE_CHANGED come from the XY layer.
void decode_record_only(RecordOnlyModels& o, Point14& last, std::vector<ArithmeticDecoder>& layer,
                        const std::vector<bool>& active, unsigned kind, unsigned time_changed,
                        bool angle_changed, bool source_changed) {
  if (active[kFlags]) {
    last.flags = static_cast<std::uint8_t>(layer[kFlags].decode_symbol(o.flags[last.flags]));
  }
  if (active[kIntensity]) {
    const unsigned i = (kind << 1) | time_changed;
    last.intensity = static_cast<std::uint16_t>(
        o.intensity.decompress(layer[kIntensity], o.last_intensity[i], kind));
    o.last_intensity[i] = last.intensity;
  }
  if (active[kScanAngle] && angle_changed) {
    last.scan_angle = static_cast<std::int16_t>(
        o.scan_angle.decompress(layer[kScanAngle], last.scan_angle, time_changed));
  }
  if (active[kUserData]) {
    last.user_data =
        static_cast<std::uint8_t>(layer[kUserData].decode_symbol(o.user_data[last.user_data / 4u]));
  }
  if (active[kPointSource] && source_changed) {
    last.point_source = static_cast<std::uint16_t>(
        o.point_source.decompress(layer[kPointSource], last.point_source));
  }
  if (active[kGpsTime] && time_changed) {
    o.gps.decode(layer[kGpsTime]);
    last.gps_time = o.gps.time();
  }
}

}  // namespace

void Point14Decoder::decode_point() {
  Channel* ch = channels_[current_].get();
  Point14* last = &ch->last;

  // XY layer: what changed, in the context of the previous point's return kind and time change.
  const unsigned previous = (last->return_number == 1 ? 1u : 0u) +
                            (last->return_number >= last->number_of_returns ? 2u : 0u) +
                            (last->gps_time_changed ? 4u : 0u);
  const std::uint32_t changed = xy_.decode_symbol(ch->changed[previous]);
  if (changed & 64) {  // another scanner channel: predict from its last point from now on
    const unsigned next = (current_ + xy_.decode_symbol(ch->channel_delta) + 1) & 3u;
    if (!channels_[next] || !channels_[next]->used) start_channel(next, *last);
    current_ = next;
    ch = channels_[current_].get();
    last = &ch->last;
    last->channel = static_cast<std::uint8_t>(next);
  }
  const bool source_changed = (changed & 32) != 0;
  const unsigned time_changed = (changed >> 4) & 1u;
  const bool angle_changed = (changed & 8) != 0;

  unsigned n = last->number_of_returns;
  if (changed & 4) n = xy_.decode_symbol(ch->number_of_returns[n]);
  const unsigned last_r = last->return_number;
  unsigned r;
  switch (changed & 3) {
    case 0:
      r = last_r;
      break;
    case 1:
      r = (last_r + 1) & 15u;
      break;
    case 2:
      r = (last_r + 15) & 15u;
      break;
    default:
      r = time_changed ? xy_.decode_symbol(ch->return_number[last_r])
                       : (last_r + xy_.decode_symbol(ch->return_number_same_time) + 2) & 15u;
      break;
  }
  last->number_of_returns = static_cast<std::uint8_t>(n);
  last->return_number = static_cast<std::uint8_t>(r);

  const unsigned m = kReturnMap16[n][r];
  const unsigned kind = (r == 1 ? 1u : 0u) + (r >= n ? 2u : 0u);  // 3 single, 1 first, 2 last
  const unsigned single = n == 1 ? 1u : 0u;
  const unsigned slot = (m << 1) | time_changed;
  std::int32_t diff = ch->dx.decompress(xy_, ch->x_diffs[slot].get(), single);
  last->x = wrapping_add(last->x, diff);
  ch->x_diffs[slot].add(diff);
  unsigned k = ch->dx.k();
  diff = ch->dy.decompress(xy_, ch->y_diffs[slot].get(), single + (k < 20 ? (k & ~1u) : 20));
  last->y = wrapping_add(last->y, diff);
  ch->y_diffs[slot].add(diff);

  if (active_[kZ]) {
    k = (ch->dx.k() + ch->dy.k()) / 2;
    const unsigned level = return_level(n, r);
    last->z = ch->z.decompress(layer_[kZ], ch->last_z[level], single + (k < 18 ? (k & ~1u) : 18));
    ch->last_z[level] = last->z;
  }
  if (active_[kClassLayer]) {
    const unsigned context = ((last->classification & 0x1Fu) << 1) + (kind == 3 ? 1u : 0u);
    last->classification =
        static_cast<std::uint8_t>(layer_[kClassLayer].decode_symbol(ch->classification[context]));
  }
  if (ch->others) {
    decode_record_only(*ch->others, *last, layer_, active_, kind, time_changed, angle_changed,
                       source_changed);
  }
  // Not part of the record: a context for the channel's next point.
  last->gps_time_changed = time_changed != 0;

  if (fields_ == kEveryField) {
    if (layout_.rgb) decode_colour();
    if (layout_.extra_bytes > 0) decode_bytes();
  }
}

// Item versions 3 and 4 differ in one thing: on a switch to a channel already seen in this chunk,
// version 3 codes that point's colour and extra bytes against the previous channel's last values
// (and stores the result there); version 4 against the new channel's own.
void Point14Decoder::decode_colour() {
  unsigned from = colour_current_;
  if (colour_current_ != current_) {
    colour_current_ = current_;
    if (!colour_[current_] || !colour_[current_]->used) {
      if (!colour_[current_]) colour_[current_] = std::make_unique<ColourChannel>();
      ColourChannel& c = *colour_[current_];
      c.used = true;
      c.rgb.reset();
      c.nir.reset();
      std::memcpy(c.last, colour_[from]->last, sizeof c.last);
      from = current_;
    } else if (v4_) {
      from = current_;
    }
  }
  colour_last_ = from;
  ColourChannel& models = *colour_[colour_current_];
  std::uint16_t* last = colour_[from]->last;
  const unsigned rgb_layer = kFixedLayers;
  if (active_[rgb_layer]) {
    std::uint16_t rgb[3];
    models.rgb.decode(layer_[rgb_layer], last, rgb);
    std::memcpy(last, rgb, sizeof rgb);
  }
  if (layout_.nir && active_[rgb_layer + 1]) {
    last[3] = models.nir.decode(layer_[rgb_layer + 1], last[3]);
  }
}

void Point14Decoder::decode_bytes() {
  unsigned from = bytes_current_;
  if (bytes_current_ != current_) {
    bytes_current_ = current_;
    if (!bytes_[current_] || !bytes_[current_]->used) {
      if (!bytes_[current_]) bytes_[current_] = std::make_unique<BytesChannel>(layout_.extra_bytes);
      BytesChannel& b = *bytes_[current_];
      b.used = true;
      for (SymbolModel& m : b.models) m.reset();
      b.last = bytes_[from]->last;
      from = current_;
    } else if (v4_) {
      from = current_;
    }
  }
  bytes_last_ = from;
  BytesChannel& models = *bytes_[bytes_current_];
  std::vector<std::uint8_t>& last = bytes_[from]->last;
  const std::size_t first_layer = layers_ - layout_.extra_bytes;
  for (std::size_t i = 0; i < last.size(); ++i) {
    if (!active_[first_layer + i]) continue;
    last[i] = static_cast<std::uint8_t>(fold_byte(static_cast<std::int32_t>(
        last[i] + layer_[first_layer + i].decode_symbol(models.models[i]))));
  }
}

void Point14Decoder::fail(const ChunkInput& in, std::uint64_t point) const {
  throw in.error(point, "the compressed data ends early (chunk of " + count_text(in.size) +
                            " bytes) or is corrupt");
}

void Point14Decoder::end_chunk(const ChunkInput& in) const {
  static const char* const kNames[kFixedLayers] = {
      "XY",         "Z",         "classification", "flags",   "intensity",
      "scan angle", "user data", "point source",   "GPS time"};
  for (unsigned i = 0; i < layers_; ++i) {
    const bool failed = i == kXy ? in.points > 1 && xy_.failed() : active_[i] && layer_[i].failed();
    if (!failed) continue;
    const std::string name = i < kFixedLayers ? kNames[i] : "layer " + count_text(i);
    throw in.error(in.points - 1, "the " + name + " layer's data ends early or is corrupt");
  }
}

void Point14Decoder::write_record(std::uint8_t* out) const {
  pack(point(), out);
  std::size_t at = 30;
  if (layout_.rgb) {
    const std::uint16_t* colour = colour_[colour_last_]->last;
    std::memcpy(out + at, colour, layout_.nir ? 8 : 6);
    at += layout_.nir ? 8 : 6;
  }
  if (layout_.waveform) at += 29;
  if (layout_.extra_bytes > 0) {
    std::memcpy(out + at, bytes_[bytes_last_]->last.data(), layout_.extra_bytes);
  }
}

}  // namespace tincdt::io::laz
