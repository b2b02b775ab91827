#include "error_message.hpp"

#include <cstddef>
#include <iterator>
#include <string_view>
#include <utility>

namespace tincdt::cli {
namespace {

// What the user can do about an error, by the option that does it: one row per Remedy, in the
// enum's order (checked below), appended to the library's message.
constexpr std::pair<Remedy, std::string_view> kHints[] = {
    {Remedy::none, ""},
    {Remedy::overwrite, " (use --overwrite to replace it)"},
    {Remedy::choose_layer, " or with --layer"},
    {Remedy::z_field, ", or take z from an attribute with --z-field NAME"},
    {Remedy::vector_as_points,
     "; give vector lines with --contours or --hard-lines, polygons with --clip or --erase"},
    {Remedy::class_filter, " (asked by --keep-class / --drop-class)"},
    {Remedy::return_filter, " (asked by --first-only / --last-only)"},
    {Remedy::larger_buffer,
     " (run this tile with a larger --buffer or --max-buffer; the tiles already built stay "
     "valid)"},
    {Remedy::override_crs,
     "; if the coordinates are in another CRS, give it with --override-srs SRS"},
    {Remedy::assign_crs, "; give the CRS of the inputs that have none with --a-srs SRS"},
    {Remedy::target_after_merge,
     "; merge the tiles, then transform the merged TIN into the target CRS with --t-srs in a job "
     "of its own, giving it the lines again (a PLY's points carry no constrained edges)"},
};

constexpr bool one_row_per_remedy() {
  for (std::size_t i = 0; i < std::size(kHints); ++i)
    if (static_cast<std::size_t>(kHints[i].first) != i) return false;
  return static_cast<std::size_t>(Remedy::target_after_merge) + 1 == std::size(kHints);  // the last
}
static_assert(one_row_per_remedy(), "kHints: one row per Remedy, in order");

}  // namespace

std::string error_message(const Error& e) {
  return e.what() + std::string(kHints[static_cast<std::size_t>(e.remedy())].second);
}

}  // namespace tincdt::cli
