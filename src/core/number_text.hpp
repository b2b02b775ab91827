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

// Whole values below 1e15 in full, grouped ("1,000", "-25"); others as %g, the integer part
// grouped ("12,345.7", "0.25", "1e+308", "nan").
inline std::string number_text(double v) {
  char text[48];
  if (std::isfinite(v) && v == std::floor(v) && std::fabs(v) < 1e15)
    std::snprintf(text, sizeof text, "%.0f", v);
  else
    std::snprintf(text, sizeof text, "%g", v);
  const std::string_view s(text);
  if (s.find_first_of("en") != std::string_view::npos) return std::string(s);  // exponent, inf, nan
  return detail::group_thousands(s);
}

}  // namespace tincdt
