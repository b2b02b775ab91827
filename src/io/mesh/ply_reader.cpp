#include "io/mesh/ply_reader.hpp"

#include <array>
#include <charconv>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/error.hpp"
#include "core/number_text.hpp"
#include "core/quoted_text.hpp"
#include "io/mapped_file.hpp"

namespace tincdt::io {
namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };

struct Property {
  std::string name;
  Type type = Type::f64;
  bool list = false;
  Type count_type = Type::u8;
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> props;
  int find(std::string_view n) const {
    for (std::size_t i = 0; i < props.size(); ++i)
      if (props[i].name == n) return static_cast<int>(i);
    return -1;
  }
};

std::size_t size_of(Type t) {
  switch (t) {
    case Type::i8:
    case Type::u8:
      return 1;
    case Type::i16:
    case Type::u16:
      return 2;
    case Type::i32:
    case Type::u32:
    case Type::f32:
      return 4;
    case Type::f64:
      return 8;
  }
  return 8;
}

bool parse_type(const std::string& s, Type& t) {
  static const std::pair<const char*, Type> kNames[] = {
      {"char", Type::i8},   {"int8", Type::i8},     {"uchar", Type::u8},   {"uint8", Type::u8},
      {"short", Type::i16}, {"int16", Type::i16},   {"ushort", Type::u16}, {"uint16", Type::u16},
      {"int", Type::i32},   {"int32", Type::i32},   {"uint", Type::u32},   {"uint32", Type::u32},
      {"float", Type::f32}, {"float32", Type::f32}, {"double", Type::f64}, {"float64", Type::f64}};
  for (const auto& [name, type] : kNames)
    if (s == name) {
      t = type;
      return true;
    }
  return false;
}

// Values in order, from binary little-endian bytes or ASCII tokens.
class Values {
 public:
  Values(const std::string& path, const std::uint8_t* p, const std::uint8_t* end, bool ascii)
      : path_(path), p_(p), begin_(p), end_(end), ascii_(ascii) {}

  double get(Type t) {
    if (ascii_) return token();
    if (static_cast<std::size_t>(end_ - p_) < size_of(t)) fail("the file ends inside the data");
    double v = 0;
    switch (t) {
      case Type::i8:
        v = static_cast<std::int8_t>(*p_);
        break;
      case Type::u8:
        v = *p_;
        break;
      case Type::i16:
        v = load<std::int16_t>();
        break;
      case Type::u16:
        v = load<std::uint16_t>();
        break;
      case Type::i32:
        v = load<std::int32_t>();
        break;
      case Type::u32:
        v = load<std::uint32_t>();
        break;
      case Type::f32:
        v = load<float>();
        break;
      case Type::f64:
        v = load<double>();
        break;
    }
    p_ += size_of(t);
    return v;
  }

  std::size_t remaining() const { return static_cast<std::size_t>(end_ - p_); }
  [[noreturn]] void fail(const std::string& what) const {
    throw InputError(path_, "byte " + count_text(p_ - begin_) + " after the header", what);
  }

 private:
  template <class T>
  T load() const {
    T v;
    std::memcpy(&v, p_, sizeof v);
    return v;
  }

  double token() {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) ++p_;
    const auto* start = reinterpret_cast<const char*>(p_);
    while (p_ < end_ && !(*p_ == ' ' || *p_ == '\t' || *p_ == '\r' || *p_ == '\n')) ++p_;
    const auto* stop = reinterpret_cast<const char*>(p_);
    if (start == stop) fail("the file ends inside the data");
    double v = 0;
    const auto [ptr, ec] = std::from_chars(start, stop, v);
    if (ec != std::errc() || ptr != stop)
      fail(quoted_text({start, static_cast<std::size_t>(stop - start)}) + " is not a number");
    return v;
  }

  const std::string& path_;
  const std::uint8_t* p_;
  const std::uint8_t* begin_;
  const std::uint8_t* end_;
  bool ascii_;
};

std::uint32_t index_of(Values& in, double v, std::size_t vertices, const char* what) {
  if (!(v >= 0 && v < static_cast<double>(vertices) && v == std::floor(v)))
    in.fail(std::string(what) + " names vertex " + number_text(v) + " of " + count_text(vertices));
  return static_cast<std::uint32_t>(v);
}

// The header's elements and format; the offset and CRS comments go into MESH.
struct Header {
  std::vector<Element> elements;
  bool ascii = false;
};

Header read_header(const std::string& path, std::string_view text, PlyMesh& mesh) {
  Header h;
  std::istringstream header{std::string(text)};
  std::size_t line_no = 0;
  for (std::string line; std::getline(header, line);) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::istringstream ls(line);
    std::string word;
    ls >> word;
    const auto bad = [&](const std::string& what) {
      throw InputError(path, "header line " + count_text(line_no), what);
    };
    if (word == "format") {
      std::string f;
      ls >> f;
      if (f == "ascii")
        h.ascii = true;
      else if (f != "binary_little_endian")
        bad("format " + quoted_text(f) + " (ascii and binary_little_endian are read)");
    } else if (word == "comment") {
      std::string key;
      ls >> key;
      std::string rest;
      std::getline(ls >> std::ws, rest);
      if (key == "offset") {
        std::istringstream os(rest);
        if (!(os >> mesh.offset.x >> mesh.offset.y >> mesh.offset.z)) bad("a bad offset comment");
      } else if (key == "crs") {
        mesh.crs = rest;
      } else if (key == "trimmed") {
        mesh.trimmed = rest;
      }
    } else if (word == "element") {
      Element e;
      if (!(ls >> e.name >> e.count)) bad("an element needs a name and a count");
      h.elements.push_back(std::move(e));
    } else if (word == "property") {
      if (h.elements.empty()) bad("a property before any element");
      Property p;
      std::string type;
      ls >> type;
      if (type == "list") {
        std::string count_type, item_type;
        ls >> count_type >> item_type >> p.name;
        p.list = true;
        if (!parse_type(count_type, p.count_type) || !parse_type(item_type, p.type))
          bad("an unknown list type");
      } else {
        ls >> p.name;
        if (!parse_type(type, p.type)) bad("unknown property type " + quoted_text(type));
      }
      h.elements.back().props.push_back(std::move(p));
    } else if (word != "ply" && word != "obj_info" && !word.empty()) {
      bad("unknown header line " + quoted_text(word));
    }
  }
  return h;
}

// Where an element's wanted properties are (-1: absent), and which kind of element it is.
struct Columns {
  int x, y, z, v1, v2, apex, constrained, list;
  bool is_vertex, is_face, is_edge;
};

// The columns of E, checked against what its kind needs, and its count against the bytes left.
Columns columns_of(Values& in, const Element& e, bool ascii) {
  // Every element needs at least this many bytes: refuse counts the file cannot hold before
  // allocating for them.
  std::size_t min_bytes = 0;
  for (const Property& p : e.props)
    min_bytes += ascii ? 2 : size_of(p.list ? p.count_type : p.type);
  if (min_bytes > 0 && e.count > in.remaining() / min_bytes)
    in.fail("element " + quoted_text(e.name) + " announces " + count_text(e.count) +
            " items, more than the file holds");
  Columns c{};
  c.x = e.find("x"), c.y = e.find("y"), c.z = e.find("z");
  c.v1 = e.find("vertex1"), c.v2 = e.find("vertex2"), c.apex = e.find("apex");
  c.constrained = e.find("constrained");
  c.list = e.find("vertex_indices");
  if (c.list < 0) c.list = e.find("vertex_index");
  c.is_vertex = e.name == "vertex", c.is_face = e.name == "face", c.is_edge = e.name == "edge";
  if (c.is_vertex && (c.x < 0 || c.y < 0 || c.z < 0)) in.fail("vertices without x, y and z");
  if (c.is_face && (c.list < 0 || !e.props[static_cast<std::size_t>(c.list)].list))
    in.fail("faces without a vertex_indices list");
  if (c.is_edge && (c.v1 < 0 || c.v2 < 0)) in.fail("edges without vertex1 and vertex2");
  return c;
}

// Stores item K of an element (its scalar values ROW, its face FACE) in MESH.
void store_item(Values& in, const Columns& c, std::uint64_t k, const std::vector<double>& row,
                const std::array<std::uint32_t, 3>& face, PlyMesh& mesh) {
  const auto at = [&row](int column) { return row[static_cast<std::size_t>(column)]; };
  if (c.is_vertex) {
    const Point3 v{at(c.x) + mesh.offset.x, at(c.y) + mesh.offset.y, at(c.z) + mesh.offset.z};
    if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
      in.fail("vertex " + count_text(k) + " is not finite");
    mesh.vertices.push_back(v);
  } else if (c.is_face) {
    mesh.faces.push_back(face);
  } else if (c.is_edge) {
    PlyMesh::Edge edge;
    const std::size_t nv = mesh.vertices.size();
    edge.a = index_of(in, at(c.v1), nv, "an edge");
    edge.b = index_of(in, at(c.v2), nv, "an edge");
    if (c.apex >= 0) edge.apex = index_of(in, at(c.apex), nv, "an edge");
    if (c.constrained >= 0) edge.constrained = at(c.constrained) != 0;
    mesh.edges.push_back(edge);
  }
}

// Reads the items of element E into MESH (vertices, faces and edges; others are skipped).
void read_element(Values& in, const Element& e, bool ascii, PlyMesh& mesh) {
  const Columns c = columns_of(in, e, ascii);
  if (c.is_vertex) mesh.vertices.reserve(static_cast<std::size_t>(e.count));
  if (c.is_face) mesh.faces.reserve(static_cast<std::size_t>(e.count));
  if (c.is_edge) mesh.edges.reserve(static_cast<std::size_t>(e.count));
  if (c.is_edge && c.apex >= 0) mesh.outline = true;
  std::vector<double> row(e.props.size());
  std::array<std::uint32_t, 3> face{};
  for (std::uint64_t k = 0; k < e.count; ++k) {
    for (std::size_t i = 0; i < e.props.size(); ++i) {
      const Property& p = e.props[i];
      if (!p.list) {
        row[i] = in.get(p.type);
        continue;
      }
      const double n = in.get(p.count_type);
      if (!(n >= 0 && n == std::floor(n))) in.fail("a list with a bad count");
      if (c.is_face && static_cast<int>(i) == c.list) {
        if (n != 3) in.fail("face " + count_text(k) + " is not a triangle");
        for (auto& corner : face)
          corner = index_of(in, in.get(p.type), mesh.vertices.size(), "a face");
      } else {
        for (double j = 0; j < n; ++j) in.get(p.type);
      }
    }
    store_item(in, c, k, row, face, mesh);
  }
}

}  // namespace

PlyMesh read_ply(const std::string& path) {
  const detail::MappedFile file(path);
  const auto* data = file.data();
  const std::size_t size = file.size();
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::size_t end_header = text.find("end_header");
  if (size < 4 || text.substr(0, 4) != "ply\n" || end_header == std::string_view::npos)
    throw InputError(path, "", "not a PLY file");
  std::size_t body = text.find('\n', end_header);
  if (body == std::string_view::npos) throw InputError(path, "header", "no data after the header");
  ++body;

  PlyMesh mesh;
  const Header header = read_header(path, text.substr(0, end_header), mesh);
  Values in(path, data + body, data + size, header.ascii);
  for (const Element& e : header.elements) read_element(in, e, header.ascii, mesh);
  return mesh;
}

}  // namespace tincdt::io
