// COPC files node by node, for callers that choose the nodes themselves (the tile plan's rim).
#include <sys/stat.h>

#include <cassert>
#include <memory>
#include <string>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "io/mapped_file.hpp"
#include "io/points/laz/copc_hierarchy.hpp"
#include "io/points/laz/laz_reader.hpp"
#include "io/points/point_reader.hpp"

namespace tincdt::io {

struct CopcNodes::File {
  explicit File(const std::string& path) : mapping(path) {}
  detail::MappedFile mapping;
  laz::LazSource source;
  std::vector<laz::CopcNode> nodes;
};

CopcNodes::CopcNodes(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return;  // read_points() says
  auto file = std::make_unique<File>(path);
  const detail::MappedFile& m = file->mapping;
  if (m.size() < 4 || std::string(m.chars(), 4) != "LASF") return;
  std::vector<std::string> warnings;
  try {
    file->source = laz::open_laz(path, m.data(), m.size(), warnings);
  } catch (const InputError&) {
    return;  // not LAZ, or damaged: read_points() says how
  }
  // Only the layered point formats (6, 7, 8) are read by node; others are read whole.
  if (file->source.copc_info == nullptr || file->source.point_format < 6) return;
  file->source.mapping = &file->mapping;
  file->nodes = laz::read_hierarchy(file->source, nullptr).nodes;
  for (const laz::CopcNode& n : file->nodes)
    nodes_.push_back({n.bounds, n.key.level, n.points, n.bytes, n.offset});
  file_ = std::move(file);
}

CopcNodes::~CopcNodes() = default;

std::vector<std::uint64_t> CopcNodes::read(const std::vector<std::size_t>& nodes,
                                           const PointFilter& filter, std::vector<Point3>& out,
                                           unsigned threads) const {
  std::vector<laz::CopcNode> chosen;
  for (const std::size_t i : nodes) {
    if (i >= nodes_.size()) throw InternalError("CopcNodes::read: no node " + count_text(i));
    chosen.push_back(file_->nodes[i]);
  }
  laz::LazReadFigures figures;
  std::vector<std::uint64_t> kept_per_node;
  laz::read_nodes(file_->source, std::move(chosen), filter, threads, out, figures, &kept_per_node);
  assert(kept_per_node.size() == nodes.size());
  return kept_per_node;
}

}  // namespace tincdt::io
