// Benchmark driver in the format of ../shared/bench (bench_run.py): times tincdt's Delaunay
// stage on points.bin, or its whole CDT on pslg.txt, excluding file parsing, and prints
//   RESULT tool=tincdt mode=dt n=... tri_s=... triangles=... valid=...
// Usage: tincdt_tin_driver dt POINTS.bin [--check] [--threads N]
//        tincdt_tin_driver cdt PSLG.txt [--check] [--threads N]
// --threads: as tincdt's (0, the default: every core).
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "constraints/constraints.hpp"
#include "delaunay/delaunay.hpp"

namespace {

double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<tincdt::Point3> read_points_bin(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<tincdt::Point3> points(bytes.size() / sizeof(tincdt::Point3));
  std::memcpy(points.data(), bytes.data(), points.size() * sizeof(tincdt::Point3));
  return points;
}

// pslg.txt: "nv ns", nv lines "x y z", ns lines "i j" (0-based).
void read_pslg(const std::string& path, std::vector<tincdt::Point3>& points,
               std::vector<tincdt::constraints::Segment>& segments) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const char* c = text.data();
  const char* end = c + text.size();
  auto next = [&](auto& value) {
    while (c < end && (*c == ' ' || *c == '\n' || *c == '\r' || *c == '\t')) ++c;
    c = std::from_chars(c, end, value).ptr;
  };
  std::size_t nv = 0, ns = 0;
  next(nv);
  next(ns);
  points.resize(nv);
  for (auto& p : points) {
    next(p.x);
    next(p.y);
    next(p.z);
  }
  segments.resize(ns);
  for (std::uint32_t i = 0; i < ns; ++i) {
    next(segments[i].a);
    next(segments[i].b);
    segments[i].source = i;
  }
}

int run_cdt(const std::string& path, bool check, unsigned threads) {
  std::vector<tincdt::Point3> points;
  std::vector<tincdt::constraints::Segment> segments;
  read_pslg(path, points, segments);
  const std::size_t n = points.size();
  const double t0 = now_s();
  tincdt::delaunay::DelaunayResult r = tincdt::delaunay::triangulate(
      std::move(points), {.keep_point_map = true, .threads = threads});
  const double t1 = now_s();
  for (auto& s : segments) {
    s.a = r.vertex_of_point[s.a];
    s.b = r.vertex_of_point[s.b];
  }
  const tincdt::constraints::ConstraintResult c =
      tincdt::constraints::insert_constraints(r.tin, segments);
  const double t2 = now_s();
  std::size_t constrained = 0;
  r.tin.for_each_constrained_edge([&](tincdt::EdgeId) { ++constrained; });
  const std::string problem = check ? r.tin.validate() : "";
  std::printf(
      "RESULT tool=tincdt mode=cdt n=%zu points_s=%.4f constraints_s=%.4f tri_s=%.4f "
      "triangles=%zu constrained_edges=%zu flips_insertion=%llu flips_restoration=%llu "
      "valid=%s\n",
      n, t1 - t0, t2 - t1, t2 - t0, r.tin.triangle_count(), constrained,
      static_cast<unsigned long long>(c.flips_insertion),
      static_cast<unsigned long long>(c.flips_restoration),
      check ? (problem.empty() ? "yes" : problem.c_str()) : "unchecked");
  return problem.empty() ? 0 : 1;
}

}  // namespace

int main(int argc, char** argv) {
  bool check = false, usage = argc < 3;
  unsigned threads = 0;
  for (int i = 3; i < argc && !usage; ++i) {
    if (std::strcmp(argv[i], "--check") == 0) {
      check = true;
    } else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) {
      threads = static_cast<unsigned>(std::strtoul(argv[++i], nullptr, 10));
    } else {
      usage = true;
    }
  }
  if (usage || (std::strcmp(argv[1], "dt") != 0 && std::strcmp(argv[1], "cdt") != 0)) {
    std::fprintf(stderr, "usage: %s dt POINTS.bin | cdt PSLG.txt [--check] [--threads N]\n",
                 argv[0]);
    return 2;
  }
  if (std::strcmp(argv[1], "cdt") == 0) return run_cdt(argv[2], check, threads);
  std::vector<tincdt::Point3> points = read_points_bin(argv[2]);
  const std::size_t n = points.size();
  const double t0 = now_s();
  tincdt::delaunay::DelaunayResult r =
      tincdt::delaunay::triangulate(std::move(points), {.threads = threads});
  const double t1 = now_s();
  const std::string problem = check ? r.tin.validate() : "";
  std::printf(
      "RESULT tool=tincdt mode=dt n=%zu tri_s=%.4f vertices=%zu triangles=%zu "
      "tin_bytes_per_vertex=%.1f flips=%llu valid=%s\n",
      n, t1 - t0, r.tin.vertex_count(), r.tin.triangle_count(),
      static_cast<double>(r.tin.memory_bytes()) / static_cast<double>(r.tin.vertex_count()),
      static_cast<unsigned long long>(r.flips),
      check ? (problem.empty() ? "yes" : problem.c_str()) : "unchecked");
  return problem.empty() ? 0 : 1;
}
