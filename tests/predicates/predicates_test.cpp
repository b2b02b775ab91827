// Exact predicates against an independent reference: every double is an integer times a power
// of two, so after scaling all coordinates of a case by one common power of two the
// determinants are integer polynomials, evaluated here with a small arbitrary-precision integer.
// Each case also checks every exact stage on its own and the permutation symmetries.
#include "predicates/predicates.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <limits>
#include <random>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "predicates/exact_stages.hpp"

namespace tincdt::predicates {
namespace {

// ---------------------------------------------------------------------------------------------
// Reference: signed arbitrary-precision integers, magnitude in 32-bit limbs, little-endian.

class BigInt {
 public:
  BigInt() = default;
  BigInt(std::uint64_t magnitude, bool negative) : negative_(negative) {
    while (magnitude != 0) {
      limbs_.push_back(static_cast<std::uint32_t>(magnitude & 0xffffffffu));
      magnitude >>= 32;
    }
    normalize();
  }

  int sign() const { return limbs_.empty() ? 0 : (negative_ ? -1 : 1); }

  BigInt shifted_left(int bits) const {
    BigInt result;
    result.negative_ = negative_;
    result.limbs_.assign(static_cast<std::size_t>(bits / 32), 0u);
    const int bit = bits % 32;
    std::uint32_t carry = 0;
    for (const std::uint32_t limb : limbs_) {
      result.limbs_.push_back(bit == 0 ? limb : ((limb << bit) | carry));
      carry = bit == 0 ? 0u : limb >> (32 - bit);
    }
    result.limbs_.push_back(carry);
    result.normalize();
    return result;
  }

  friend BigInt operator-(BigInt value) {
    value.negative_ = !value.negative_;
    value.normalize();
    return value;
  }

  friend BigInt operator+(const BigInt& a, const BigInt& b) {
    BigInt result;
    if (a.negative_ == b.negative_) {
      result.limbs_ = add_magnitudes(a.limbs_, b.limbs_);
      result.negative_ = a.negative_;
    } else if (compare_magnitudes(a.limbs_, b.limbs_) >= 0) {
      result.limbs_ = subtract_magnitudes(a.limbs_, b.limbs_);
      result.negative_ = a.negative_;
    } else {
      result.limbs_ = subtract_magnitudes(b.limbs_, a.limbs_);
      result.negative_ = b.negative_;
    }
    result.normalize();
    return result;
  }

  friend BigInt operator-(const BigInt& a, const BigInt& b) { return a + (-b); }

  friend BigInt operator*(const BigInt& a, const BigInt& b) {
    BigInt result;
    result.limbs_.assign(a.limbs_.size() + b.limbs_.size(), 0u);
    for (std::size_t i = 0; i < a.limbs_.size(); ++i) {
      std::uint64_t carry = 0;
      for (std::size_t j = 0; j < b.limbs_.size(); ++j) {
        const std::uint64_t t =
            static_cast<std::uint64_t>(a.limbs_[i]) * b.limbs_[j] + result.limbs_[i + j] + carry;
        result.limbs_[i + j] = static_cast<std::uint32_t>(t & 0xffffffffu);
        carry = t >> 32;
      }
      result.limbs_[i + b.limbs_.size()] = static_cast<std::uint32_t>(carry);
    }
    result.negative_ = a.negative_ != b.negative_;
    result.normalize();
    return result;
  }

  friend bool operator==(const BigInt& a, const BigInt& b) {
    return a.negative_ == b.negative_ && a.limbs_ == b.limbs_;
  }

 private:
  using Limbs = std::vector<std::uint32_t>;

  void normalize() {
    while (!limbs_.empty() && limbs_.back() == 0) limbs_.pop_back();
    if (limbs_.empty()) negative_ = false;
  }

  static int compare_magnitudes(const Limbs& a, const Limbs& b) {
    if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
    for (std::size_t i = a.size(); i > 0; --i) {
      if (a[i - 1] != b[i - 1]) return a[i - 1] < b[i - 1] ? -1 : 1;
    }
    return 0;
  }

  static Limbs add_magnitudes(const Limbs& a, const Limbs& b) {
    Limbs sum(std::max(a.size(), b.size()) + 1, 0u);
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i + 1 < sum.size(); ++i) {
      carry += (i < a.size() ? a[i] : 0u);
      carry += (i < b.size() ? b[i] : 0u);
      sum[i] = static_cast<std::uint32_t>(carry & 0xffffffffu);
      carry >>= 32;
    }
    sum.back() = static_cast<std::uint32_t>(carry);
    return sum;
  }

  // |a| >= |b|.
  static Limbs subtract_magnitudes(const Limbs& a, const Limbs& b) {
    Limbs difference(a.size(), 0u);
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      std::int64_t t = static_cast<std::int64_t>(a[i]) - borrow -
                       static_cast<std::int64_t>(i < b.size() ? b[i] : 0u);
      borrow = t < 0 ? 1 : 0;
      if (t < 0) t += std::int64_t{1} << 32;
      difference[i] = static_cast<std::uint32_t>(t);
    }
    return difference;
  }

  Limbs limbs_;
  bool negative_ = false;
};

// The coordinates of one case as integers in units of their smallest power of two.
template <std::size_t kCount>
std::array<BigInt, kCount> exact_integers(const std::array<double, kCount>& values) {
  std::array<std::int64_t, kCount> mantissas{};
  std::array<int, kCount> exponents{};
  int lowest = std::numeric_limits<int>::max();
  for (std::size_t i = 0; i < kCount; ++i) {
    if (values[i] == 0.0) continue;
    int exponent = 0;
    const double fraction = std::frexp(values[i], &exponent);  // in [0.5, 1): 53 bits
    mantissas[i] = static_cast<std::int64_t>(std::ldexp(fraction, 53));
    exponents[i] = exponent - 53;
    lowest = std::min(lowest, exponents[i]);
  }
  std::array<BigInt, kCount> result;
  for (std::size_t i = 0; i < kCount; ++i) {
    if (mantissas[i] == 0) continue;
    const bool negative = mantissas[i] < 0;
    const auto magnitude = static_cast<std::uint64_t>(negative ? -mantissas[i] : mantissas[i]);
    result[i] = BigInt(magnitude, negative).shifted_left(exponents[i] - lowest);
  }
  return result;
}

// | bx-ax  by-ay ; cx-ax  cy-ay |
int reference_orient2d(Point2 a, Point2 b, Point2 c) {
  const auto [ax, ay, bx, by, cx, cy] = exact_integers(std::array{a.x, a.y, b.x, b.y, c.x, c.y});
  return ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax)).sign();
}

// | adx ady adx^2+ady^2 ; bdx bdy ... ; cdx cdy ... |, expanded along the first column.
int reference_incircle(Point2 a, Point2 b, Point2 c, Point2 d) {
  const auto [ax, ay, bx, by, cx, cy, dx, dy] =
      exact_integers(std::array{a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y});
  const BigInt adx = ax - dx, ady = ay - dy;
  const BigInt bdx = bx - dx, bdy = by - dy;
  const BigInt cdx = cx - dx, cdy = cy - dy;
  const BigInt alift = adx * adx + ady * ady;
  const BigInt blift = bdx * bdx + bdy * bdy;
  const BigInt clift = cdx * cdx + cdy * cdy;
  const BigInt det = adx * (bdy * clift - blift * cdy) - bdx * (ady * clift - alift * cdy) +
                     cdx * (ady * blift - alift * bdy);
  return det.sign();
}

// ---------------------------------------------------------------------------------------------
// Checking one case.

std::string describe(Point2 p) {
  char text[96];
  std::snprintf(text, sizeof text, "(%a, %a)", p.x, p.y);
  return text;
}

// What a group of cases exercised, so that tests can assert they hit the paths they aim at.
struct Coverage {
  int cases = 0;
  int zero = 0;                // exactly degenerate: the filter can never decide these
  int exact_differences = 0;   // stage 1 applicable
  int as_integers = 0;         // stage 1a applicable (incircle only)
  int as_small_integers = 0;   // its first try, the exact double evaluation, applicable
  int expansions = 0;          // stage 2 applicable
  int wide_integers_only = 0;  // neither: only stage 3
};

void count_stages(Coverage& coverage, int expected, int stage1, int stage2,
                  int stage1a = detail::kNotApplicable,
                  int stage1a_small = detail::kNotApplicable) {
  ++coverage.cases;
  if (stage1a != detail::kNotApplicable) ++coverage.as_integers;
  if (stage1a_small != detail::kNotApplicable) ++coverage.as_small_integers;
  if (expected == 0) ++coverage.zero;
  if (stage1 != detail::kNotApplicable) ++coverage.exact_differences;
  if (stage2 != detail::kNotApplicable) ++coverage.expansions;
  if (stage1 == detail::kNotApplicable && stage2 == detail::kNotApplicable) {
    ++coverage.wide_integers_only;
  }
}

void expect_sign(std::string& problems, const char* what, int got, int expected) {
  if (got != expected) {
    problems += std::string(" ") + what + "=" + std::to_string(got) + " (want " +
                std::to_string(expected) + ")";
  }
}

::testing::AssertionResult orient2d_is_exact(Point2 a, Point2 b, Point2 c, Coverage& coverage) {
  const int expected = reference_orient2d(a, b, c);
  std::string problems;
  expect_sign(problems, "orient2d", orient2d(a, b, c), expected);
  const int stage1 = detail::orient2d_from_exact_differences(a, b, c);
  const int stage2 = detail::orient2d_by_expansions(a, b, c);
  if (stage1 != detail::kNotApplicable) expect_sign(problems, "stage1", stage1, expected);
  if (stage2 != detail::kNotApplicable) expect_sign(problems, "stage2", stage2, expected);
  expect_sign(problems, "stage3", detail::orient2d_by_wide_integers(a, b, c), expected);
  expect_sign(problems, "exact", detail::orient2d_exact(a, b, c), expected);
  // Cyclic shifts keep the sign, a transposition flips it.
  expect_sign(problems, "orient2d(b,c,a)", orient2d(b, c, a), expected);
  expect_sign(problems, "orient2d(c,a,b)", orient2d(c, a, b), expected);
  expect_sign(problems, "orient2d(b,a,c)", orient2d(b, a, c), -expected);
  expect_sign(problems, "orient2d(a,c,b)", orient2d(a, c, b), -expected);
  count_stages(coverage, expected, stage1, stage2);
  if (problems.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "a=" << describe(a) << " b=" << describe(b) << " c=" << describe(c) << ":" << problems;
}

::testing::AssertionResult incircle_is_exact(Point2 a, Point2 b, Point2 c, Point2 d,
                                             Coverage& coverage) {
  const int expected = reference_incircle(a, b, c, d);
  std::string problems;
  expect_sign(problems, "incircle", incircle(a, b, c, d), expected);
  const int stage1 = detail::incircle_from_exact_differences(a, b, c, d);
  const int stage1a = detail::incircle_from_exact_differences_as_integers(a, b, c, d);
  const int stage1a_small = detail::incircle_from_exact_differences_as_small_integers(a, b, c, d);
  const int stage1b = detail::incircle_from_exact_differences_as_expansions(a, b, c, d);
  const int stage2 = detail::incircle_by_expansions(a, b, c, d);
  if (stage1 != detail::kNotApplicable) expect_sign(problems, "stage1", stage1, expected);
  if (stage1a != detail::kNotApplicable) expect_sign(problems, "stage1a", stage1a, expected);
  if (stage1a_small != detail::kNotApplicable) {
    expect_sign(problems, "stage1a small", stage1a_small, expected);
    // Small integers are integers below 2^62 too.
    if (stage1a == detail::kNotApplicable) problems += " stage1a small applies where 1a does not";
  }
  // 1b applies exactly where 1 does (1a is a shortcut inside it).
  if ((stage1b == detail::kNotApplicable) != (stage1 == detail::kNotApplicable)) {
    problems += " stage1b applicability differs from stage1";
  } else if (stage1b != detail::kNotApplicable) {
    expect_sign(problems, "stage1b", stage1b, expected);
  }
  if (stage2 != detail::kNotApplicable) expect_sign(problems, "stage2", stage2, expected);
  expect_sign(problems, "stage3", detail::incircle_by_wide_integers(a, b, c, d), expected);
  expect_sign(problems, "exact", detail::incircle_exact(a, b, c, d), expected);
  // Invariant under cyclic rotation of a, b, c; swapping two of them flips the sign. The
  // determinant is alternating in all four points, so swapping d with one of them flips it too.
  expect_sign(problems, "incircle(b,c,a,d)", incircle(b, c, a, d), expected);
  expect_sign(problems, "incircle(c,a,b,d)", incircle(c, a, b, d), expected);
  expect_sign(problems, "incircle(b,a,c,d)", incircle(b, a, c, d), -expected);
  expect_sign(problems, "incircle(a,c,b,d)", incircle(a, c, b, d), -expected);
  expect_sign(problems, "incircle(c,b,a,d)", incircle(c, b, a, d), -expected);
  expect_sign(problems, "incircle(a,b,d,c)", incircle(a, b, d, c), -expected);
  count_stages(coverage, expected, stage1, stage2, stage1a, stage1a_small);
  if (problems.empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure()
         << "a=" << describe(a) << " b=" << describe(b) << " c=" << describe(c)
         << " d=" << describe(d) << ":" << problems;
}

// Stops a broken build from printing thousands of failures.
constexpr int kMaxReportedFailures = 10;

struct Triple {
  Point2 a, b, c;
};
struct Quad {
  Point2 a, b, c, d;
};

Coverage check_all(const std::vector<Triple>& cases) {
  Coverage coverage;
  int failures = 0;
  for (const Triple& t : cases) {
    const auto result = orient2d_is_exact(t.a, t.b, t.c, coverage);
    EXPECT_TRUE(result);
    if (!result && ++failures >= kMaxReportedFailures) break;
  }
  return coverage;
}

Coverage check_all(const std::vector<Quad>& cases) {
  Coverage coverage;
  int failures = 0;
  for (const Quad& q : cases) {
    const auto result = incircle_is_exact(q.a, q.b, q.c, q.d, coverage);
    EXPECT_TRUE(result);
    if (!result && ++failures >= kMaxReportedFailures) break;
  }
  return coverage;
}

// ---------------------------------------------------------------------------------------------
// Deterministic case generation (own conversions, so the cases do not depend on the standard
// library's distribution algorithms).

class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  // Uniform in [0, 1) with 53 random bits.
  double unit() { return static_cast<double>(engine_() >> 11) * 0x1p-53; }
  double uniform(double low, double high) { return low + (high - low) * unit(); }
  // Uniform integer in [low, high].
  int integer(int low, int high) {
    const auto range = static_cast<std::uint64_t>(std::int64_t{high} - low + 1);
    return static_cast<int>(low + static_cast<std::int64_t>(engine_() % range));
  }
  bool coin() { return (engine_() & 1u) != 0; }

 private:
  std::mt19937_64 engine_;
};

// v moved by `ulps` representable doubles (negative: downwards).
double nudge(double v, int ulps) {
  const double toward =
      ulps < 0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  for (int i = 0; i < std::abs(ulps); ++i) v = std::nextafter(v, toward);
  return v;
}

Point2 scaled(Point2 p, int power_of_two) {
  return {std::ldexp(p.x, power_of_two), std::ldexp(p.y, power_of_two)};
}

// UTM-like magnitudes: eastings near 500 km, northings near 4000 km.
constexpr double kEasting = 500000.0;
constexpr double kNorthing = 4000000.0;

Point2 random_utm(Random& random, double extent) {
  return {kEasting + random.uniform(0.0, extent), kNorthing + random.uniform(0.0, extent)};
}

std::vector<Triple> random_triples(std::uint64_t seed, int count, double low, double high) {
  Random random(seed);
  std::vector<Triple> cases;
  for (int i = 0; i < count; ++i) {
    auto point = [&] { return Point2{random.uniform(low, high), random.uniform(low, high)}; };
    cases.push_back({point(), point(), point()});
  }
  return cases;
}

std::vector<Quad> random_quads(std::uint64_t seed, int count, double low, double high) {
  Random random(seed);
  std::vector<Quad> cases;
  for (int i = 0; i < count; ++i) {
    auto point = [&] { return Point2{random.uniform(low, high), random.uniform(low, high)}; };
    cases.push_back({point(), point(), point(), point()});
  }
  return cases;
}

// c on (or as near as doubles allow to) the line through a and b, then moved by -2..2 ulps in
// x and in y: 25 cases per line.
void add_nudged(std::vector<Triple>& cases, Point2 a, Point2 b, Point2 on_line) {
  for (int nx = -2; nx <= 2; ++nx) {
    for (int ny = -2; ny <= 2; ++ny) {
      cases.push_back({a, b, {nudge(on_line.x, nx), nudge(on_line.y, ny)}});
    }
  }
}

// Lines through two random UTM points. For t = -1, 2, 3 the point a + t (b - a) is computed
// exactly (Sterbenz differences, same binade), so it is exactly collinear before the nudges.
std::vector<Triple> near_collinear_utm(std::uint64_t seed, int lines) {
  Random random(seed);
  std::vector<Triple> cases;
  for (int i = 0; i < lines; ++i) {
    const Point2 a = random_utm(random, 1000.0);
    const Point2 b = random_utm(random, 1000.0);
    const std::array<double, 4> choices{-1.0, 2.0, 3.0, random.uniform(-1.0, 2.0)};
    const double t = choices[static_cast<std::size_t>(i % 4)];
    add_nudged(cases, a, b, {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
  }
  return cases;
}

// Exactly collinear lattice points (whole metres at UTM offsets), and each nudged by one ulp.
std::vector<Triple> collinear_lattice_utm(std::uint64_t seed, int count) {
  Random random(seed);
  std::vector<Triple> cases;
  for (int i = 0; i < count; ++i) {
    const Point2 origin{kEasting + random.integer(0, 1000), kNorthing + random.integer(0, 1000)};
    const int dx = random.integer(-7, 7);
    const int dy = random.integer(-7, 7);
    auto along = [&](int k) { return Point2{origin.x + k * dx, origin.y + k * dy}; };
    const Point2 a = along(random.integer(-20, 20));
    const Point2 b = along(random.integer(-20, 20));
    const Point2 c = along(random.integer(-20, 20));
    cases.push_back({a, b, c});
    const int ulps = random.coin() ? 1 : -1;
    if (random.coin()) {
      cases.push_back({a, b, {nudge(c.x, ulps), c.y}});
    } else {
      cases.push_back({{a.x, nudge(a.y, ulps)}, b, c});
    }
  }
  return cases;
}

// Lattice points on circles: all integer points at squared distance r2 from an integer centre.
std::vector<std::pair<int, int>> lattice_circle(int r2) {
  std::vector<std::pair<int, int>> points;
  for (int x = -100; x <= 100; ++x) {
    for (int y = -100; y <= 100; ++y) {
      if (x * x + y * y == r2) points.emplace_back(x, y);
    }
  }
  return points;
}

// Four points of one lattice circle at UTM offsets (exactly cocircular), and variants with one
// coordinate nudged by one ulp (just inside or just outside).
std::vector<Quad> cocircular_lattice_utm(std::uint64_t seed, int count) {
  Random random(seed);
  const std::array<int, 5> radii_squared{25, 65, 325, 625, 1105};  // many lattice points each
  std::vector<std::vector<std::pair<int, int>>> circles;
  for (const int r2 : radii_squared) circles.push_back(lattice_circle(r2));
  std::vector<Quad> cases;
  for (int i = 0; i < count; ++i) {
    const auto& circle = circles[static_cast<std::size_t>(random.integer(0, 4))];
    const double cx = kEasting + random.integer(0, 5000);
    const double cy = kNorthing + random.integer(0, 5000);
    std::array<Point2, 4> p;
    for (Point2& point : p) {
      const auto [x, y] =
          circle[static_cast<std::size_t>(random.integer(0, static_cast<int>(circle.size()) - 1))];
      point = {cx + x, cy + y};
    }
    cases.push_back({p[0], p[1], p[2], p[3]});
    Point2& moved = p[static_cast<std::size_t>(random.integer(0, 3))];
    double& coordinate = random.coin() ? moved.x : moved.y;
    coordinate = nudge(coordinate, random.coin() ? 1 : -1);
    cases.push_back({p[0], p[1], p[2], p[3]});
  }
  return cases;
}

// Cells and small rectangles of 1 m and 0.1 m UTM lattices: the corners of a rectangle are
// exactly cocircular whatever its (exact) coordinates.
std::vector<Quad> grid_quads_utm(std::uint64_t seed, int count) {
  Random random(seed);
  std::vector<Quad> cases;
  for (int i = 0; i < count; ++i) {
    const double spacing = random.coin() ? 1.0 : 0.1;
    const double x0 = kEasting + spacing * random.integer(0, 100000);
    const double y0 = kNorthing + spacing * random.integer(0, 100000);
    const double x1 = x0 + spacing * random.integer(1, 3);
    const double y1 = y0 + spacing * random.integer(1, 3);
    std::array<Point2, 4> corners{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
    // A random corner order: orientation of the first three varies.
    for (std::size_t k = 3; k > 0; --k) {
      std::swap(corners[k],
                corners[static_cast<std::size_t>(random.integer(0, static_cast<int>(k)))]);
    }
    cases.push_back({corners[0], corners[1], corners[2], corners[3]});
  }
  return cases;
}

// Rectangles and isosceles trapezoids with fractional UTM coordinates: exactly cocircular,
// with exact differences of up to ~40 significant bits (stage 1 with long expansions).
std::vector<Quad> cocircular_fractional_utm(std::uint64_t seed, int count) {
  Random random(seed);
  std::vector<Quad> cases;
  for (int i = 0; i < count; ++i) {
    std::array<Point2, 4> p;
    if (random.coin()) {
      const Point2 low = random_utm(random, 1000.0);
      const Point2 high = random_utm(random, 1000.0);
      p = {{{low.x, low.y}, {high.x, low.y}, {high.x, high.y}, {low.x, high.y}}};
    } else {
      // Symmetric about x = axis; every value a multiple of 2^-20, so the sums are exact.
      auto fixed = [&](double v) { return std::ldexp(std::round(std::ldexp(v, 20)), -20); };
      const double axis = fixed(kEasting + random.uniform(0.0, 1000.0));
      const double w1 = fixed(random.uniform(0.0, 50.0));
      const double w2 = fixed(random.uniform(0.0, 50.0));
      const double y1 = fixed(kNorthing + random.uniform(0.0, 1000.0));
      const double y2 = fixed(kNorthing + random.uniform(0.0, 1000.0));
      p = {{{axis - w1, y1}, {axis + w1, y1}, {axis + w2, y2}, {axis - w2, y2}}};
    }
    for (std::size_t k = 3; k > 0; --k) {
      std::swap(p[k], p[static_cast<std::size_t>(random.integer(0, static_cast<int>(k)))]);
    }
    cases.push_back({p[0], p[1], p[2], p[3]});
    Point2& moved = p[static_cast<std::size_t>(random.integer(0, 3))];
    moved.y = nudge(moved.y, random.coin() ? 1 : -1);
    cases.push_back({p[0], p[1], p[2], p[3]});
  }
  return cases;
}

// Degenerate configurations around the origin with coordinates of both signs: differences
// are mostly not exact doubles, so stage 1 does not apply and stage 2 must decide. Half the
// lines pass through the origin, with points p * +-2^k on them (exactly collinear).
std::vector<Triple> near_collinear_mixed_signs(std::uint64_t seed, int lines) {
  Random random(seed);
  std::vector<Triple> cases;
  for (int i = 0; i < lines; ++i) {
    const Point2 p{random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0)};
    if (i % 2 == 0) {
      auto on_line = [&] {
        const Point2 q = scaled(p, random.integer(-3, 3));
        return random.coin() ? q : Point2{-q.x, -q.y};
      };
      const Point2 a = on_line();
      const Point2 b = on_line();
      add_nudged(cases, a, b, on_line());
    } else {
      const Point2 b{random.uniform(-1.0, 1.0), random.uniform(-1.0, 1.0)};
      const double t = random.uniform(-1.0, 2.0);
      add_nudged(cases, p, b, {p.x + t * (b.x - p.x), p.y + t * (b.y - p.y)});
    }
  }
  return cases;
}

std::vector<Quad> cocircular_mixed_signs(std::uint64_t seed, int count) {
  Random random(seed);
  std::vector<Quad> cases;
  for (int i = 0; i < count; ++i) {
    const double x0 = random.uniform(-1.0, 0.0), x1 = random.uniform(0.0, 1.0);
    const double y0 = random.uniform(-1.0, 0.0), y1 = random.uniform(0.0, 1.0);
    std::array<Point2, 4> p{{{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}};
    cases.push_back({p[0], p[1], p[2], p[3]});
    cases.push_back({p[2], p[0], p[3], p[1]});
    p[1].x = nudge(p[1].x, random.coin() ? 1 : -1);
    cases.push_back({p[0], p[1], p[2], p[3]});
  }
  return cases;
}

template <class Case>
std::vector<Case> scaled_cases(const std::vector<Case>& cases, int power_of_two) {
  std::vector<Case> result = cases;
  for (Case& c : result) {
    if constexpr (std::is_same_v<Case, Triple>) {
      c = {scaled(c.a, power_of_two), scaled(c.b, power_of_two), scaled(c.c, power_of_two)};
    } else {
      c = {scaled(c.a, power_of_two), scaled(c.b, power_of_two), scaled(c.c, power_of_two),
           scaled(c.d, power_of_two)};
    }
  }
  return result;
}

bool all_finite(std::initializer_list<Point2> points) {
  return std::all_of(points.begin(), points.end(),
                     [](Point2 p) { return std::isfinite(p.x) && std::isfinite(p.y); });
}

// Any finite double: random sign, exponent and mantissa, subnormals and zeros included, and
// short mantissas (small integers times 2^k) that reach the ends of the exponent range.
double random_finite(Random& random) {
  const int pick = random.integer(0, 19);
  double magnitude = 0.0;
  if (pick <= 3) {
    magnitude = std::ldexp(random.integer(1, 15), random.integer(-1074, 1019));
  } else if (pick == 4) {
    magnitude = std::ldexp(random.unit(), -1022);  // subnormal
  } else if (pick != 5) {
    magnitude = std::ldexp(1.0 + random.unit(), random.integer(-1022, 1023));
  }
  return random.coin() ? -magnitude : magnitude;
}

// ---------------------------------------------------------------------------------------------
// The reference itself.

TEST(PredicatesReference, BigIntArithmeticMatchesNativeIntegers) {
  Random random(1);
  for (int i = 0; i < 2000; ++i) {
    const std::int64_t x = random.integer(-2000000000, 2000000000);
    const std::int64_t y = random.integer(-2000000000, 2000000000);
    const auto big = [](std::int64_t v) {
      return BigInt(static_cast<std::uint64_t>(v < 0 ? -v : v), v < 0);
    };
    const auto sign = [](std::int64_t v) { return (v > 0) - (v < 0); };
    EXPECT_EQ((big(x) * big(y)).sign(), sign(x * y));
    EXPECT_EQ(big(x) * big(y) - big(x * y), BigInt());
    EXPECT_EQ(big(x) + big(y) - big(x + y), BigInt());
    EXPECT_EQ(big(x) - big(y) - big(x - y), BigInt());
  }
  // Carries across limbs: (2^64 - 1)^2 = 2^128 - 2^65 + 1.
  const BigInt all_ones(~std::uint64_t{0}, false);
  const BigInt square = all_ones * all_ones;
  const BigInt expected =
      BigInt(1, false).shifted_left(128) - BigInt(1, false).shifted_left(65) + BigInt(1, false);
  EXPECT_EQ(square, expected);
  EXPECT_EQ((BigInt(1, false).shifted_left(2000) - BigInt(1, false).shifted_left(1999) -
             BigInt(1, false).shifted_left(1999)),
            BigInt());
}

TEST(PredicatesReference, KnownConfigurations) {
  EXPECT_EQ(reference_orient2d({0, 0}, {1, 0}, {0, 1}), 1);
  EXPECT_EQ(reference_orient2d({0, 0}, {0, 1}, {1, 0}), -1);
  EXPECT_EQ(reference_orient2d({0, 0}, {1, 1}, {3, 3}), 0);
  EXPECT_EQ(reference_incircle({1, 0}, {0, 1}, {-1, 0}, {0, 0}), 1);
  EXPECT_EQ(reference_incircle({1, 0}, {0, 1}, {-1, 0}, {0, 2}), -1);
  EXPECT_EQ(reference_incircle({1, 0}, {0, 1}, {-1, 0}, {0, -1}), 0);
  EXPECT_EQ(reference_incircle({1, 0}, {-1, 0}, {0, 1}, {0, 0}), -1);  // clockwise a, b, c
  // Smallest subnormal against the largest double: 2^-1074 * 2^1023 is far from zero.
  const double tiny = std::numeric_limits<double>::denorm_min();
  const double huge = std::numeric_limits<double>::max();
  EXPECT_EQ(reference_orient2d({0, 0}, {huge, huge}, {tiny, 0}), -1);
}

// ---------------------------------------------------------------------------------------------
// orient2d

TEST(Orient2d, SimpleConfigurations) {
  EXPECT_EQ(orient2d({0, 0}, {1, 0}, {0, 1}), 1);
  EXPECT_EQ(orient2d({0, 0}, {0, 1}, {1, 0}), -1);
  EXPECT_EQ(orient2d({0, 0}, {1, 1}, {2, 2}), 0);
  EXPECT_EQ(orient2d({1, 1}, {1, 1}, {1, 1}), 0);
  EXPECT_EQ(orient2d({0.5, 0.5}, {12, 12}, {24, 24}), 0);
}

TEST(Orient2d, RandomPoints) {
  const Coverage unit = check_all(random_triples(101, 5000, -1.0, 1.0));
  const Coverage large = check_all(random_triples(102, 5000, -1e6, 1e6));
  EXPECT_EQ(unit.cases + large.cases, 10000);
}

TEST(Orient2d, RandomUtmPoints) {
  std::vector<Triple> cases;
  Random random(103);
  for (int i = 0; i < 10000; ++i) {
    const double extent = i % 2 == 0 ? 1000.0 : 1.0;
    cases.push_back(
        {random_utm(random, extent), random_utm(random, extent), random_utm(random, extent)});
  }
  EXPECT_EQ(check_all(cases).cases, 10000);
}

TEST(Orient2d, NearCollinearUtm) {
  const Coverage coverage = check_all(near_collinear_utm(104, 400));
  EXPECT_EQ(coverage.cases, 10000);
  EXPECT_GE(coverage.zero, 300);  // the un-nudged point of every exactly computed line
  EXPECT_EQ(coverage.exact_differences, coverage.cases);
}

TEST(Orient2d, CollinearLatticeUtm) {
  const Coverage coverage = check_all(collinear_lattice_utm(105, 3000));
  EXPECT_EQ(coverage.cases, 6000);
  EXPECT_GE(coverage.zero, 3000);
  EXPECT_EQ(coverage.exact_differences, coverage.cases);
}

TEST(Orient2d, NearCollinearMixedSigns) {
  const Coverage coverage = check_all(near_collinear_mixed_signs(106, 400));
  EXPECT_EQ(coverage.cases, 10000);
  EXPECT_GT(coverage.zero, 100);
  EXPECT_LT(coverage.exact_differences, coverage.cases / 2);
  EXPECT_EQ(coverage.expansions, coverage.cases);
}

TEST(Orient2d, TinyMagnitudes) {
  // Around 2^-520 products are subnormal (only partly precise), below that they vanish;
  // 2^-1000 ~ 1e-301, and 2^-1060 gives subnormal coordinates.
  for (const int power : {-505, -515, -525, -540, -1000, -1060}) {
    SCOPED_TRACE(power);
    const Coverage lines = check_all(scaled_cases(near_collinear_mixed_signs(107, 100), power));
    const Coverage utm = check_all(scaled_cases(collinear_lattice_utm(108, 1000), power - 22));
    EXPECT_EQ(lines.cases + utm.cases, 4500);
  }
}

TEST(Orient2d, HugeMagnitudes) {
  // 2^1000 ~ 1e301: products overflow, and with differences near DBL_MAX so do differences.
  for (const int power : {520, 990, 1018}) {  // |coordinates| < 8 before scaling
    SCOPED_TRACE(power);
    const Coverage lines = check_all(scaled_cases(near_collinear_mixed_signs(109, 100), power));
    const Coverage utm = check_all(scaled_cases(collinear_lattice_utm(110, 1000), power - 23));
    EXPECT_EQ(lines.cases + utm.cases, 4500);
  }
  const double max = std::numeric_limits<double>::max();
  Coverage extremes;
  EXPECT_TRUE(orient2d_is_exact({-max, -max}, {max, max}, {0, 0}, extremes));
  EXPECT_TRUE(orient2d_is_exact({-max, -max}, {max, max}, {0, 1e-300}, extremes));
  EXPECT_TRUE(orient2d_is_exact({-max, max}, {max, -max}, {nudge(max, -1), -max}, extremes));
}

TEST(Orient2d, FilterStaysExactWhenProductsUnderflow) {
  // Nearly collinear points within ~2^-520 of each other: the products are subnormals, and the
  // plain stage-A bound (relative to them) underflows to nothing.
  Random random(112);
  std::vector<Triple> cases;
  for (int i = 0; i < 400; ++i) {
    const double unit = std::ldexp(1.0, -500 - random.integer(0, 30));
    const Point2 a{unit * random.uniform(-1, 1), unit * random.uniform(-1, 1)};
    const Point2 b{unit * random.uniform(-1, 1), unit * random.uniform(-1, 1)};
    const double t = random.uniform(-1, 2);
    add_nudged(cases, a, b, {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
  }
  EXPECT_EQ(check_all(cases).cases, 10000);
}

TEST(Orient2d, AnyFiniteDoubles) {
  Random random(111);
  std::vector<Triple> cases;
  for (int i = 0; i < 3000; ++i) {
    auto point = [&] { return Point2{random_finite(random), random_finite(random)}; };
    const Point2 a = point();
    cases.push_back({a, point(), point()});
    // Collinear with the origin (exactly, unless scaling rounds): 0, a, 2^k a; a, 2a, ~4a.
    cases.push_back({{0, 0}, a, scaled(a, random.integer(-60, 60))});
    cases.push_back({a, scaled(a, 1), {nudge(std::ldexp(a.x, 2), 1), std::ldexp(a.y, 2)}});
  }
  std::erase_if(cases, [](const Triple& t) { return !all_finite({t.a, t.b, t.c}); });
  const Coverage coverage = check_all(cases);
  EXPECT_GT(coverage.cases, 8000);
  EXPECT_GT(coverage.wide_integers_only, 1000);
}

// ---------------------------------------------------------------------------------------------
// incircle

TEST(Incircle, SimpleConfigurations) {
  EXPECT_EQ(incircle({1, 0}, {0, 1}, {-1, 0}, {0, 0}), 1);
  EXPECT_EQ(incircle({1, 0}, {0, 1}, {-1, 0}, {0, 5}), -1);
  EXPECT_EQ(incircle({1, 0}, {0, 1}, {-1, 0}, {0, -1}), 0);
  EXPECT_EQ(incircle({1, 0}, {-1, 0}, {0, 1}, {0, 0}), -1);  // clockwise: reversed
  EXPECT_EQ(incircle({0, 0}, {1, 0}, {1, 1}, {0, 1}), 0);
}

TEST(Incircle, RandomPoints) {
  const Coverage unit = check_all(random_quads(201, 5000, -1.0, 1.0));
  const Coverage large = check_all(random_quads(202, 5000, -1e6, 1e6));
  EXPECT_EQ(unit.cases + large.cases, 10000);
}

TEST(Incircle, RandomUtmPoints) {
  std::vector<Quad> cases;
  Random random(203);
  for (int i = 0; i < 10000; ++i) {
    const double extent = i % 2 == 0 ? 1000.0 : 1.0;
    cases.push_back({random_utm(random, extent), random_utm(random, extent),
                     random_utm(random, extent), random_utm(random, extent)});
  }
  EXPECT_EQ(check_all(cases).cases, 10000);
}

TEST(Incircle, CocircularLatticeUtm) {
  const Coverage coverage = check_all(cocircular_lattice_utm(204, 3000));
  EXPECT_EQ(coverage.cases, 6000);
  EXPECT_GE(coverage.zero, 3000);
  EXPECT_EQ(coverage.exact_differences, coverage.cases);
  EXPECT_EQ(coverage.as_integers, coverage.cases);
}

TEST(Incircle, GridCellsUtm) {
  const Coverage coverage = check_all(grid_quads_utm(205, 4000));
  EXPECT_EQ(coverage.cases, 4000);
  EXPECT_EQ(coverage.zero, coverage.cases);
  EXPECT_EQ(coverage.exact_differences, coverage.cases);
  EXPECT_GT(coverage.as_small_integers, coverage.cases / 3);  // the 1 m cells; not 0.1 m
}

TEST(Incircle, CocircularFractionalUtm) {
  const Coverage coverage = check_all(cocircular_fractional_utm(206, 3000));
  EXPECT_EQ(coverage.cases, 6000);
  EXPECT_GE(coverage.zero, 3000);
  EXPECT_EQ(coverage.exact_differences, coverage.cases);
  EXPECT_EQ(coverage.as_integers, coverage.cases);  // ~44 bits from lowest bit to 1 km
}

TEST(Incircle, IntegerStageAtItsLimits) {
  // Differences whose span (leading bit over lowest set bit) is around the 62 bits of stage 1a:
  // odd 53-bit integers times 2^k, d at the origin. Random points and rectangles (cocircular).
  Random random(215);
  std::vector<Quad> cases;
  for (int span = 56; span <= 68; ++span) {
    auto coordinate = [&] {
      const double odd = std::ldexp(1.0 + random.unit(), 52) + (random.coin() ? 1.0 : -1.0);
      const double v = std::ldexp(std::floor(odd / 2) * 2 + 1, random.integer(0, span - 53));
      return random.coin() ? v : -v;
    };
    for (int i = 0; i < 150; ++i) {
      auto point = [&] { return Point2{coordinate(), coordinate()}; };
      cases.push_back({point(), point(), point(), {1.0, 0.0}});
      const double w = coordinate();
      const double h = coordinate();
      cases.push_back({{0, 0}, {w, 0}, {w, h}, {0, h}});
      cases.push_back({{w, 0}, {0, h}, {0, 0}, {w, nudge(h, 1)}});
    }
  }
  const Coverage coverage = check_all(cases);
  EXPECT_EQ(coverage.cases, 13 * 450);
  EXPECT_GT(coverage.as_integers, 1000);
  EXPECT_LT(coverage.as_integers, coverage.exact_differences);
}

TEST(Incircle, SmallIntegerShortcutAtItsLimits) {
  // Differences that are integers up to 2^12 - 1 in units of 2^k (every product and sum of the
  // double evaluation near 2^53 units^4, so a lost bit would show) and, past the limit, 2^12 to
  // 2^13 - 1 with a unit bit set; at UTM offsets and near zero, rectangles (ties) and random
  // points.
  Random random(216);
  for (const bool past_limit : {false, true}) {
    std::vector<Quad> cases;
    for (const int k : {-30, -7, -1, 0, 3, 20}) {
      const double unit = std::ldexp(1.0, k);
      auto integer = [&] {
        const int top = past_limit ? 8191 : 4095;
        const int v = random.integer(past_limit ? 4096 : top - 64, top) | (past_limit ? 1 : 0);
        return (random.coin() ? v : -v) * unit;
      };
      for (const Point2 origin : {Point2{0, 0}, Point2{500000, 4000000}}) {
        if (origin.x != 0 && k < -20) continue;  // the differences would not be exact
        for (int i = 0; i < 200; ++i) {
          auto point = [&] { return Point2{origin.x + integer(), origin.y + integer()}; };
          cases.push_back({point(), point(), point(), origin});
          const double w = integer(), h = integer();
          cases.push_back({origin,
                           {origin.x + w, origin.y},
                           {origin.x + w, origin.y + h},
                           {origin.x, origin.y + h}});
        }
      }
    }
    const Coverage coverage = check_all(cases);
    EXPECT_EQ(coverage.cases, 11 * 400);
    EXPECT_GE(coverage.zero, 2000);
    EXPECT_EQ(coverage.as_small_integers, past_limit ? 0 : coverage.cases);
  }
}

TEST(Incircle, CocircularWideSpanDifferences) {
  // Rectangles with a corner at the origin and sides of very different magnitudes: every
  // difference is exact, but they span far more than 62 bits, so stage 1b (expansions) decides.
  Random random(214);
  std::vector<Quad> cases;
  for (int i = 0; i < 1000; ++i) {
    const double w = std::ldexp(1.0 + random.unit(), random.integer(-150, -20));
    const double h = std::ldexp(1.0 + random.unit(), random.integer(20, 150));
    std::array<Point2, 4> p{{{0, 0}, {w, 0}, {w, h}, {0, h}}};
    if (random.coin()) {
      for (Point2& corner : p) std::swap(corner.x, corner.y);
    }
    for (std::size_t k = 3; k > 0; --k) {
      std::swap(p[k], p[static_cast<std::size_t>(random.integer(0, static_cast<int>(k)))]);
    }
    cases.push_back({p[0], p[1], p[2], p[3]});
    Point2& moved = p[static_cast<std::size_t>(random.integer(0, 3))];
    moved.x = nudge(moved.x, random.coin() ? 1 : -1);
    cases.push_back({p[0], p[1], p[2], p[3]});
  }
  const Coverage coverage = check_all(cases);
  EXPECT_EQ(coverage.cases, 2000);
  EXPECT_GE(coverage.zero, 1000);
  EXPECT_GE(coverage.exact_differences, 1000);  // nudging a zero makes some inexact
  EXPECT_EQ(coverage.as_integers, 0);
}

TEST(Incircle, CocircularMixedSigns) {
  const Coverage coverage = check_all(cocircular_mixed_signs(207, 2000));
  EXPECT_EQ(coverage.cases, 6000);
  EXPECT_GE(coverage.zero, 4000);
  EXPECT_LT(coverage.exact_differences, coverage.cases / 2);
  EXPECT_EQ(coverage.expansions, coverage.cases);
}

TEST(Incircle, TinyMagnitudes) {
  for (const int power : {-260, -300, -515, -540, -1000, -1060}) {
    SCOPED_TRACE(power);
    const Coverage mixed = check_all(scaled_cases(cocircular_mixed_signs(208, 300), power));
    const Coverage utm = check_all(scaled_cases(cocircular_lattice_utm(209, 500), power - 22));
    EXPECT_EQ(mixed.cases + utm.cases, 1900);
  }
}

TEST(Incircle, HugeMagnitudes) {
  for (const int power : {260, 520, 990, 1021}) {
    SCOPED_TRACE(power);
    const Coverage mixed = check_all(scaled_cases(cocircular_mixed_signs(210, 300), power));
    const Coverage utm = check_all(scaled_cases(cocircular_lattice_utm(211, 500), power - 23));
    EXPECT_EQ(mixed.cases + utm.cases, 1900);
  }
}

TEST(Incircle, FilterStaysExactWhenProductsUnderflow) {
  // a far away (|a - d|^2 ~ 2^200) and b, c, d nearly collinear within ~2^-520 of each other:
  // the 2x2 minor of b, c (relative to d) is a subnormal whose absolute error, times the huge
  // lift of a, exceeds both the determinant and the plain stage-A error bound.
  Random random(212);
  std::vector<Quad> cases;
  for (int i = 0; i < 3000; ++i) {
    const double unit = std::ldexp(1.0, -500 - random.integer(0, 30));
    const Point2 d{unit * random.uniform(-1, 1), unit * random.uniform(-1, 1)};
    const Point2 b{unit * random.uniform(-1, 1), unit * random.uniform(-1, 1)};
    const double t = random.uniform(-1, 2);
    const Point2 c{nudge(d.x + t * (b.x - d.x), random.integer(-2, 2)),
                   nudge(d.y + t * (b.y - d.y), random.integer(-2, 2))};
    const Point2 a{std::ldexp(random.uniform(-1, 1), 100), std::ldexp(random.uniform(-1, 1), 100)};
    cases.push_back({a, b, c, d});
  }
  EXPECT_EQ(check_all(cases).cases, 3000);
}

TEST(Incircle, AnyFiniteDoubles) {
  Random random(213);
  std::vector<Quad> cases;
  for (int i = 0; i < 800; ++i) {
    auto point = [&] { return Point2{random_finite(random), random_finite(random)}; };
    cases.push_back({point(), point(), point(), point()});
    // A square of side s at an arbitrary place: cocircular if the corners are exact.
    const Point2 p = point();
    const double side = std::fabs(random_finite(random));
    cases.push_back({p, {p.x + side, p.y}, {p.x + side, p.y + side}, {p.x, p.y + side}});
    // The four axis points of a circle of any radius around the origin.
    const double r = std::fabs(random_finite(random));
    cases.push_back({{r, 0}, {0, r}, {-r, 0}, {0, nudge(-r, random.integer(-1, 1))}});
  }
  std::erase_if(cases, [](const Quad& q) { return !all_finite({q.a, q.b, q.c, q.d}); });
  const Coverage coverage = check_all(cases);
  EXPECT_GT(coverage.cases, 2000);
  EXPECT_GT(coverage.wide_integers_only, 1000);
}

// ---------------------------------------------------------------------------------------------
// Symmetries alone, on many more cases than the reference can afford: the exact sign must be
// invariant under the even permutations and flip under the odd ones.

TEST(PredicateSymmetry, Orient2dPermutations) {
  std::vector<Triple> cases = near_collinear_utm(301, 2000);
  const auto lattice = collinear_lattice_utm(302, 20000);
  cases.insert(cases.end(), lattice.begin(), lattice.end());
  int failures = 0;
  for (const Triple& t : cases) {
    const int s = orient2d(t.a, t.b, t.c);
    const bool ok = orient2d(t.b, t.c, t.a) == s && orient2d(t.c, t.a, t.b) == s &&
                    orient2d(t.b, t.a, t.c) == -s && orient2d(t.c, t.b, t.a) == -s &&
                    orient2d(t.a, t.c, t.b) == -s;
    EXPECT_TRUE(ok) << describe(t.a) << describe(t.b) << describe(t.c);
    if (!ok && ++failures >= kMaxReportedFailures) break;
  }
}

TEST(PredicateSymmetry, IncirclePermutations) {
  std::vector<Quad> cases = cocircular_lattice_utm(303, 20000);
  const auto fractional = cocircular_fractional_utm(304, 10000);
  cases.insert(cases.end(), fractional.begin(), fractional.end());
  int failures = 0;
  for (const Quad& q : cases) {
    const int s = incircle(q.a, q.b, q.c, q.d);
    const bool ok = incircle(q.b, q.c, q.a, q.d) == s && incircle(q.c, q.a, q.b, q.d) == s &&
                    incircle(q.b, q.a, q.c, q.d) == -s && incircle(q.c, q.b, q.a, q.d) == -s &&
                    incircle(q.a, q.c, q.b, q.d) == -s && incircle(q.d, q.a, q.b, q.c) == -s;
    EXPECT_TRUE(ok) << describe(q.a) << describe(q.b) << describe(q.c) << describe(q.d);
    if (!ok && ++failures >= kMaxReportedFailures) break;
  }
}

}  // namespace
}  // namespace tincdt::predicates
