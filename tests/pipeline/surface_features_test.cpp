// The surface-feature stage (pipeline/surface.hpp) on its own, with polygons that do what users
// do: clip and erase rings larger than the data, bow-ties, overlaps, rings
// wholly outside, 2D and 3D. The TIN must stay valid and inside its hull, the kept triangles must
// be exactly those inside the polygons by an even-odd test written here, and a 3D ring's z must
// reach the TIN only where the ring itself runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "delaunay/delaunay.hpp"
#include "pipeline/surface.hpp"
#include "predicates/predicates.hpp"
#include "support/errors.hpp"
#include "terrain/polygons.hpp"

namespace tincdt::pipeline::detail {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Rng {
  std::uint64_t state;
  double uniform(double lo, double hi) {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return lo + (hi - lo) * static_cast<double>(state >> 11) / 9007199254740992.0;
  }
};

// A jittered grid on [0, 100]^2 with its border straight (the hull is the square), z a tilted
// plane, so that the z of any point of the TIN is known.
double plane(double x, double y) {
  return 50 + 0.25 * x - 0.125 * y;
}

mesh::Triangulation grid_tin(Rng& rng, int n = 16) {
  std::vector<Point3> points;
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      double x = 100.0 * i / n, y = 100.0 * j / n;
      if (i > 0 && i < n) x += rng.uniform(-1.5, 1.5);
      if (j > 0 && j < n) y += rng.uniform(-1.5, 1.5);
      points.push_back({x, y, plane(x, y)});
    }
  return delaunay::triangulate(std::move(points)).tin;
}

using Ring = std::vector<Point3>;

// One polygon feature per entry, each a list of rings.
struct Job {
  explicit Job(mesh::Triangulation t) : tin(std::move(t)) {}
  mesh::Triangulation tin;
  SourceTable sources;
  SurfaceInput input;
  SurfaceResult result;
};

void run(Job& job, SourceKind kind, const std::vector<std::vector<Ring>>& features) {
  job.input.kind = kind;
  job.input.first_source = static_cast<std::uint32_t>(job.sources.size());
  const std::uint32_t file = job.sources.add_file("polygons.geojson");
  job.input.data.files = {"polygons.geojson"};
  for (std::size_t i = 0; i < features.size(); ++i) {
    io::ShapeFeature f;
    f.fid = static_cast<std::int64_t>(i);
    for (const Ring& r : features[i]) f.parts.push_back({r, true});
    job.sources.add(file, f.fid, kind, is_draped(kind, f));
    job.input.data.features.push_back(std::move(f));
  }
  job.result = insert_surface_features(job.tin, {&job.input}, job.sources, {},
                                       constraints::Restore::delaunay, nullptr);
}

// Even-odd, written here independently of terrain::PolygonIndex.
bool inside(const std::vector<std::vector<Ring>>& features, double x, double y) {
  for (const auto& rings : features) {
    bool in = false;
    for (const Ring& r : rings)
      for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++)
        if ((r[i].y > y) != (r[j].y > y) &&
            x < (r[j].x - r[i].x) * (y - r[i].y) / (r[j].y - r[i].y) + r[i].x)
          in = !in;
    if (in) return true;
  }
  return false;
}

double distance_to_rings(const std::vector<std::vector<Ring>>& features, double x, double y) {
  double d = std::numeric_limits<double>::infinity();
  for (const auto& rings : features)
    for (const Ring& r : rings)
      for (std::size_t i = 0, j = r.size() - 1; i < r.size(); j = i++) {
        const double dx = r[i].x - r[j].x, dy = r[i].y - r[j].y;
        const double t =
            std::clamp(((x - r[j].x) * dx + (y - r[j].y) * dy) / (dx * dx + dy * dy), 0.0, 1.0);
        d = std::min(d, std::hypot(r[j].x + t * dx - x, r[j].y + t * dy - y));
      }
  return d;
}

// Checks what every run must give: a valid TIN, every vertex in the square, and after clip or
// erase the kept triangles exactly those inside (or outside) the polygons, away from the rings.
void check(Job& job, SourceKind kind, const std::vector<std::vector<Ring>>& features,
           const std::string& what) {
  ASSERT_EQ(job.tin.validate(), "") << what;
  for (VertexId v = 0; v < job.tin.vertex_count(); ++v) {
    const Point2 p = job.tin.point(v);
    ASSERT_TRUE(p.x >= 0 && p.x <= 100 && p.y >= 0 && p.y <= 100)
        << what << ": vertex " << p.x << " " << p.y << " outside the data's hull";
  }
  if (kind != SourceKind::clip && kind != SourceKind::erase) return;
  const std::vector<terrain::Polygon> polygons = polygons_of(job.input.data);
  if (kind == SourceKind::clip) {
    terrain::remove_outside(job.tin, polygons);
  } else {
    terrain::remove_inside(job.tin, polygons);
  }
  double kept_area = 0;
  for (TriangleId t = 0; t < job.tin.triangle_slots(); ++t) {
    if (job.tin.is_ghost(t)) continue;
    const auto c = job.tin.triangle(t);
    const Point2 a = job.tin.point(c[0]), b = job.tin.point(c[1]), d = job.tin.point(c[2]);
    const double cx = (a.x + b.x + d.x) / 3, cy = (a.y + b.y + d.y) / 3;
    const double area = ((b.x - a.x) * (d.y - a.y) - (b.y - a.y) * (d.x - a.x)) / 2;
    if (job.tin.is_kept(t)) kept_area += area;
    if (distance_to_rings(features, cx, cy) < 1e-6) continue;  // a sliver along a ring
    const bool want = inside(features, cx, cy) == (kind == SourceKind::clip);
    ASSERT_EQ(job.tin.is_kept(t), want) << what << ": triangle with centroid " << cx << " " << cy;
  }
  // The kept area, by a grid of sample points classified by the test's own even-odd rule.
  double sampled = 0;
  constexpr int kSamples = 400;
  for (int i = 0; i < kSamples; ++i)
    for (int j = 0; j < kSamples; ++j) {
      const double x = (i + 0.5) * 100.0 / kSamples, y = (j + 0.5) * 100.0 / kSamples;
      sampled += inside(features, x, y) == (kind == SourceKind::clip);
    }
  sampled *= 100.0 * 100.0 / (kSamples * kSamples);
  EXPECT_NEAR(kept_area, sampled, 100.0) << what;  // 1% of the square: the sampling's error
}

Ring ring(std::initializer_list<std::array<double, 2>> xy, double z = kNaN) {
  Ring r;
  for (const auto& p : xy) r.push_back({p[0], p[1], z});
  return r;
}

// The example: a 3D boundary a little larger than the data. It crashed (a vertex
// inserted outside the hull flipped ghost edges into the vertex index); now it is cut to the
// hull, which follows the TIN's own hull vertices, so no vertex takes the ring's z.
TEST(SurfaceFeatures, A3dClipRingLargerThanTheDataIsCutToTheHull) {
  for (const SourceKind kind : {SourceKind::clip, SourceKind::erase}) {
    Rng rng{12345};
    Job job{grid_tin(rng)};
    const std::size_t vertices = job.tin.vertex_count();
    const std::vector<std::vector<Ring>> box = {
        {ring({{-10, -10}, {110, -10}, {110, 110}, {-10, 110}}, 800)}};
    run(job, kind, box);
    check(job, kind, box, "box");
    EXPECT_EQ(job.tin.vertex_count(), vertices);
    for (VertexId v = 0; v < job.tin.vertex_count(); ++v) EXPECT_NE(job.tin.z(v), 800);
    EXPECT_EQ(job.result.rings_cut, 1u);
  }
}

// Where a 3D ring crosses the hull, the new vertex's z is interpolated along the ring's segment.
TEST(SurfaceFeatures, A3dRingCrossingTheHullTakesItsOwnZThere) {
  Rng rng{777};
  Job job{grid_tin(rng)};
  Ring r = ring({{40.25, -20}, {60.25, -20}, {60.25, 50.5}, {40.25, 50.5}});
  for (Point3& p : r) p.z = 100 + p.y;  // z = 100 + y along every segment
  run(job, SourceKind::clip, {{r}});
  check(job, SourceKind::clip, {{r}}, "half out");
  int crossings = 0;
  for (VertexId v = 0; v < job.tin.vertex_count(); ++v) {
    const Point2 p = job.tin.point(v);
    if (p.y == 0 && (std::fabs(p.x - 40.25) < 1e-9 || std::fabs(p.x - 60.25) < 1e-9)) {
      ++crossings;
      EXPECT_NEAR(job.tin.z(v), 100.0, 1e-9);
    }
  }
  EXPECT_EQ(crossings, 2);
}

// A 2D ring partly outside was refused ("lies outside the TIN"); now it is cut and draped.
TEST(SurfaceFeatures, A2dRingPartlyOutsideIsCutAndDraped) {
  Rng rng{99};
  Job job{grid_tin(rng)};
  const std::vector<std::vector<Ring>> f = {{ring({{-30, 20.5}, {70.5, 20.5}, {70.5, 130}})}};
  run(job, SourceKind::erase, f);
  for (VertexId v = 0; v < job.tin.vertex_count(); ++v) {
    const Point2 p = job.tin.point(v);
    EXPECT_NEAR(job.tin.z(v), plane(p.x, p.y), 1e-9);
  }
  check(job, SourceKind::erase, f, "2D partly outside");
}

// Property: random rings over and around the data, any shape (bow-ties, overlaps, holes), 2D
// and 3D, as clip and as erase.
TEST(SurfaceFeatures, RandomRingsAroundTheDataKeepExactlyTheirInside) {
  Rng rng{2024};
  for (int trial = 0; trial < 60; ++trial) {
    const SourceKind kind = trial % 2 ? SourceKind::clip : SourceKind::erase;
    std::vector<std::vector<Ring>> features(1 + trial % 3);
    for (auto& rings : features) {
      const double z = trial % 4 < 2 ? kNaN : rng.uniform(0, 200);
      const int count = 1 + (trial / 3) % 2;
      for (int r = 0; r < count; ++r) {
        Ring ring;
        const int n = 3 + static_cast<int>(rng.uniform(0, 6));
        for (int k = 0; k < n; ++k)
          ring.push_back({rng.uniform(-40, 140), rng.uniform(-40, 140), z});
        rings.push_back(ring);
      }
    }
    Job job{grid_tin(rng, 10)};
    const std::string what = "trial " + std::to_string(trial);
    try {
      run(job, kind, features);
    } catch (const InputError& e) {
      // Only clip polygons that all miss the data may be refused.
      EXPECT_EQ(kind, SourceKind::clip) << what << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("wholly outside"), std::string::npos) << e.what();
      continue;
    }
    check(job, kind, features, what);
  }
}

TEST(SurfaceFeatures, DegenerateRingsAreRefusedOrLeftOut) {
  Rng rng{5};
  {
    Job job{grid_tin(rng)};  // all vertices on one line: no area, refused naming the feature
    const std::string e = test::error_of([&] {
      run(job, SourceKind::erase,
          {{ring({{10, 10}, {50, 50}, {90, 90}})}, {ring({{1, 1}, {5, 1}, {5, 5}})}});
    });
    EXPECT_NE(e.find("polygons.geojson: feature 0: ring 0 encloses no area"), std::string::npos)
        << e;
  }
  {
    Job job{grid_tin(rng)};  // an erase ring wholly outside: nothing to erase
    run(job, SourceKind::erase, {{ring({{120, 120}, {150, 120}, {150, 150}})}});
    EXPECT_EQ(job.result.rings_outside, 1u);
    check(job, SourceKind::erase, {{ring({{120, 120}, {150, 120}, {150, 150}})}}, "outside");
  }
  {
    Job job{grid_tin(rng)};  // clip rings that all miss the data: refused naming the file
    const std::string e = test::error_of([&] {
      run(job, SourceKind::clip, {{ring({{-50, 0}, {-10, 0}, {-10, 50}})}});
    });
    EXPECT_NE(e.find("polygons.geojson: the clip polygons lie wholly outside the TIN"),
              std::string::npos)
        << e;
  }
  {
    Job job{grid_tin(rng)};  // touching the hull from outside along an edge: no area inside
    run(job, SourceKind::erase, {{ring({{-20, 10}, {0, 10}, {0, 60}, {-20, 60}})}});
    EXPECT_EQ(job.result.rings_outside, 1u);
  }
}

// --replace on a 3D polygon outside the data named it a "2D polygon ring".
TEST(SurfaceFeatures, AReplaceRingOutsideTheDataIsNamedAsSuch) {
  Rng rng{6};
  Job job{grid_tin(rng)};
  const std::string e = test::error_of([&] {
    run(job, SourceKind::replace, {{ring({{10, 10}, {150, 10}, {10, 50}}, 70)}});
  });
  EXPECT_NE(e.find("feature 0: vertex (150.000, 10.000) lies outside the TIN: a replace polygon"),
            std::string::npos)
      << e;
  EXPECT_EQ(e.find("2D"), std::string::npos) << e;
}

}  // namespace
}  // namespace tincdt::pipeline::detail
