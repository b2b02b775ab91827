#include "pipeline/input_crs.hpp"

#include "core/error.hpp"
#include "io/crs.hpp"

namespace tincdt::pipeline::detail {

InputCrs::InputCrs(Job& job) : job_(job) {}

void InputCrs::add(const std::string& path, const std::string& own, bool implied) {
  if (!added_.insert(path).second) return;
  CrsNames& names = job_.crs_names;
  std::string taken = own;
  if (!job_.override_crs_wkt.empty()) {
    taken = job_.override_crs_wkt;
    if (!own.empty() && !io::same_crs(own, taken))
      job_.debug(path + ": its CRS " + names.name(own) + " replaced by " + names.name(taken));
  } else if (own.empty() || implied) {
    taken = job_.assign_crs_wkt;
    if (taken.empty() && implied) {
      implied_.push_back({path, own});
      return;
    }
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
}

void InputCrs::check_none_without() const {
  if (crs_.empty()) return;
  const std::string known = source_ + " is in " + job_.crs_names.name(crs_);
  if (!without_crs_.empty())
    throw InputError(without_crs_.front(), "",
                     "no CRS in the file, while " + known + " (a file's CRS is not guessed)",
                     Remedy::assign_crs);
  if (!implied_.empty())
    throw InputError(implied_.front().path, "",
                     "the file names no CRS (GeoJSON's default would be " +
                         job_.crs_names.name(implied_.front().wkt) + "), while " + known +
                         " (a file's CRS is not guessed)",
                     Remedy::assign_crs);
}

void InputCrs::finish() {
  check_none_without();
  if (!crs_.empty() || implied_.empty()) return;
  crs_ = implied_.front().wkt;
  source_ = implied_.front().path;
  for (const Implied& other : implied_) {
    if (io::same_crs(other.wkt, crs_)) continue;
    throw InputError(other.path, "",
                     "its default CRS " + job_.crs_names.name(other.wkt) + " differs from " +
                         job_.crs_names.name(crs_) + " of " + source_,
                     Remedy::assign_crs);
  }
  for (const std::string& path : without_crs_)
    job_.warn(path + ": no CRS in the file; assuming " + job_.crs_names.name(crs_) + " of " +
              source_ + ", which names none either (its format's default)");
}

}  // namespace tincdt::pipeline::detail
