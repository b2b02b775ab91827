#include "io/crs_probe.hpp"

#include <fstream>
#include <string>
#include <utility>

#include "io/points/point_reader.hpp"
#include "io/vector/ogr_source.hpp"

namespace tincdt::io {

std::optional<std::string> point_file_crs(const std::string& path) {
  if (path == "-") return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  char signature[4] = {};
  if (!in.read(signature, sizeof signature) || std::string(signature, 4) != "LASF")
    return std::nullopt;
  return read_las_crs(path);
}

VectorCrs vector_source_crs(const std::string& spec, const std::string& layer) {
  const detail::OgrLayer source(spec, layer, 0);
  std::string implied = source.implied_crs_wkt();
  if (!implied.empty()) return {std::move(implied), true};
  return {source.crs_wkt(), false};
}

}  // namespace tincdt::io
