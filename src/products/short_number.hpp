// A number as a message shows it: number_text(), six significant digits, thousands separated
// ("0.001", "12,345.7", "1e+308"), never the hundreds of digits std::to_string gives a huge
// double.
#pragma once

#include <string>

#include "core/number_text.hpp"

namespace tincdt::products {

inline std::string short_number(double v) {
  return number_text(v);
}

}  // namespace tincdt::products
