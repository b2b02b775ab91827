// Numbers as messages print them, one way everywhere: thousands separated ("3,999,996"), other
// values to six significant digits ("0.001", "12,345.7", "1e+308"), never the hundreds of digits
// std::to_string gives a huge double. Machine-read text (JSON, plans) keeps plain numbers.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>

namespace tincdt {

namespace detail {

// DIGITS ("-1234567.5") with its integer part's thousands separated ("-1,234,567.5").
inline std::string group_thousands(std::string_view digits) {
  const std::size_t sign = !digits.empty() && digits.front() == '-' ? 1 : 0;
  std::size_t end = sign;
  while (end < digits.size() && digits[end] >= '0' && digits[end] <= '9') ++end;
  std::string out(digits.substr(0, sign));
  for (std::size_t i = sign; i < end; ++i) {
    if (i > sign && (end - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  out += digits.substr(end);
  return out;
}

}  // namespace detail

// 3999996 -> "3,999,996".
inline std::string count_text(std::uint64_t n) {
  return detail::group_thousands(std::to_string(n));
}

// A count and its noun, the noun singular for one: (1, "segment") -> "1 segment", (1200,
// "segment") -> "1,200 segments". PLURAL is for a noun that does not just take an "s" ("vertex",
// "vertices").
inline std::string count_text(std::uint64_t n, std::string_view noun,
                              std::string_view plural = {}) {
  std::string text = count_text(n) + ' ';
  if (n == 1)
    text += noun;
  else if (plural.empty())
    text.append(noun).append("s");
  else
    text += plural;
  return text;
}

// count_text for a value that can be negative: -1234567 -> "-1,234,567".
inline std::string signed_count_text(std::int64_t n) {
  return detail::group_thousands(std::to_string(n));
}

// Six significant digits, without an exponent from 1e-4 to 1e15 and the integer part grouped
// ("0.25", "12,345.7", "19,876,500"); an exponent beyond ("1e-07", "1e+308"); "inf", "nan".
inline std::string number_text(double v) {
  char text[48];
  const double size = std::fabs(v);
  if (!std::isfinite(v) || size >= 1e15 || (size < 1e-4 && size != 0)) {
    std::snprintf(text, sizeof text, "%g", v);
    return text;
  }
  if (size >= 999999.5) {  // %g would switch to an exponent here (six digits round up)
    const double unit = std::pow(10.0, std::floor(std::log10(size)) - 5);
    std::snprintf(text, sizeof text, "%.0f", std::round(v / unit) * unit);
  } else {
    std::snprintf(text, sizeof text, "%g", v);
  }
  return detail::group_thousands(text);
}

}  // namespace tincdt
