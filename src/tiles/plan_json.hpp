// Internal to the pipeline: the small JSON reader and writer helpers the tile plan needs
// (RFC 8259: objects, arrays, strings, numbers, true, false, null). Numbers are read with
// std::from_chars and written with 17 significant digits, so every double survives a round trip
// bit for bit: tile boxes and bounds read back are the ones written.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace tincdt::tiles::detail {

class JsonValue {
 public:
  enum class Kind { null, boolean, number, string, array, object };

  // Parses TEXT whole; throws JsonError with the byte offset of the first problem.
  static JsonValue parse(std::string_view text);

  Kind kind() const { return kind_; }
  bool is(Kind k) const { return kind_ == k; }
  bool boolean() const { return boolean_; }
  double number() const { return number_; }
  const std::string& string() const { return string_; }
  const std::vector<JsonValue>& items() const { return items_; }  // an array's
  // The member KEY of an object, or null when this is not an object or has no such member.
  const JsonValue* find(std::string_view key) const;

 private:
  friend class JsonParser;
  Kind kind_ = Kind::null;
  bool boolean_ = false;
  double number_ = 0;
  std::string string_;
  std::vector<JsonValue> items_;
  std::vector<std::string> keys_;  // an object's member names; items_ holds their values
};

// A JSON syntax error at byte `offset` of the text.
struct JsonError {
  std::size_t offset;
  std::string what;
};

// TEXT as a JSON string literal, quotes included.
std::string json_string(std::string_view text);
// V with 17 significant digits (integers without an exponent up to 2^53); V must be finite.
std::string json_number(double v);

}  // namespace tincdt::tiles::detail
