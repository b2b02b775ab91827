// A number as a message shows it: printf's %g, six significant digits ("0.001", "1e+308"),
// never the hundreds of digits std::to_string gives a huge double.
#pragma once

#include <cstdio>
#include <string>

namespace tincdt::products {

inline std::string short_number(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

}  // namespace tincdt::products
