// JSON (RFC 8259) for the documents tincdt writes whole and reads back: the --stats report, its
// quality block and tile plans. A streaming writer, and a reader into a small tree. (The mesh,
// constraint and diagnostics writers stream their GeoJSON a feature at a time with json_string.)
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "core/error.hpp"
#include "core/json_text.hpp"

namespace tincdt::json {

// How doubles are written: each reads back to the same double, and one that is not finite is
// written null. Each kind of document has its own form, so that its bytes stay the same.
enum class Numbers {
  plain,     // shortest text, plain decimals ("500000", "0.25") for 1e-4 <= |v| < 1e15: --stats
  shortest,  // shortest text, with an exponent wherever that is shorter ("5e+05"): quality block
  digits17,  // 17 significant digits, whole numbers below 2^53 without a point: tile plans
};

// V as STYLE writes it.
std::string number(double v, Numbers style);

// Where a container puts its items. A container inside a one-line container stays on its line.
enum class Layout {
  lines,    // one item a line, indented two spaces a level: {\n  "a": 1,\n  "b": [\n    2\n  ]\n}
  spaced,   // one line, a space after ',' and ':': {"a": 1, "b": [2, 3]}
  compact,  // one line, no spaces: {"a":1,"b":[2,3]}
};

// Writes one JSON value, a piece at a time: in an object, key() before each member's value.
class Writer {
 public:
  explicit Writer(Numbers numbers = Numbers::plain, NonUtf8 non_utf8 = NonUtf8::replace)
      : numbers_(numbers), non_utf8_(non_utf8) {}

  Writer& begin_object(Layout layout = Layout::lines) { return open('{', true, layout); }
  Writer& end_object() { return close('}', true); }
  Writer& begin_array(Layout layout = Layout::lines) { return open('[', false, layout); }
  Writer& end_array() { return close(']', false); }
  // The name of the next member of the object open.
  Writer& key(std::string_view name);

  Writer& value(double v);
  Writer& value(bool v) { return raw(v ? "true" : "false"); }
  template <std::integral T>
  Writer& value(T v) {
    if constexpr (std::is_signed_v<T>)
      return integer(static_cast<std::int64_t>(v));
    else
      return integer(static_cast<std::uint64_t>(v));
  }
  Writer& value(std::string_view text);
  Writer& value(const std::string& text) { return value(std::string_view(text)); }
  Writer& value(const char* text) { return value(std::string_view(text)); }
  Writer& null() { return raw("null"); }
  // A value that is JSON text already (one line).
  Writer& raw(std::string_view json);

  // key(NAME) and its value.
  template <class T>
  Writer& field(std::string_view name, const T& v) {
    return key(name).value(v);
  }
  // An array of the values of RANGE.
  template <class Range>
  Writer& array(const Range& range, Layout layout = Layout::lines) {
    begin_array(layout);
    for (const auto& v : range) value(v);
    return end_array();
  }

  // The text so far: the whole value once every container is closed.
  const std::string& str() const { return out_; }

 private:
  struct Open {
    Layout layout;
    bool object;
    bool empty = true;
  };

  Writer& open(char bracket, bool object, Layout layout);
  Writer& close(char bracket, bool object);
  Writer& integer(std::int64_t v);
  Writer& integer(std::uint64_t v);
  void begin_value();
  void begin_item();

  std::string out_;
  std::vector<Open> open_;
  bool after_key_ = false;
  Numbers numbers_;
  NonUtf8 non_utf8_;
};

// A text that is not JSON: where (line and column, from 1, and byte offset) and what.
class ParseError : public InputError {
 public:
  ParseError(std::string file, std::size_t offset, std::size_t line, std::size_t column,
             const std::string& what);

  std::size_t offset() const { return offset_; }
  std::size_t line() const { return line_; }
  std::size_t column() const { return column_; }  // in bytes

 private:
  std::size_t offset_, line_, column_;
};

// Arrays and objects nested deeper than this are refused (the reader recurses).
constexpr int kMaxDepth = 64;

// One JSON value and all it holds. Strings are kept as bytes: a file name that is not UTF-8,
// written with NonUtf8::keep, reads back the same.
class Value {
 public:
  enum class Kind { null, boolean, number, string, array, object };

  Kind kind() const { return kind_; }
  bool is(Kind k) const { return kind_ == k; }
  bool boolean() const { return boolean_; }
  double number() const { return number_; }
  const std::string& string() const { return string_; }
  const std::vector<Value>& items() const { return items_; }      // an array's, an object's values
  const std::vector<std::string>& keys() const { return keys_; }  // an object's, as items()
  // The member KEY of an object, or null when this is not an object or has no such member.
  const Value* find(std::string_view key) const;

 private:
  friend class Parser;
  Kind kind_ = Kind::null;
  bool boolean_ = false;
  double number_ = 0;
  std::string string_;
  std::vector<Value> items_;
  std::vector<std::string> keys_;
};

// TEXT whole as one value. Numbers must be finite doubles; a member name may not repeat. Throws
// ParseError at the first problem, naming FILE.
Value parse(std::string_view text, const std::string& file = {});

}  // namespace tincdt::json
