#include "io/points/laz/point10_decoder.hpp"

namespace tincdt::io::laz {

Point10Item::Point10Item()
    : changed_(64),
      returns_(256),
      intensity_(16, 4),
      classification_(256),
      scan_angle_{SymbolModel(256), SymbolModel(256)},
      user_data_(256),
      point_source_(16, 1),
      dx_(32, 2),
      dy_(32, 22),
      z_(32, 20) {}

void Point10Item::reset(const std::uint8_t* raw) {
  std::memcpy(&last_, raw, sizeof last_);
  for (std::uint16_t& v : last_intensity_) v = 0;
  for (Median5& m : x_diffs_) m.reset();
  for (Median5& m : y_diffs_) m.reset();
  for (std::int32_t& z : last_z_) z = 0;
  changed_.reset();
  returns_.new_chunk();
  intensity_.reset();
  classification_.new_chunk();
  scan_angle_[0].reset();
  scan_angle_[1].reset();
  user_data_.new_chunk();
  point_source_.reset();
  dx_.reset();
  dy_.reset();
  z_.reset();
}

Point10Decoder::Point10Decoder(const PointLayout& layout, unsigned /*fields*/) : layout_(layout) {
  std::size_t offset = sizeof(Point10);
  if (layout.gps_time) {
    gps_.emplace();
    gps_offset_ = offset;
    offset += 8;
  }
  if (layout.rgb) {
    rgb_.emplace();
    rgb_offset_ = offset;
    offset += 6;
  }
  if (layout.extra_bytes > 0) {
    extra_.emplace(layout.extra_bytes);
    extra_offset_ = offset;
  }
}

void Point10Decoder::write_record(std::uint8_t* out) const {
  std::memcpy(out, &point_.point(), sizeof(Point10));
  if (gps_) {
    const std::uint64_t t = gps_->time();
    std::memcpy(out + gps_offset_, &t, 8);
  }
  if (rgb_) std::memcpy(out + rgb_offset_, rgb_last_, 6);
  if (extra_) std::memcpy(out + extra_offset_, extra_->bytes().data(), extra_->bytes().size());
}

}  // namespace tincdt::io::laz
