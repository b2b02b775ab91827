// The CRS a job's inputs are taken in. Each input's own CRS must be one a terrain TIN can be built
// in; the override CRS replaces every input's own, the default CRS is given to inputs without
// one; then every input has a CRS, or none has.
#pragma once

#include <string>
#include <vector>

#include "pipeline/job.hpp"

namespace tincdt::pipeline::detail {

class InputCrs {
 public:
  // Takes the override and default CRSs from JOB (--override-srs, --a-srs); messages go to its
  // log with its CRS names.
  explicit InputCrs(Job& job);

  // Input PATH, whose own CRS is OWN ("" for none): returns the CRS it is taken in. Throws
  // InputError (Remedy::override_crs) when OWN is not usable and nothing replaces it, and when it
  // differs from the inputs' CRS found so far.
  std::string add(const std::string& path, const std::string& own);

  // After the inputs: the inputs without a CRS take the one found, with a warning each.
  void finish() const;

  // The CRS of the inputs, "" when none has one.
  const std::string& crs() const { return crs_; }
  // The input it comes from, or the option that gave it.
  const std::string& source() const { return source_; }

 private:
  Job& job_;
  std::string crs_;
  std::string source_;
  std::vector<std::string> without_crs_;
};

}  // namespace tincdt::pipeline::detail
