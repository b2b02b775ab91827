// ns per call of orient2d / incircle on the paths a Delaunay build takes: the inline filter on
// generic UTM points, and the exact fallback stages on degenerate inputs. One predicate call per
// benchmark iteration, cycling through a precomputed pool of cases (larger than the branch
// predictor can learn, small enough to stay in L1/L2).
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "predicates/exact_stages.hpp"
#include "predicates/predicates.hpp"

namespace {

using tincdt::Point2;
namespace predicates = tincdt::predicates;

constexpr std::size_t kPool = 4096;  // cases per benchmark, a power of two
constexpr double kEasting = 500000.0;
constexpr double kNorthing = 4000000.0;

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1p-53; }
  int integer(int low, int high) {
    return low + static_cast<int>(engine_() % static_cast<std::uint64_t>(high - low + 1));
  }

 private:
  std::mt19937_64 engine_;
};

using Triple = std::array<Point2, 3>;
using Quad = std::array<Point2, 4>;

std::vector<Quad> random_utm_quads() {
  Random random(1);
  std::vector<Quad> cases(kPool);
  for (Quad& q : cases) {
    for (Point2& p : q) p = {kEasting + 1000.0 * random.unit(), kNorthing + 1000.0 * random.unit()};
  }
  return cases;
}

// Whole-metre lattice points on one line.
std::vector<Quad> collinear_lattice() {
  Random random(2);
  std::vector<Quad> cases(kPool);
  for (Quad& q : cases) {
    const double x = kEasting + random.integer(0, 1000);
    const double y = kNorthing + random.integer(0, 1000);
    const int dx = random.integer(-5, 5);
    const int dy = random.integer(1, 5);
    for (Point2& p : q) {
      const int k = random.integer(-10, 10);
      p = {x + k * dx, y + k * dy};
    }
  }
  return cases;
}

// Four of the 24 lattice points on the circle of squared radius 325 around a lattice point.
std::vector<Quad> cocircular_lattice() {
  std::vector<Point2> circle;
  for (int x = -18; x <= 18; ++x) {
    for (int y = -18; y <= 18; ++y) {
      if (x * x + y * y == 325) circle.push_back({static_cast<double>(x), static_cast<double>(y)});
    }
  }
  Random random(3);
  std::vector<Quad> cases(kPool);
  for (Quad& q : cases) {
    const double cx = kEasting + random.integer(0, 1000);
    const double cy = kNorthing + random.integer(0, 1000);
    for (Point2& p : q) {
      const Point2 offset =
          circle[static_cast<std::size_t>(random.integer(0, static_cast<int>(circle.size()) - 1))];
      p = {cx + offset.x, cy + offset.y};
    }
  }
  return cases;
}

// Corners of rectangles with full-precision UTM coordinates: cocircular, exact differences of
// ~44 significant bits.
std::vector<Quad> cocircular_fractional() {
  Random random(4);
  std::vector<Quad> cases(kPool);
  for (Quad& q : cases) {
    const double x0 = kEasting + 1000.0 * random.unit(), x1 = kEasting + 1000.0 * random.unit();
    const double y0 = kNorthing + 1000.0 * random.unit(), y1 = kNorthing + 1000.0 * random.unit();
    q = {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
  }
  return cases;
}

// Rectangles straddling the origin: differences are inexact, so stage 2 (expansions of the raw
// coordinates) decides.
std::vector<Quad> cocircular_mixed_signs() {
  Random random(5);
  std::vector<Quad> cases(kPool);
  for (Quad& q : cases) {
    const double x0 = -random.unit(), x1 = random.unit();
    const double y0 = -random.unit(), y1 = random.unit();
    q = {{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
  }
  return cases;
}

// Through-origin collinear points of both signs (p, -2p, 4p): stage 2 for orient2d.
std::vector<Quad> collinear_mixed_signs() {
  Random random(6);
  std::vector<Quad> cases(kPool);
  for (Quad& q : cases) {
    const Point2 p{random.unit() - 0.5, random.unit() - 0.5};
    q = {{p, {-2 * p.x, -2 * p.y}, {4 * p.x, 4 * p.y}, p}};
  }
  return cases;
}

// Cocircular lattice points scaled to ~1e-300: products underflow, only stage 3 is exact.
std::vector<Quad> cocircular_tiny() {
  std::vector<Quad> cases = cocircular_lattice();
  for (Quad& q : cases) {
    for (Point2& p : q) p = {p.x * 0x1p-1020, p.y * 0x1p-1020};
  }
  return cases;
}

// Rectangles with a corner at the origin and sides 2^-40 and 2^40: exact differences spanning
// over 62 bits, so incircle stage 1b (expansions) decides.
std::vector<Quad> cocircular_wide_span() {
  Random random(7);
  std::vector<Quad> cases(kPool);
  for (Quad& q : cases) {
    const double w = (1.0 + random.unit()) * 0x1p-40, h = (1.0 + random.unit()) * 0x1p40;
    q = {{{0, 0}, {w, 0}, {w, h}, {0, h}}};
  }
  return cases;
}

// The predicate is a lambda so that the inline filter is inlined into the loop, as in real use.
template <class Predicate>
void run(benchmark::State& state, const std::vector<Quad>& cases, Predicate predicate) {
  std::size_t i = 0;
  int sum = 0;
  for (auto _ : state) {
    sum += predicate(cases[i]);
    i = (i + 1) & (kPool - 1);
  }
  benchmark::DoNotOptimize(sum);
  state.SetItemsProcessed(state.iterations());
}

const auto orient = [](const Quad& q) { return predicates::orient2d(q[0], q[1], q[2]); };
const auto in_circle = [](const Quad& q) { return predicates::incircle(q[0], q[1], q[2], q[3]); };

// Plain double determinant without the filter: the floor against which the filter's overhead
// shows. Not exact.
const auto orient_naive = [](const Quad& q) {
  const double det = (q[0].x - q[2].x) * (q[1].y - q[2].y) - (q[0].y - q[2].y) * (q[1].x - q[2].x);
  return (det > 0) - (det < 0);
};
const auto in_circle_naive = [](const Quad& q) {
  const double adx = q[0].x - q[3].x, ady = q[0].y - q[3].y;
  const double bdx = q[1].x - q[3].x, bdy = q[1].y - q[3].y;
  const double cdx = q[2].x - q[3].x, cdy = q[2].y - q[3].y;
  const double det = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy) +
                     (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy) +
                     (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
  return (det > 0) - (det < 0);
};

void BM_Orient2dNaiveDouble(benchmark::State& state) {
  run(state, random_utm_quads(), orient_naive);
}
void BM_Orient2dFilterRandomUtm(benchmark::State& state) {
  run(state, random_utm_quads(), orient);
}
void BM_Orient2dCollinearLattice(benchmark::State& state) {
  run(state, collinear_lattice(), orient);
}
void BM_Orient2dCollinearMixedSigns(benchmark::State& state) {
  run(state, collinear_mixed_signs(), orient);
}
void BM_IncircleNaiveDouble(benchmark::State& state) {
  run(state, random_utm_quads(), in_circle_naive);
}
void BM_IncircleFilterRandomUtm(benchmark::State& state) {
  run(state, random_utm_quads(), in_circle);
}
void BM_IncircleCocircularLattice(benchmark::State& state) {
  run(state, cocircular_lattice(), in_circle);
}
void BM_IncircleCocircularFractionalUtm(benchmark::State& state) {
  run(state, cocircular_fractional(), in_circle);
}
void BM_IncircleCocircularWideSpan(benchmark::State& state) {
  run(state, cocircular_wide_span(), in_circle);
}
void BM_IncircleCocircularMixedSigns(benchmark::State& state) {
  run(state, cocircular_mixed_signs(), in_circle);
}
void BM_IncircleCocircularTiny(benchmark::State& state) {
  run(state, cocircular_tiny(), in_circle);
}

BENCHMARK(BM_Orient2dNaiveDouble);
BENCHMARK(BM_Orient2dFilterRandomUtm);
BENCHMARK(BM_Orient2dCollinearLattice);
BENCHMARK(BM_Orient2dCollinearMixedSigns);
BENCHMARK(BM_IncircleNaiveDouble);
BENCHMARK(BM_IncircleFilterRandomUtm);
BENCHMARK(BM_IncircleCocircularLattice);
BENCHMARK(BM_IncircleCocircularFractionalUtm);
BENCHMARK(BM_IncircleCocircularWideSpan);
BENCHMARK(BM_IncircleCocircularMixedSigns);
BENCHMARK(BM_IncircleCocircularTiny);

}  // namespace

BENCHMARK_MAIN();
