#include "error_message.hpp"

namespace tincdt::cli {

std::string error_message(const Error& e) {
  std::string message = e.what();
  switch (e.remedy()) {
    case Remedy::none:
      break;
    case Remedy::overwrite:
      message += " (use --overwrite to replace it)";
      break;
    case Remedy::choose_layer:
      message += " or with --layer";
      break;
    case Remedy::z_field:
      message += ", or take z from an attribute with --z-field NAME";
      break;
    case Remedy::larger_buffer:
      message +=
          " (run this tile with a larger --buffer or --max-buffer; the tiles already "
          "built stay valid)";
      break;
    case Remedy::vector_as_points:
      message +=
          "; give vector lines with --contours or --hard-lines, polygons with --clip or "
          "--erase";
      break;
    case Remedy::class_filter:
      message += " (asked by --keep-class / --drop-class)";
      break;
    case Remedy::return_filter:
      message += " (asked by --first-only / --last-only)";
      break;
    case Remedy::override_crs:
      message += "; if the coordinates are in another CRS, give it with --override-srs SRS";
      break;
    case Remedy::assign_crs:
      message += "; give the CRS of the inputs that have none with --a-srs SRS";
      break;
  }
  return message;
}

}  // namespace tincdt::cli
