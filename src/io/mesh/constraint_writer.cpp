// Constraint lines as GeoJSON: see constraint_writer.hpp. Written directly with to_chars through
// the TIN writer's BlockWriter, header and positions (writer_detail.hpp), so both GeoJSON
// outputs agree to the bit.
#include "io/mesh/constraint_writer.hpp"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/json_text.hpp"
#include "core/memory.hpp"
#include "core/number_text.hpp"
#include "io/mesh/writer_detail.hpp"
#include "io/output_file.hpp"

namespace tincdt::io {
namespace {

std::string edge_where(std::size_t i) {
  return "constraint edge " + count_text(i);
}

// Checks the edges against the TIN and the feature table; returns the number of distinct
// vertices they use.
std::uint64_t check_edges(const std::string& path, const mesh::Triangulation& tin,
                          const std::vector<ConstraintEdge>& edges,
                          const std::vector<ConstraintFeatureInfo>& features) {
  const std::size_t nv = tin.vertex_count();
  std::vector<bool> used(nv, false);
  std::uint64_t distinct = 0;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const ConstraintEdge& e = edges[i];
    for (const VertexId v : {e.a, e.b}) {
      if (v >= nv)
        throw OutputError(path, edge_where(i),
                          "vertex " + count_text(v) + " is not a vertex of the TIN (" +
                              count_text(nv) + " vertices)");
      if (!used[v]) {
        used[v] = true;
        ++distinct;
      }
    }
    if (e.feature >= features.size())
      throw OutputError(path, edge_where(i),
                        "feature index " + count_text(e.feature) + " is out of range (" +
                            count_text(features.size()) + " features)");
  }
  return distinct;
}

// The GeoJSON document into OUT (checked by check_edges()), not committed.
void write_lines(OutputFile& out, const mesh::Triangulation& tin,
                 const std::vector<ConstraintEdge>& edges,
                 const std::vector<ConstraintFeatureInfo>& features,
                 const TinWriteOptions& options) {
  using detail::BlockWriter;
  const std::string& path = out.path();

  BlockWriter w(out);
  detail::put_feature_collection_start(w, path, options);
  // The escaped file name of the last feature seen: consecutive edges mostly share their file.
  std::string file_json;
  const std::string* file_of_json = nullptr;
  for (std::size_t i = 0; i < edges.size(); ++i) {
    const ConstraintEdge& e = edges[i];
    const ConstraintFeatureInfo& f = features[e.feature];
    if (file_of_json == nullptr || *file_of_json != f.file) {
      file_json = json_string(f.file);
      file_of_json = &f.file;
    }
    // Throws for a coordinate, the height included, that is not finite.
    const Point3 a = detail::shifted_vertex(path, tin, e.a, options.offset);
    const Point3 b = detail::shifted_vertex(path, tin, e.b, options.offset);

    if (i > 0) w.put(std::string_view(",\n"));
    w.put(std::string_view("{\"type\":\"Feature\",\"properties\":{\"source_file\":"));
    w.put(file_json);
    w.put(std::string_view(",\"source_fid\":"));
    if (f.fid < 0) {
      w.put('-');
      w.put_uint(0 - static_cast<std::uint64_t>(f.fid));
    } else {
      w.put_uint(static_cast<std::uint64_t>(f.fid));
    }
    w.put(std::string_view(",\"z_start\":"));
    w.put_double(tin.z(e.a));
    w.put(std::string_view(",\"z_end\":"));
    w.put_double(tin.z(e.b));
    w.put(std::string_view("},\"geometry\":{\"type\":\"LineString\",\"coordinates\":["));
    detail::put_position(w, a);
    w.put(',');
    detail::put_position(w, b);
    w.put(std::string_view("]}}"));
  }
  w.put(std::string_view("\n]\n}\n"));
  w.flush();
}

}  // namespace

TinWriteStats write_constraint_lines(OutputFile& out, const mesh::Triangulation& tin,
                                     const std::vector<ConstraintEdge>& edges,
                                     const std::vector<ConstraintFeatureInfo>& features,
                                     const TinWriteOptions& options) {
  const std::uint64_t distinct = check_edges(out.path(), tin, edges, features);
  write_lines(out, tin, edges, features, options);
  return {distinct, 0, out.bytes_written()};
}

TinWriteStats write_constraint_lines(const std::string& path, const mesh::Triangulation& tin,
                                     const std::vector<ConstraintEdge>& edges,
                                     const std::vector<ConstraintFeatureInfo>& features,
                                     const TinWriteOptions& options) {
  const std::uint64_t distinct = check_edges(path, tin, edges, features);
  OutputFile out(path, options.overwrite);
  write_lines(out, tin, edges, features, options);
  out.commit();
  return {distinct, 0, out.bytes_written()};
}

}  // namespace tincdt::io
