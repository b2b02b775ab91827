// The CRS a job's inputs are taken in. Each input's own CRS must be one a terrain TIN can be built
// in; the override CRS replaces every input's own, the default CRS is given to inputs without
// one; then every input has a CRS, or none has: a file's CRS is never guessed from the others'.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "pipeline/job.hpp"

namespace tincdt::pipeline::detail {

class InputCrs {
 public:
  // Takes the override and default CRSs from JOB (--override-srs, --a-srs); messages go to its
  // log with its CRS names.
  explicit InputCrs(Job& job);

  // Input PATH, whose own CRS is OWN ("" for none); IMPLIED: OWN is only its format's default
  // (a GeoJSON file that names no CRS), which counts as none beside inputs that name theirs. An
  // input added before is skipped (its header was read before its points). Throws InputError
  // (Remedy::override_crs) when OWN is not usable and nothing replaces it, and when the CRS it is
  // taken in differs from the inputs' CRS found so far.
  void add(const std::string& path, const std::string& own, bool implied = false);

  // Throws InputError (Remedy::assign_crs) naming the first input without a CRS when another
  // has one.
  void check_none_without() const;

  // After every input: check_none_without(); then, when no input names a CRS, the one implied
  // (if any) is the inputs', and the inputs without a CRS take it, with a warning each.
  void finish();

  // The CRS of the inputs, "" when none has one.
  const std::string& crs() const { return crs_; }

 private:
  struct Implied {
    std::string path;
    std::string wkt;
  };
  Job& job_;
  std::string crs_;
  std::string source_;  // the input the CRS comes from
  std::set<std::string> added_;
  std::vector<std::string> without_crs_;
  std::vector<Implied> implied_;
};

}  // namespace tincdt::pipeline::detail
