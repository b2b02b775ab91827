// The one exception family of the library. `apps/` turns it into a message and an exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace tincdt {

// what() is a single line: "FILE: WHERE: DETAIL", leaving out the parts that are empty.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& detail) : Error({}, {}, detail) {}
  // file: the input or output path; where: "line 12", "byte 4096", "layer contours, feature 7".
  Error(std::string file, std::string where, std::string detail);

  const std::string& file() const { return file_; }
  const std::string& where() const { return where_; }
  const std::string& detail() const { return detail_; }

 private:
  std::string file_;
  std::string where_;
  std::string detail_;
};

// Unreadable, malformed or unsupported input.
class InputError : public Error {
  using Error::Error;
};

// An output that cannot be written (permissions, disk full, exists without --overwrite).
class OutputError : public Error {
  using Error::Error;
};

// Input that is well-formed but cannot be triangulated (fewer than 3 distinct points, all
// collinear).
class GeometryError : public Error {
  using Error::Error;
};

// A Progress callback asked to stop.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

}  // namespace tincdt
