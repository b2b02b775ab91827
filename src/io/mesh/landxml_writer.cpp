// LandXML 1.2 (http://www.landxml.org/schema/LandXML-1.2), the exchange format of civil-design
// software (Civil 3D, 12d, Trimble Business Center): one <Surface> whose <Definition
// surfType="TIN"> holds the vertices as <P id="n">northing easting elevation</P> (y x z, the
// order LandXML uses) and the triangles as <F>a b c</F> (1-based ids, counter-clockwise seen from
// above), and whose <SourceData><Breaklines> holds the constrained edges joined into polylines.
// <Units> follows the CRS's linear unit (metre, foot, US survey foot), <CoordinateSystem> names
// the CRS. Streamed through a BlockWriter, one element per line: no document is built in memory.
// LandXML has no place for an offset, and civil software expects real coordinates: a non-zero
// offset is refused (write_tin).
#include <algorithm>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <utility>
#include <vector>

#include "io/crs.hpp"
#include "io/gdal_support.hpp"
#include "io/mesh/writer_detail.hpp"

namespace tincdt::io::detail {
namespace {

std::string xml_escape(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        // Control characters are not allowed in XML 1.0 text: a blank instead.
        out += static_cast<unsigned char>(c) < 0x20 ? ' ' : c;
    }
  }
  return out;
}

// The <Units> element for the CRS's linear unit; metres when it is unknown or not linear.
std::string units_element(const std::string& path, const std::string& crs_wkt) {
  const char* metric =
      "<Units><Metric areaUnit=\"squareMeter\" linearUnit=\"meter\" volumeUnit=\"cubicMeter\" "
      "temperatureUnit=\"celsius\" pressureUnit=\"milliBars\"/></Units>\n";
  if (crs_wkt.empty()) return metric;
  const GdalQuiet quiet;
  const OGRSpatialReference srs = parse_crs(path, crs_wkt, "the CRS");
  if (!srs.IsProjected() && !srs.IsLocal()) return metric;
  const double metres = srs.GetLinearUnits(nullptr);
  const auto imperial = [](const char* unit) {
    return std::string("<Units><Imperial areaUnit=\"squareFoot\" linearUnit=\"") + unit +
           "\" volumeUnit=\"cubicFeet\" temperatureUnit=\"fahrenheit\" pressureUnit=\"inHG\"/>"
           "</Units>\n";
  };
  if (std::fabs(metres - 0.3048) < 1e-9) return imperial("foot");
  if (std::fabs(metres - 1200.0 / 3937.0) < 1e-9) return imperial("USSurveyFoot");
  return metric;
}

// <CoordinateSystem> with the CRS's name, EPSG code when known, and its WKT: OGC WKT 1, which
// the attribute is named after and civil software reads, or WKT 2 when WKT 1 cannot hold it.
std::string coordinate_system_element(const std::string& crs_wkt) {
  if (crs_wkt.empty()) return {};
  std::string name = crs_label(crs_wkt);
  std::string wkt = crs_wkt;
  {
    const GdalQuiet quiet;
    OGRSpatialReference srs = gis_order_srs();
    if (import_wkt(srs, crs_wkt)) {
      if (srs.GetName() != nullptr) name = srs.GetName();
      char* wkt1 = nullptr;
      const char* const wkt1_options[] = {"FORMAT=WKT1", nullptr};
      if (srs.exportToWkt(&wkt1, wkt1_options) == OGRERR_NONE && wkt1 != nullptr) wkt = wkt1;
      CPLFree(wkt1);
    }
  }
  std::string e = "<CoordinateSystem";
  if (!name.empty()) e += " name=\"" + xml_escape(name) + "\"";
  const std::string code = crs_code(crs_wkt);
  if (code.rfind("EPSG:", 0) == 0) e += " epsgCode=\"" + xml_escape(code.substr(5)) + "\"";
  e += " ogcWktCode=\"" + xml_escape(one_line(wkt)) + "\"/>\n";
  return e;
}

// "date=\"2024-05-01\" time=\"13:45:00\"", from SOURCE_DATE_EPOCH when set (reproducible builds'
// convention), else now, in UTC.
std::string date_time_attributes() {
  std::time_t now = std::time(nullptr);
  if (const char* epoch = std::getenv("SOURCE_DATE_EPOCH")) {
    char* end = nullptr;
    const long long v = std::strtoll(epoch, &end, 10);
    if (end != epoch && *end == '\0') now = static_cast<std::time_t>(v);
  }
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[64];
  std::strftime(text, sizeof text, "date=\"%Y-%m-%d\" time=\"%H:%M:%S\"", &utc);
  return text;
}

// The constrained edges of the written TIN joined into polylines of vertex ids: chains between
// vertices where they do not simply pass through (an end, or three or more edges meeting), then
// the closed loops left. Sorted half-edges instead of per-vertex arrays: memory in the number of
// constrained edges, not of vertices.
std::vector<std::vector<VertexId>> breaklines(const mesh::Triangulation& tin) {
  std::vector<std::pair<VertexId, VertexId>> half;  // both directions of every edge
  for_each_constrained_segment(tin, true, [&half](VertexId a, VertexId b) {
    half.emplace_back(a, b);
    half.emplace_back(b, a);
  });
  std::sort(half.begin(), half.end());
  std::vector<std::uint8_t> used(half.size(), 0);
  const auto first_of = [&half](VertexId v) {
    return static_cast<std::size_t>(
        std::lower_bound(half.begin(), half.end(), std::pair<VertexId, VertexId>{v, 0}) -
        half.begin());
  };
  const auto degree = [&](VertexId v) {
    std::size_t i = first_of(v), n = 0;
    while (i + n < half.size() && half[i + n].first == v) ++n;
    return n;
  };
  const auto mark = [&](std::size_t i) {
    used[i] = 1;
    const auto it = std::lower_bound(half.begin(), half.end(),
                                     std::pair<VertexId, VertexId>{half[i].second, half[i].first});
    used[static_cast<std::size_t>(it - half.begin())] = 1;
  };
  std::vector<std::vector<VertexId>> lines;
  const auto walk = [&](std::size_t i) {
    std::vector<VertexId> line{half[i].first};
    for (;;) {
      mark(i);
      const VertexId v = half[i].second;
      line.push_back(v);
      if (degree(v) != 2) break;
      std::size_t next = first_of(v);
      if (used[next]) ++next;
      if (used[next]) break;  // back at the start of a loop
      i = next;
    }
    lines.push_back(std::move(line));
  };
  for (std::size_t i = 0; i < half.size(); ++i)
    if (!used[i] && degree(half[i].first) != 2) walk(i);
  for (std::size_t i = 0; i < half.size(); ++i)
    if (!used[i]) walk(i);
  return lines;
}

void put_nez(BlockWriter& w, const Point3& p) {
  w.put_double(p.y);
  w.put(' ');
  w.put_double(p.x);
  w.put(' ');
  w.put_double(p.z);
}

}  // namespace

TinWriteStats write_landxml(OutputFile& out, const mesh::Triangulation& tin,
                            const TinWriteOptions& options) {
  const std::string& path = out.path();
  const TriangleCounts counts = count_triangles(tin);
  const VertexNumbering number(tin, counts.removed > 0);
  const std::size_t nv = number.count();
  if (nv < 3 || counts.kept == 0)
    throw OutputError(path, "", "LandXML needs a surface of at least one triangle");
  const std::string surface = std::filesystem::path(path).stem().string();

  BlockWriter w(out);
  w.put(std::string_view(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      "<LandXML xmlns=\"http://www.landxml.org/schema/LandXML-1.2\" "
      "xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" "
      "xsi:schemaLocation=\"http://www.landxml.org/schema/LandXML-1.2 "
      "http://www.landxml.org/schema/LandXML-1.2/LandXML-1.2.xsd\" version=\"1.2\" "));
  w.put(date_time_attributes());
  w.put(std::string_view(">\n"));
  w.put(units_element(path, options.crs_wkt));
  w.put(coordinate_system_element(options.crs_wkt));
  w.put(std::string_view("<Application name=\"tincdt\" manufacturer=\"tincdt\"/>\n<Surfaces>\n"));
  w.put("<Surface name=\"" + xml_escape(surface.empty() ? "TIN" : surface) + "\">\n");

  const std::vector<std::vector<VertexId>> lines = breaklines(tin);
  if (!lines.empty()) {
    w.put(std::string_view("<SourceData>\n<Breaklines>\n"));
    for (std::size_t i = 0; i < lines.size(); ++i) {
      w.put(std::string_view("<Breakline brkType=\"standard\" name=\""));
      w.put_uint(i + 1);
      w.put(std::string_view("\"><PntList3D>"));
      for (std::size_t k = 0; k < lines[i].size(); ++k) {
        if (k) w.put(' ');
        put_nez(w, shifted_vertex(path, tin, lines[i][k], options.offset));
      }
      w.put(std::string_view("</PntList3D></Breakline>\n"));
    }
    w.put(std::string_view("</Breaklines>\n</SourceData>\n"));
  }

  Progress progress(options.progress, "write", nv + counts.kept);
  std::uint64_t done = 0;
  w.put(std::string_view("<Definition surfType=\"TIN\">\n<Pnts>\n"));
  for (std::size_t i = 0; i < nv; ++i) {
    progress.tick(done++);
    w.put(std::string_view("<P id=\""));
    w.put_uint(i + 1);
    w.put(std::string_view("\">"));
    put_nez(w, shifted_vertex(path, tin, number.vertex(i), options.offset));
    w.put(std::string_view("</P>\n"));
  }
  w.put(std::string_view("</Pnts>\n<Faces>\n"));
  tin.for_each_triangle([&](TriangleId, const std::array<VertexId, 3>& c) {
    progress.tick(done++);
    w.put(std::string_view("<F>"));
    w.put_uint(std::uint64_t{number(c[0])} + 1);
    w.put(' ');
    w.put_uint(std::uint64_t{number(c[1])} + 1);
    w.put(' ');
    w.put_uint(std::uint64_t{number(c[2])} + 1);
    w.put(std::string_view("</F>\n"));
  });
  w.put(std::string_view("</Faces>\n</Definition>\n</Surface>\n</Surfaces>\n</LandXML>\n"));
  w.flush();
  progress.finish();
  return {nv, counts.kept, 0};
}

}  // namespace tincdt::io::detail
