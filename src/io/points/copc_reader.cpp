// COPC files node by node, for callers that choose the nodes themselves (the tile plan's rim).
#include <sys/stat.h>

#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/mapped_file.hpp"
#include "io/points/laz/copc_hierarchy.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/point_reader.hpp"

namespace tincdt::io {

std::vector<CopcNodeSummary> copc_nodes(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return {};  // read_points() says
  const detail::MappedFile file(path);
  if (file.size() < 4 || std::string(file.chars(), 4) != "LASF") return {};
  std::vector<std::string> warnings;
  laz::LazSource src;
  try {
    src = laz::open_laz(path, file.data(), file.size(), warnings);
  } catch (const InputError&) {
    return {};  // not LAZ, or damaged: read_points() says how
  }
  // Only the layered point formats (6, 7, 8) are read by node; others are read whole.
  if (src.copc_info == nullptr || src.point_format < 6) return {};
  std::vector<CopcNodeSummary> out;
  for (const laz::CopcNode& n : laz::read_hierarchy(src, nullptr).nodes)
    out.push_back({n.bounds, n.key.level, n.points, n.bytes});
  return out;
}

PointReadStats read_copc_nodes(const std::string& path, const PointFilter& filter,
                               const std::vector<std::size_t>& nodes, std::vector<Point3>& out,
                               unsigned threads) {
  const detail::MappedFile file(path);
  PointReadStats stats;
  laz::LazSource src = laz::open_laz(path, file.data(), file.size(), stats.warnings);
  if (src.copc_info == nullptr) throw InputError(path, "", "not a COPC file");
  src.mapping = &file;
  const laz::CopcHierarchy h = laz::read_hierarchy(src, nullptr);
  std::vector<laz::CopcNode> chosen;
  for (const std::size_t i : nodes) {
    if (i >= h.nodes.size()) throw InternalError("read_copc_nodes: no node " + count_text(i));
    chosen.push_back(h.nodes[i]);
  }
  laz::LazReadFigures figures;
  const std::size_t first = out.size();
  stats.format = "copc";
  stats.points_kept = laz::read_nodes(src, std::move(chosen), filter, threads, out, figures);
  stats.points_read = figures.points_decoded;
  stats.bytes_read = figures.chunk_bytes + h.page_bytes;
  for (std::size_t i = first; i < out.size(); ++i) stats.extent.add(out[i].x, out[i].y);
  return stats;
}

}  // namespace tincdt::io
