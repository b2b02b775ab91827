// Readers for the TINs the tests have tincdt write: ASCII PLY and OBJ back into vertices, faces
// and edges, and the element counts of a PLY header. Header-only, for the tests.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/files.hpp"

namespace tincdt::test {

// What an ASCII PLY or an OBJ holds, and a few measures of it.
struct MeshFile {
  std::vector<std::array<double, 3>> v;
  std::vector<std::array<std::size_t, 3>> f;  // 0-based
  std::vector<std::array<std::size_t, 2>> e;  // PLY edges

  double area() const {
    double a = 0;
    for (const auto& t : f) a += signed_area(t);
    return a;
  }
  double signed_area(const std::array<std::size_t, 3>& t) const {
    const auto &p = v[t[0]], &q = v[t[1]], &r = v[t[2]];
    return ((q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])) / 2;
  }
  std::array<double, 2> centroid(const std::array<std::size_t, 3>& t) const {
    return {(v[t[0]][0] + v[t[1]][0] + v[t[2]][0]) / 3, (v[t[0]][1] + v[t[1]][1] + v[t[2]][1]) / 3};
  }
  std::size_t used_vertices() const {
    std::set<std::size_t> used;
    for (const auto& t : f) used.insert(t.begin(), t.end());
    return used.size();
  }
  double max_edge_length(const std::array<std::size_t, 3>& t) const {
    double m = 0;
    for (int i = 0; i < 3; ++i) {
      const auto &p = v[t[i]], &q = v[t[(i + 1) % 3]];
      m = std::max(m, std::hypot(q[0] - p[0], q[1] - p[1]));
    }
    return m;
  }
};

// The N of the "element NAME N" line in HEADER (a PLY header, up to "end_header" or beyond);
// nullopt when there is none.
inline std::optional<std::uint64_t> ply_element_count(const std::string& header,
                                                      const std::string& name) {
  std::istringstream in(header);
  for (std::string line; std::getline(in, line) && line != "end_header";) {
    std::istringstream ls(line);
    std::string word, element;
    std::uint64_t n = 0;
    ls >> word >> element >> n;
    if (word == "element" && element == name) return n;
  }
  return std::nullopt;
}

// The header of the PLY file at PATH: its lines before "end_header".
inline std::string ply_header(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string header;
  for (std::string line; std::getline(in, line) && line != "end_header";) header += line + "\n";
  return header;
}

// "v x y z" and "f a b c" (1-based) lines; anything else is skipped.
inline MeshFile read_obj(const std::filesystem::path& p) {
  MeshFile m;
  std::istringstream in(slurp(p));
  for (std::string line; std::getline(in, line);) {
    std::istringstream ls(line);
    std::string tag;
    ls >> tag;
    if (tag == "v") {
      std::array<double, 3> v{};
      ls >> v[0] >> v[1] >> v[2];
      m.v.push_back(v);
    } else if (tag == "f") {
      std::array<std::size_t, 3> f{};
      ls >> f[0] >> f[1] >> f[2];
      for (auto& i : f) --i;
      m.f.push_back(f);
    }
  }
  return m;
}

// An ASCII PLY: the vertex, face and edge elements the header counts.
inline MeshFile read_ply_ascii(const std::filesystem::path& p) {
  MeshFile m;
  std::istringstream in(slurp(p));
  std::string header;
  for (std::string line; std::getline(in, line) && line != "end_header";) header += line + "\n";
  m.v.resize(ply_element_count(header, "vertex").value_or(0));
  for (auto& v : m.v) in >> v[0] >> v[1] >> v[2];
  m.f.resize(ply_element_count(header, "face").value_or(0));
  for (auto& f : m.f) {
    int three = 0;
    in >> three >> f[0] >> f[1] >> f[2];
  }
  m.e.resize(ply_element_count(header, "edge").value_or(0));
  for (auto& e : m.e) in >> e[0] >> e[1];
  return m;
}

// An OBJ or an ASCII PLY, by the file's extension.
inline MeshFile read_mesh(const std::filesystem::path& p) {
  return p.extension() == ".obj" ? read_obj(p) : read_ply_ascii(p);
}

}  // namespace tincdt::test
