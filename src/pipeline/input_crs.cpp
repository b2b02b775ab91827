#include "pipeline/input_crs.hpp"

#include "core/error.hpp"
#include "io/crs.hpp"

namespace tincdt::pipeline::detail {

InputCrs::InputCrs(Job& job) : job_(job) {}

std::string InputCrs::add(const std::string& path, const std::string& own) {
  CrsNames& names = job_.crs_names;
  std::string taken = own;
  if (!job_.override_crs_wkt.empty()) {
    taken = job_.override_crs_wkt;
    if (!own.empty() && !io::same_crs(own, taken))
      job_.debug(path + ": its CRS " + names.name(own) + " replaced by " + names.name(taken));
  } else if (own.empty()) {
    taken = job_.assign_crs_wkt;
  } else if (const std::string why = io::crs_unusable_reason(own); !why.empty()) {
    throw InputError(path, "", "its CRS " + names.name(own) + " cannot be used: " + why,
                     Remedy::override_crs);
  }
  if (taken.empty()) {
    without_crs_.push_back(path);
  } else if (crs_.empty()) {
    crs_ = taken;
    source_ = path;
  } else if (!io::same_crs(crs_, taken)) {
    const std::string mine = names.name(taken), theirs = names.name(crs_);
    throw InputError(path, "",
                     "CRS " + mine + " differs from " + theirs + " of " + source_ +
                         (mine == theirs ? " (same name, different definition)" : "") +
                         " (reproject one of them)",
                     Remedy::override_crs);
  }
  return taken;
}

void InputCrs::finish() const {
  if (crs_.empty()) return;
  for (const std::string& path : without_crs_)
    job_.warn(path + ": no CRS in the file; assuming " + job_.crs_names.name(crs_) + " of " +
              source_);
}

}  // namespace tincdt::pipeline::detail
