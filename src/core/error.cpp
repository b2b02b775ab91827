#include "core/error.hpp"

#include <utility>

#include "core/quoted_text.hpp"

namespace tincdt {
namespace {

std::string compose(const std::string& file, const std::string& where, const std::string& detail) {
  std::string s;
  for (const std::string* part : {&file, &where, &detail}) {
    if (part->empty()) continue;
    if (!s.empty()) s += ": ";
    s += part == &file ? name_text(file) : *part;
  }
  return s;
}

}  // namespace

Error::Error(std::string file, std::string where, std::string detail, Remedy remedy)
    : std::runtime_error(compose(file, where, detail)),
      file_(std::move(file)),
      where_(std::move(where)),
      detail_(std::move(detail)),
      remedy_(remedy) {}

}  // namespace tincdt
