// Names and bytes as messages echo them: in single quotes, on one line, and short. File content
// and names from a plan can hold anything (binary bytes, newlines, a megabyte of text); what
// reaches the terminal is printable text only, with the rest escaped, and cut in the middle.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace tincdt {

namespace detail {

// The length of the well-formed UTF-8 sequence of two or more bytes at TEXT[I], or 0.
inline std::size_t utf8_sequence(std::string_view text, std::size_t i) {
  const auto c = static_cast<unsigned char>(text[i]);
  const std::size_t n = c >= 0xC2 && c <= 0xDF   ? 2
                        : c >= 0xE0 && c <= 0xEF ? 3
                        : c >= 0xF0 && c <= 0xF4 ? 4
                                                 : 0;
  if (n == 0 || text.size() - i < n) return 0;
  for (std::size_t k = 1; k < n; ++k)
    if ((static_cast<unsigned char>(text[i + k]) & 0xC0) != 0x80) return 0;
  return n;
}

// The character at TEXT[I] as a message shows it ("a", "é", "\n", "\x01", "\\"), and the bytes it
// takes.
inline std::size_t escaped_char(std::string_view text, std::size_t i, std::string& out) {
  const auto c = static_cast<unsigned char>(text[i]);
  if (c == '\\') {
    out = "\\\\";  // doubled, so that a backslash in the text is not read as an escape
    return 1;
  }
  if (c >= 0x20 && c < 0x7F) {
    out.assign(1, static_cast<char>(c));
    return 1;
  }
  if (c >= 0x80) {
    if (const std::size_t n = utf8_sequence(text, i)) {
      out.assign(text.substr(i, n));
      return n;
    }
  }
  if (c == '\n')
    out = "\\n";
  else if (c == '\r')
    out = "\\r";
  else if (c == '\t')
    out = "\\t";
  else {
    char hex[8];
    std::snprintf(hex, sizeof hex, "\\x%02X", c);
    out = hex;
  }
  return 1;
}

// Columns a shown character takes: one for a UTF-8 character, its length for the rest.
inline std::size_t shown_width(const std::string& shown) {
  return static_cast<unsigned char>(shown[0]) >= 0x80 ? 1 : shown.size();
}

}  // namespace detail

// TEXT in single quotes, printable ("'a\x01b\nc.las'"), at most MAX columns between the quotes:
// a longer text keeps its start and its end (a path's file name) around "..." (ASCII, as the
// rest of a message, for any terminal and log).
inline std::string quoted_text(std::string_view text, std::size_t max = 80) {
  if (max < 8) max = 8;
  std::string head, shown;
  std::size_t i = 0, width = 0;
  const std::size_t head_max = max - max / 3 - 3;  // three columns for the "..."
  std::size_t head_end = 0;                        // bytes of TEXT in HEAD
  std::string head_cut;
  while (i < text.size()) {
    const std::size_t n = detail::escaped_char(text, i, shown);
    width += detail::shown_width(shown);
    if (width > max) break;
    head += shown;
    i += n;
    if (width <= head_max) head_cut = head, head_end = i;
  }
  if (i == text.size()) return "'" + head + "'";
  // The tail: the last characters that fit in the columns the head leaves. Each shows in at most
  // 4 columns from at most 4 bytes, so the last 4 * TAIL_MAX bytes are enough to look at.
  const std::size_t tail_max = max - head_max - 3;
  std::size_t from = text.size() - std::min(text.size() - head_end, 4 * tail_max);
  while (from < text.size() && from > head_end &&
         (static_cast<unsigned char>(text[from]) & 0xC0) == 0x80)
    ++from;  // start on a character, not inside one
  std::vector<std::string> tail;
  std::size_t tail_width = 0;
  for (std::size_t k = from; k < text.size();) {
    k += detail::escaped_char(text, k, shown);
    tail_width += detail::shown_width(shown);
    tail.push_back(shown);
  }
  std::size_t first = 0;
  for (; tail_width > tail_max; ++first) tail_width -= detail::shown_width(tail[first]);
  std::string out = "'" + head_cut + "...";
  for (std::size_t k = first; k < tail.size(); ++k) out += tail[k];
  return out + "'";
}

// A file name where a message starts with it ("FILE: line 3: ..."): as it is when it is short
// printable text, else quoted_text(), so that a name from a damaged plan keeps the message one
// short line.
inline std::string name_text(std::string_view name, std::size_t max = 160) {
  bool plain = name.size() <= max;
  for (std::size_t i = 0; plain && i < name.size();) {
    const auto c = static_cast<unsigned char>(name[i]);
    const std::size_t n = c >= 0x80 ? detail::utf8_sequence(name, i) : c >= 0x20 && c < 0x7F;
    plain = n > 0;
    i += n;
  }
  return plain ? std::string(name) : quoted_text(name, max);
}

}  // namespace tincdt
