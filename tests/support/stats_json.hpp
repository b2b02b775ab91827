// A --stats file read as JSON (GDAL's CPLJSONDocument, no other dependency), so that the tests
// ask for a value by its place in the document ("vertices", "timings_s/read") instead of
// searching the text. Header-only, for the tests; link GDAL::GDAL.
#pragma once

#include <cpl_json.h>

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace tincdt::test {

class StatsJson {
 public:
  explicit StatsJson(const std::string& text) : ok_(doc_.LoadMemory(text)) {}

  // False when the text is not JSON.
  bool ok() const { return ok_; }
  // Whether PATH (member names joined by '/') names a value.
  bool has(const std::string& path) const { return at(path).IsValid(); }

  // The whole number at PATH; UINT64_MAX when it is missing, negative or not an integer.
  std::uint64_t count(const std::string& path) const {
    const CPLJSONObject v = at(path);
    const auto type = v.GetType();
    if (type != CPLJSONObject::Type::Integer && type != CPLJSONObject::Type::Long)
      return std::numeric_limits<std::uint64_t>::max();
    const GInt64 n = v.ToLong();
    return n < 0 ? std::numeric_limits<std::uint64_t>::max() : static_cast<std::uint64_t>(n);
  }

  // The number at PATH; nullopt when it is missing or not a number.
  std::optional<double> number(const std::string& path) const { return number_of(at(path)); }

  // The string at PATH; nullopt when it is missing or not a string.
  std::optional<std::string> text(const std::string& path) const {
    const CPLJSONObject v = at(path);
    if (v.GetType() != CPLJSONObject::Type::String) return std::nullopt;
    return v.ToString();
  }

  // The numbers of the array at PATH; nullopt when it is missing or holds anything else.
  std::optional<std::vector<double>> numbers(const std::string& path) const {
    const CPLJSONObject v = at(path);
    if (v.GetType() != CPLJSONObject::Type::Array) return std::nullopt;
    const CPLJSONArray array = doc_.GetRoot().GetArray(path);
    std::vector<double> out;
    for (int i = 0; i < array.Size(); ++i) {
      const std::optional<double> x = number_of(array[i]);
      if (!x) return std::nullopt;
      out.push_back(*x);
    }
    return out;
  }

 private:
  CPLJSONObject at(const std::string& path) const { return doc_.GetRoot().GetObj(path); }

  static std::optional<double> number_of(const CPLJSONObject& v) {
    const auto type = v.GetType();
    if (type != CPLJSONObject::Type::Integer && type != CPLJSONObject::Type::Long &&
        type != CPLJSONObject::Type::Double)
      return std::nullopt;
    return v.ToDouble();
  }

  CPLJSONDocument doc_;
  bool ok_;
};

}  // namespace tincdt::test
