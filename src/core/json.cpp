#include "core/json.hpp"

#include <cassert>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <unordered_set>
#include <utility>

#include "core/number_text.hpp"

namespace tincdt::json {
namespace {

void append_number(std::string& out, double v, Numbers style) {
  if (!std::isfinite(v)) {
    out += "null";
    return;
  }
  char buf[64];
  char* end = buf;
  switch (style) {
    case Numbers::plain: {
      const double a = std::fabs(v);
      const bool fixed = a == 0 || (a >= 1e-4 && a < 1e15);
      end = std::to_chars(buf, buf + sizeof buf, v,
                          fixed ? std::chars_format::fixed : std::chars_format::general)
                .ptr;
      break;
    }
    case Numbers::shortest:
      end = std::to_chars(buf, buf + sizeof buf, v).ptr;
      break;
    case Numbers::digits17: {
      const bool whole = v == std::floor(v) && std::fabs(v) < 0x1p53;
      end = buf + std::snprintf(buf, sizeof buf, whole ? "%.0f" : "%.17g", v);
      break;
    }
  }
  out.append(buf, end);
}

}  // namespace

std::string number(double v, Numbers style) {
  std::string out;
  append_number(out, v, style);
  return out;
}

// ---- writing ----------------------------------------------------------------------------------

Writer& Writer::key(std::string_view name) {
  assert(!open_.empty() && open_.back().object && !after_key_);
  begin_item();
  out_ += json_string(name, non_utf8_);
  out_ += open_.back().layout == Layout::compact ? ":" : ": ";
  after_key_ = true;
  return *this;
}

Writer& Writer::value(double v) {
  begin_value();
  append_number(out_, v, numbers_);
  return *this;
}

Writer& Writer::integer(std::int64_t v) {
  begin_value();
  char buf[24];
  out_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
  return *this;
}

Writer& Writer::integer(std::uint64_t v) {
  begin_value();
  char buf[24];
  out_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
  return *this;
}

Writer& Writer::value(std::string_view text) {
  begin_value();
  out_ += json_string(text, non_utf8_);
  return *this;
}

Writer& Writer::raw(std::string_view json) {
  begin_value();
  out_ += json;
  return *this;
}

Writer& Writer::open(char bracket, bool object, Layout layout) {
  begin_value();
  // Inside a one-line container, everything is on its line.
  if (!open_.empty() && open_.back().layout != Layout::lines) layout = open_.back().layout;
  out_ += bracket;
  open_.push_back({layout, object});
  return *this;
}

Writer& Writer::close(char bracket, bool object) {
  assert(!open_.empty() && open_.back().object == object && !after_key_);
  (void)object;
  const Open closed = open_.back();
  open_.pop_back();
  if (closed.layout == Layout::lines && !closed.empty) {
    out_ += '\n';
    out_.append(2 * open_.size(), ' ');
  }
  out_ += bracket;
  return *this;
}

// A value: a member's after its key, an array's item, or the document.
void Writer::begin_value() {
  if (after_key_) {
    after_key_ = false;
    return;
  }
  assert(open_.empty() ? out_.empty() : !open_.back().object);
  begin_item();
}

// The separator before an item (a member or an array's value) of the container open.
void Writer::begin_item() {
  if (open_.empty()) return;
  Open& o = open_.back();
  if (!o.empty) out_ += ',';
  if (o.layout == Layout::lines) {
    out_ += '\n';
    out_.append(2 * open_.size(), ' ');
  } else if (!o.empty && o.layout == Layout::spaced) {
    out_ += ' ';
  }
  o.empty = false;
}

// ---- reading ----------------------------------------------------------------------------------

namespace {

std::string line_and_column(std::size_t line, std::size_t column) {
  return "line " + count_text(line) + ", column " + count_text(column);
}

}  // namespace

ParseError::ParseError(std::string file, std::size_t offset, std::size_t line, std::size_t column,
                       const std::string& what)
    : InputError(std::move(file), line_and_column(line, column), "not JSON: " + what),
      offset_(offset),
      line_(line),
      column_(column) {}

const Value* Value::find(std::string_view key) const {
  if (kind_ != Kind::object) return nullptr;
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i] == key) return &items_[i];
  return nullptr;
}

class Parser {
 public:
  Parser(std::string_view text, const std::string& file) : s_(text), file_(file) {}

  Value document() {
    Value v = value(0);
    skip_blanks();
    if (pos_ != s_.size()) fail("text after the JSON value");
    return v;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    std::size_t line = 1, line_start = 0;
    for (std::size_t i = 0; i < pos_ && i < s_.size(); ++i)
      if (s_[i] == '\n') {
        ++line;
        line_start = i + 1;
      }
    throw ParseError(file_, pos_, line, pos_ - line_start + 1, what);
  }

  void skip_blanks() {
    while (pos_ < s_.size() &&
           (s_[pos_] == ' ' || s_[pos_] == '\t' || s_[pos_] == '\n' || s_[pos_] == '\r'))
      ++pos_;
  }

  bool take(char c) {
    skip_blanks();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }

  void expect(char c) {
    if (!take(c)) fail(std::string("expected '") + c + "'");
  }

  bool take_word(std::string_view word) {
    if (s_.substr(pos_, word.size()) != word) return false;
    pos_ += word.size();
    return true;
  }

  Value value(int depth) {
    if (depth > kMaxDepth) fail("nested too deeply");
    skip_blanks();
    if (pos_ >= s_.size()) fail("unexpected end of text");
    Value v;
    const char c = s_[pos_];
    if (c == '{') {
      object(v, depth);
    } else if (c == '[') {
      ++pos_;
      v.kind_ = Value::Kind::array;
      if (take(']')) return v;
      do v.items_.push_back(value(depth + 1));
      while (take(','));
      expect(']');
    } else if (c == '"') {
      v.kind_ = Value::Kind::string;
      v.string_ = string_literal();
    } else if (take_word("true")) {
      v.kind_ = Value::Kind::boolean;
      v.boolean_ = true;
    } else if (take_word("false")) {
      v.kind_ = Value::Kind::boolean;
    } else if (!take_word("null")) {
      v.kind_ = Value::Kind::number;
      v.number_ = number();
    }
    return v;
  }

  // Member names are checked for repeats by a scan while the object is small, then by a set.
  void object(Value& v, int depth) {
    static constexpr std::size_t kScanned = 16;
    ++pos_;
    v.kind_ = Value::Kind::object;
    if (take('}')) return;
    std::unordered_set<std::string> names;
    do {
      skip_blanks();
      if (pos_ >= s_.size() || s_[pos_] != '"') fail("expected a member name");
      const std::size_t at = pos_;
      std::string key = string_literal();
      expect(':');
      Value member = value(depth + 1);
      if (v.keys_.size() == kScanned)
        for (const std::string& k : v.keys_) names.insert(k);
      const bool repeated =
          v.keys_.size() < kScanned ? v.find(key) != nullptr : names.count(key) != 0;
      if (repeated) {
        pos_ = at;
        fail("a member name repeated");
      }
      v.keys_.push_back(std::move(key));
      v.items_.push_back(std::move(member));
      if (v.keys_.size() > kScanned) names.insert(v.keys_.back());
    } while (take(','));
    expect('}');
  }

  double number() {
    // RFC 8259 grammar: -? (0 | [1-9][0-9]*) (. [0-9]+)? ([eE] [+-]? [0-9]+)?
    const std::size_t start = pos_;
    auto digits = [&] {
      const std::size_t from = pos_;
      while (pos_ < s_.size() && s_[pos_] >= '0' && s_[pos_] <= '9') ++pos_;
      return pos_ - from;
    };
    if (pos_ < s_.size() && s_[pos_] == '-') ++pos_;
    const std::size_t int_start = pos_;
    const std::size_t n = digits();
    if (n == 0 || (n > 1 && s_[int_start] == '0')) {
      pos_ = start;
      fail("not a JSON value");
    }
    if (pos_ < s_.size() && s_[pos_] == '.') {
      ++pos_;
      if (digits() == 0) fail("a number with no digits after '.'");
    }
    if (pos_ < s_.size() && (s_[pos_] == 'e' || s_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-')) ++pos_;
      if (digits() == 0) fail("a number with no exponent digits");
    }
    double v = 0;
    const auto [end, ec] = std::from_chars(s_.data() + start, s_.data() + pos_, v);
    if (ec != std::errc() || end != s_.data() + pos_ || !std::isfinite(v)) {
      pos_ = start;
      fail("a number out of range");
    }
    return v;
  }

  unsigned hex4() {
    unsigned v = 0;
    for (int i = 0; i < 4; ++i, ++pos_) {
      const char c = pos_ < s_.size() ? s_[pos_] : '\0';
      v <<= 4;
      if (c >= '0' && c <= '9')
        v |= static_cast<unsigned>(c - '0');
      else if (c >= 'a' && c <= 'f')
        v |= static_cast<unsigned>(c - 'a' + 10);
      else if (c >= 'A' && c <= 'F')
        v |= static_cast<unsigned>(c - 'A' + 10);
      else
        fail("a \\u escape needs four hex digits");
    }
    return v;
  }

  static void append_utf8(std::string& out, unsigned cp) {
    if (cp < 0x80) {
      out += static_cast<char>(cp);
    } else if (cp < 0x800) {
      out += static_cast<char>(0xC0 | (cp >> 6));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else if (cp < 0x10000) {
      out += static_cast<char>(0xE0 | (cp >> 12));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (cp >> 18));
      out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (cp & 0x3F));
    }
  }

  // The code point of a \u escape, the 'u' read; a surrogate pair counts as one.
  unsigned unicode_escape() {
    const std::size_t at = pos_ - 2;
    unsigned cp = hex4();
    if (cp >= 0xD800 && cp < 0xDC00 && take_word("\\u")) {
      const unsigned low = hex4();
      if (low >= 0xDC00 && low < 0xE000) return 0x10000 + ((cp - 0xD800) << 10) + (low - 0xDC00);
    }
    if (cp >= 0xD800 && cp < 0xE000) {
      pos_ = at;
      fail("a lone surrogate in a \\u escape");
    }
    return cp;
  }

  // Bytes other than '"', '\' and control characters are kept as they are, UTF-8 or not.
  std::string string_literal() {
    static constexpr std::string_view kEscapes = "\"\\/bfnrt";
    static constexpr std::string_view kMeanings = "\"\\/\b\f\n\r\t";
    ++pos_;  // the opening quote
    std::string out;
    while (true) {
      if (pos_ >= s_.size()) fail("a string without its closing quote");
      const char c = s_[pos_];
      if (c == '"') {
        ++pos_;
        return out;
      }
      if (static_cast<unsigned char>(c) < 0x20) fail("a control character inside a string");
      ++pos_;
      if (c != '\\') {
        out += c;
        continue;
      }
      if (pos_ >= s_.size()) fail("a string without its closing quote");
      const char e = s_[pos_++];
      if (e == 'u') {
        append_utf8(out, unicode_escape());
      } else if (const std::size_t k = kEscapes.find(e); k != std::string_view::npos) {
        out += kMeanings[k];
      } else {
        --pos_;
        fail("an unknown escape in a string");
      }
    }
  }

  std::string_view s_;
  const std::string& file_;
  std::size_t pos_ = 0;
};

Value parse(std::string_view text, const std::string& file) {
  return Parser(text, file).document();
}

}  // namespace tincdt::json
