// The one exception family of the library. `apps/` turns it into a message and an exit code.
#pragma once

#include <stdexcept>
#include <string>

namespace tincdt {

// What the user can change to get past an error. The library says which; a front end says how,
// in its own terms (the command line names its option).
enum class Remedy {
  none,
  overwrite,           // the output exists: allow replacing it
  choose_layer,        // the vector source has several layers: name one
  z_field,             // a feature has no usable z of its own: take z from an attribute
  vector_as_points,    // a vector file given as points: give it as lines or polygons instead
  class_filter,        // a class filter on points without classes: leave it out for them
  return_filter,       // a return filter on points without return numbers: leave it out for them
  larger_buffer,       // a tile job's buffer is too small: allow it a larger one
  override_crs,        // an input's own CRS is unusable or wrong: replace it with the right one
  assign_crs,          // an input has no CRS while others have one: say which CRS it is in
  target_after_merge,  // a job that reads by box cannot take another CRS: transform the result
  // (apps/tincdt/error_message.cpp has a hint for each, in this order; target_after_merge is its
  // last)
};

// what() is a single line: "FILE: WHERE: DETAIL", leaving out the parts that are empty.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& detail) : Error({}, {}, detail) {}
  // file: the input or output path; where: "line 12", "byte 4096", "layer contours, feature 7".
  Error(std::string file, std::string where, std::string detail, Remedy remedy = Remedy::none);

  const std::string& file() const { return file_; }
  const std::string& where() const { return where_; }
  const std::string& detail() const { return detail_; }
  Remedy remedy() const { return remedy_; }

 private:
  std::string file_;
  std::string where_;
  std::string detail_;
  Remedy remedy_;
};

// Unreadable, malformed or unsupported input.
class InputError : public Error {
  using Error::Error;
};

// An output that cannot be written (permissions, disk full, exists and may not be replaced).
class OutputError : public Error {
  using Error::Error;
};

// Input that is well-formed but cannot be triangulated (fewer than 3 distinct points, all
// collinear).
class GeometryError : public Error {
  using Error::Error;
};

// Options that contradict each other or give no usable value: the caller's mistake, found
// before any work (the command line maps it to exit code 2).
class UsageError : public Error {
  using Error::Error;
};

// A broken invariant: a bug in tincdt, never the input's fault. what() starts with
// "internal error, please report: " (the command line maps it to exit code 3).
class InternalError : public Error {
 public:
  explicit InternalError(const std::string& detail)
      : Error({}, {}, "internal error, please report: " + detail) {}
};

// A Progress callback asked to stop.
class Cancelled : public Error {
 public:
  Cancelled() : Error("cancelled") {}
};

}  // namespace tincdt
