// Exact fallbacks for orient2d and incircle, used when the inline filter cannot decide.
//
// Three stages, cheapest first (see exact_stages.hpp):
//   1. exact coordinate differences (Two-Diff tails all zero) -> the determinant of the
//      differences: for incircle in 64/128/256-bit integers when the differences fit (1a),
//      else as expansions (1b); for orient2d from two exact products,
//   2. any coordinates in a safe range -> expansions of the raw-coordinate determinant,
//   3. anything else (extreme or mixed magnitudes) -> wide integers.
// The floating-point building blocks are the error-free transformations of Shewchuk's paper
// (Two-Sum, Two-Diff, Dekker/Veltkamp Split and Two-Product, Fast-Expansion-Sum and
// Scale-Expansion, each with zero elimination). They are exact only under IEEE round-to-nearest-
// even with no FMA contraction and no overflow or underflow; stages 1 and 2 check their range so
// that none can occur. Everything lives in fixed-size stack arrays: no allocation.
#include "predicates/predicates.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>

#include "predicates/exact_stages.hpp"

namespace tincdt::predicates::detail {
namespace {

// GCC/Clang built-ins; __extension__ keeps -Wpedantic quiet about them.
__extension__ typedef __int128 Int128;
__extension__ typedef unsigned __int128 UInt128;

// ---------------------------------------------------------------------------------------------
// Error-free transformations. Each returns head + tail == exact result, head = rounded result.

struct TwoTerm {
  double head;
  double tail;
};

// Requires |a| >= |b| (or a == 0).
inline TwoTerm fast_two_sum(double a, double b) {
  const double sum = a + b;
  const double b_virtual = sum - a;
  return {sum, b - b_virtual};
}

inline TwoTerm two_sum(double a, double b) {
  const double sum = a + b;
  const double b_virtual = sum - a;
  const double a_virtual = sum - b_virtual;
  const double b_roundoff = b - b_virtual;
  const double a_roundoff = a - a_virtual;
  return {sum, a_roundoff + b_roundoff};
}

inline TwoTerm two_diff(double a, double b) {
  const double diff = a - b;
  const double b_virtual = a - diff;
  const double a_virtual = diff + b_virtual;
  const double b_roundoff = b_virtual - b;
  const double a_roundoff = a - a_virtual;
  return {diff, a_roundoff + b_roundoff};
}

// Veltkamp split into two halves of at most 26 significant bits each, so that products of
// halves are exact. (No FMA: the build targets baseline x86-64.)
struct Halves {
  double high;
  double low;
};

inline Halves split(double a) {
  constexpr double kSplitter = 0x1p27 + 1.0;  // 2^ceil(53/2) + 1
  const double scaled = kSplitter * a;
  const double big = scaled - a;
  const double high = scaled - big;
  return {high, a - high};
}

// Dekker's product, with b already split (scale-expansion reuses one split of the scalar).
inline TwoTerm two_product_presplit(double a, double b, Halves b_halves) {
  const double product = a * b;
  const Halves a_halves = split(a);
  const double err1 = product - a_halves.high * b_halves.high;
  const double err2 = err1 - a_halves.low * b_halves.high;
  const double err3 = err2 - a_halves.high * b_halves.low;
  return {product, a_halves.low * b_halves.low - err3};
}

inline TwoTerm two_product(double a, double b) {
  return two_product_presplit(a, b, split(b));
}

inline TwoTerm two_square(double a) {
  const double square = a * a;
  const Halves halves = split(a);
  const double err1 = square - halves.high * halves.high;
  const double err3 = err1 - (halves.high + halves.high) * halves.low;
  return {square, halves.low * halves.low - err3};
}

// ---------------------------------------------------------------------------------------------
// Expansions: sums of nonoverlapping doubles, ordered by increasing magnitude, zeros removed.
// The sign of an expansion is the sign of its last (largest) component.

template <int kCapacity>
struct Expansion {
  std::array<double, kCapacity> terms;  // only [0, size) is meaningful
  int size = 0;

  void push_nonzero(double term) {
    if (term != 0.0) terms[static_cast<std::size_t>(size++)] = term;
  }
  int sign() const { return size == 0 ? 0 : sign_of(terms[static_cast<std::size_t>(size - 1)]); }
};

template <int kCapacity>
Expansion<kCapacity> negated(const Expansion<kCapacity>& e) {
  Expansion<kCapacity> result;
  result.size = e.size;
  for (std::size_t i = 0; i < static_cast<std::size_t>(e.size); ++i) result.terms[i] = -e.terms[i];
  return result;
}

// Fast-Expansion-Sum with zero elimination: merge both inputs by magnitude, then carry a running
// sum through Two-Sum, emitting the roundoff terms. h must have room for e_size + f_size terms.
int sum_expansions(const double* e, int e_size, const double* f, int f_size, double* h) {
  if (e_size == 0 || f_size == 0) {
    const double* source = e_size == 0 ? f : e;
    const int size = e_size == 0 ? f_size : e_size;
    std::copy(source, source + size, h);
    return size;
  }
  int ei = 0;
  int fi = 0;
  // Takes the smaller-magnitude head of the two inputs.
  auto next = [&]() {
    if (fi == f_size || (ei < e_size && std::fabs(e[ei]) < std::fabs(f[fi]))) return e[ei++];
    return f[fi++];
  };
  int h_size = 0;
  const double first = next();
  const TwoTerm start = fast_two_sum(next(), first);
  if (start.tail != 0.0) h[h_size++] = start.tail;
  double running = start.head;
  while (ei < e_size || fi < f_size) {
    const TwoTerm step = two_sum(running, next());
    if (step.tail != 0.0) h[h_size++] = step.tail;
    running = step.head;
  }
  if (running != 0.0) h[h_size++] = running;
  return h_size;
}

// Scale-Expansion with zero elimination: h = e * b, h has room for 2 * e_size terms.
int scale_expansion(const double* e, int e_size, double b, double* h) {
  if (e_size == 0 || b == 0.0) return 0;
  const Halves b_halves = split(b);
  int h_size = 0;
  const TwoTerm first = two_product_presplit(e[0], b, b_halves);
  if (first.tail != 0.0) h[h_size++] = first.tail;
  double running = first.head;
  for (int i = 1; i < e_size; ++i) {
    const TwoTerm product = two_product_presplit(e[i], b, b_halves);
    const TwoTerm low = two_sum(running, product.tail);
    if (low.tail != 0.0) h[h_size++] = low.tail;
    const TwoTerm high = fast_two_sum(product.head, low.head);
    if (high.tail != 0.0) h[h_size++] = high.tail;
    running = high.head;
  }
  if (running != 0.0) h[h_size++] = running;
  return h_size;
}

template <int kA, int kB>
Expansion<kA + kB> operator+(const Expansion<kA>& e, const Expansion<kB>& f) {
  Expansion<kA + kB> result;
  result.size = sum_expansions(e.terms.data(), e.size, f.terms.data(), f.size, result.terms.data());
  return result;
}

template <int kA, int kB>
Expansion<kA + kB> operator-(const Expansion<kA>& e, const Expansion<kB>& f) {
  return e + negated(f);
}

template <int kA>
Expansion<2 * kA> operator*(const Expansion<kA>& e, double b) {
  Expansion<2 * kA> result;
  result.size = scale_expansion(e.terms.data(), e.size, b, result.terms.data());
  return result;
}

// Product of two expansions: the sum over f's terms of e scaled by that term. Partial sums
// alternate between two buffers; only their meaningful prefixes are ever copied.
template <int kA, int kB>
Expansion<2 * kA * kB> operator*(const Expansion<kA>& e, const Expansion<kB>& f) {
  using Product = Expansion<2 * kA * kB>;
  Product result;
  Product other;
  Product* from = &result;
  Product* to = &other;
  for (std::size_t j = 0; j < static_cast<std::size_t>(f.size); ++j) {
    const Expansion<2 * kA> scaled = e * f.terms[j];
    to->size = sum_expansions(from->terms.data(), from->size, scaled.terms.data(), scaled.size,
                              to->terms.data());
    std::swap(from, to);
  }
  if (from != &result) {
    std::copy_n(other.terms.begin(), other.size, result.terms.begin());
    result.size = other.size;
  }
  return result;
}

inline Expansion<2> as_expansion(TwoTerm t) {
  Expansion<2> result;
  result.push_nonzero(t.tail);
  result.push_nonzero(t.head);
  return result;
}

// p.x * q.y - q.x * p.y, exactly.
inline Expansion<4> cross(double px, double py, double qx, double qy) {
  return as_expansion(two_product(px, qy)) - as_expansion(two_product(qx, py));
}

inline Expansion<4> squared_norm(double x, double y) {
  return as_expansion(two_square(x)) + as_expansion(two_square(y));
}

// ---------------------------------------------------------------------------------------------
// Ranges in which stages 1 and 2 are exact. Every nonzero operand of magnitude >= 2^-k has its
// lowest bit at >= 2^(-k-52), so every exact product of n operands is a multiple of
// 2^(n(-k-52)) and all its Two-Product tails are representable while n(-k-52) >= -1074; the
// upper limit keeps the largest determinant term, and the Splitter times any term, finite.
// orient2d (degree 2): n(-k-52) = -1064, terms <= 6 * 2^960.
// incircle (degree 4): n(-k-52) = -1008, terms <= 4 * 2^966.

constexpr double kOrientLowest = 0x1p-480;
constexpr double kOrientHighest = 0x1p480;
constexpr double kIncircleLowest = 0x1p-200;
constexpr double kIncircleHighest = 0x1p240;

// True if every value is zero or has magnitude in [lowest, highest]. Rejects inf and NaN.
template <class... Values>
bool all_in_range(double lowest, double highest, Values... values) {
  return (... &
          ((std::fabs(values) <= highest) & ((std::fabs(values) >= lowest) | (values == 0.0))));
}

template <class... Tails>
bool all_zero(Tails... tails) {
  return (... & (tails == 0.0));
}

// ---------------------------------------------------------------------------------------------
// Wide integers for stage 3: sign and magnitude, 32-bit limbs, little-endian, fixed capacity.

template <std::size_t kLimbs>
struct WideInt {
  std::array<std::uint32_t, kLimbs> limbs{};  // zero-filled: this stage is rare, keep it simple
  std::size_t size = 0;                       // no leading zero limbs; 0 for the value 0
  bool negative = false;

  int sign() const { return size == 0 ? 0 : (negative ? -1 : 1); }
  void trim() {
    while (size > 0 && limbs[size - 1] == 0) --size;
    if (size == 0) negative = false;
  }
};

template <std::size_t kA, std::size_t kB>
int compare_magnitudes(const WideInt<kA>& a, const WideInt<kB>& b) {
  if (a.size != b.size) return a.size < b.size ? -1 : 1;
  for (std::size_t i = a.size; i-- > 0;) {
    if (a.limbs[i] != b.limbs[i]) return a.limbs[i] < b.limbs[i] ? -1 : 1;
  }
  return 0;
}

// Signed sum. (Subtraction: add a negated copy.)
template <std::size_t kA, std::size_t kB>
WideInt<std::max(kA, kB) + 1> operator+(const WideInt<kA>& a, const WideInt<kB>& b) {
  WideInt<std::max(kA, kB) + 1> result;
  if (a.negative == b.negative || a.size == 0 || b.size == 0) {
    result.negative = a.size != 0 ? a.negative : b.negative;
    const std::size_t longest = std::max(a.size, b.size);
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i < longest; ++i) {
      const std::uint64_t sum =
          carry + (i < a.size ? a.limbs[i] : 0u) + (i < b.size ? b.limbs[i] : 0u);
      result.limbs[i] = static_cast<std::uint32_t>(sum);
      carry = sum >> 32;
    }
    result.limbs[longest] = static_cast<std::uint32_t>(carry);
    result.size = longest + 1;
  } else {
    // Opposite signs: subtract the smaller magnitude from the larger.
    const bool a_larger = compare_magnitudes(a, b) >= 0;
    const std::uint32_t* large = a_larger ? a.limbs.data() : b.limbs.data();
    const std::uint32_t* small = a_larger ? b.limbs.data() : a.limbs.data();
    const std::size_t large_size = a_larger ? a.size : b.size;
    const std::size_t small_size = a_larger ? b.size : a.size;
    result.negative = a_larger ? a.negative : b.negative;
    std::uint64_t borrow = 0;
    for (std::size_t i = 0; i < large_size; ++i) {
      const std::uint64_t subtrahend = (i < small_size ? small[i] : 0u) + borrow;
      const std::uint64_t minuend = large[i];
      result.limbs[i] = static_cast<std::uint32_t>(minuend - subtrahend);
      borrow = minuend < subtrahend ? 1 : 0;
    }
    result.size = large_size;
  }
  result.trim();
  return result;
}

template <std::size_t kA>
WideInt<kA> operator-(WideInt<kA> a) {
  if (a.size != 0) a.negative = !a.negative;
  return a;
}

template <std::size_t kA, std::size_t kB>
WideInt<std::max(kA, kB) + 1> operator-(const WideInt<kA>& a, const WideInt<kB>& b) {
  return a + (-b);
}

template <std::size_t kA, std::size_t kB>
WideInt<kA + kB> operator*(const WideInt<kA>& a, const WideInt<kB>& b) {
  WideInt<kA + kB> result;
  if (a.size == 0 || b.size == 0) return result;
  for (std::size_t i = 0; i < a.size; ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < b.size; ++j) {
      // At most (2^32-1)^2 + 2 (2^32-1) = 2^64 - 1: no overflow.
      const std::uint64_t t = std::uint64_t{a.limbs[i]} * b.limbs[j] + result.limbs[i + j] + carry;
      result.limbs[i + j] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    result.limbs[i + b.size] = static_cast<std::uint32_t>(carry);
  }
  result.size = a.size + b.size;
  result.negative = a.negative != b.negative;
  result.trim();
  return result;
}

// A finite double as +-mantissa * 2^exponent with an odd mantissa (or 0).
struct DyadicParts {
  std::uint64_t mantissa;
  int exponent;
  bool negative;
};

DyadicParts decompose(double value) {
  const auto bits = std::bit_cast<std::uint64_t>(value);
  const int biased_exponent = static_cast<int>((bits >> 52) & 0x7ff);
  std::uint64_t mantissa = bits & ((std::uint64_t{1} << 52) - 1);
  int exponent = -1074;  // subnormal
  if (biased_exponent != 0) {
    mantissa |= std::uint64_t{1} << 52;
    exponent = biased_exponent - 1075;
  }
  if (mantissa == 0) return {0, 0, false};
  const int trailing = std::countr_zero(mantissa);
  return {mantissa >> trailing, exponent + trailing, (bits >> 63) != 0};
}

// A coordinate in units of 2^lowest_exponent: at most 53 + (971 + 1074) = 2098 bits.
constexpr std::size_t kCoordinateLimbs = 66;
using Coordinate = WideInt<kCoordinateLimbs>;

Coordinate to_wide(const DyadicParts& parts, int lowest_exponent) {
  Coordinate result;
  if (parts.mantissa == 0) return result;
  const auto shift = static_cast<std::size_t>(parts.exponent - lowest_exponent);
  const std::size_t limb = shift / 32;
  const std::size_t bit = shift % 32;
  // mantissa < 2^53 and bit < 32, so the shifted value spans at most three limbs; those past
  // the capacity are zero (the value itself is below 2^2098).
  const std::uint64_t low = parts.mantissa << bit;
  const std::uint64_t high = bit == 0 ? 0 : parts.mantissa >> (64 - bit);
  const std::array<std::uint32_t, 3> pieces{static_cast<std::uint32_t>(low),
                                            static_cast<std::uint32_t>(low >> 32),
                                            static_cast<std::uint32_t>(high)};
  for (std::size_t i = 0; i < pieces.size() && limb + i < kCoordinateLimbs; ++i) {
    result.limbs[limb + i] = pieces[i];
  }
  result.size = std::min(limb + pieces.size(), kCoordinateLimbs);
  result.negative = parts.negative;
  result.trim();
  return result;
}

// All given doubles as integers in units of one common power of two.
template <std::size_t kCount>
std::array<Coordinate, kCount> to_common_scale(const std::array<double, kCount>& values) {
  std::array<DyadicParts, kCount> parts;
  int lowest_exponent = 0;
  bool any_nonzero = false;
  for (std::size_t i = 0; i < kCount; ++i) {
    parts[i] = decompose(values[i]);
    if (parts[i].mantissa != 0) {
      lowest_exponent =
          any_nonzero ? std::min(lowest_exponent, parts[i].exponent) : parts[i].exponent;
      any_nonzero = true;
    }
  }
  std::array<Coordinate, kCount> result;
  for (std::size_t i = 0; i < kCount; ++i) result[i] = to_wide(parts[i], lowest_exponent);
  return result;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Stage 1.

int orient2d_from_exact_differences(Point2 a, Point2 b, Point2 c) noexcept {
  const TwoTerm acx = two_diff(a.x, c.x);
  const TwoTerm bcx = two_diff(b.x, c.x);
  const TwoTerm acy = two_diff(a.y, c.y);
  const TwoTerm bcy = two_diff(b.y, c.y);
  if (!(all_zero(acx.tail, bcx.tail, acy.tail, bcy.tail) &
        all_in_range(kOrientLowest, kOrientHighest, acx.head, bcx.head, acy.head, bcy.head))) {
    return kNotApplicable;
  }
  const TwoTerm left = two_product(acx.head, bcy.head);
  const TwoTerm right = two_product(acy.head, bcx.head);
  // Rounding is monotonic, so unequal heads already order the exact products; equal heads
  // leave the (exact) tails to decide.
  if (left.head != right.head) return sign_of(left.head - right.head);
  return sign_of(left.tail - right.tail);
}

namespace {

struct IncircleDifferences {
  double adx, ady, bdx, bdy, cdx, cdy;
  double largest;  // of their magnitudes
};

// The coordinate differences relative to d, if all are exact and within the incircle range.
// (As all_zero and all_in_range, with fewer operations: this runs for every cocircular test.)
std::optional<IncircleDifferences> exact_incircle_differences(Point2 a, Point2 b, Point2 c,
                                                              Point2 d) {
  const std::array<TwoTerm, 6> v{two_diff(a.x, d.x), two_diff(a.y, d.y), two_diff(b.x, d.x),
                                 two_diff(b.y, d.y), two_diff(c.x, d.x), two_diff(c.y, d.y)};
  // Every tail 0: their magnitudes sum to 0 (an overflowing difference has a NaN tail).
  double tails = 0;
  double largest = 0;
  double smallest = std::numeric_limits<double>::infinity();  // of the nonzero magnitudes
  for (const TwoTerm& t : v) {
    tails += std::fabs(t.tail);
    const double m = std::fabs(t.head);
    largest = std::max(largest, m);
    smallest = std::min(smallest, m == 0 ? std::numeric_limits<double>::infinity() : m);
  }
  if (!(tails == 0 && largest <= kIncircleHighest && smallest >= kIncircleLowest))
    return std::nullopt;
  return IncircleDifferences{v[0].head, v[1].head, v[2].head, v[3].head,
                             v[4].head, v[5].head, largest};
}

// Stage 1a. Differences that, in units of their lowest set bit 2^k, are integers below 2^62
// (any lattice, and nearby points of one binade: UTM coordinates carry ~44 bits between their
// lowest bit and 1 km): the determinant in integers. Below 2^30 (lattices: whole metres,
// half metres...) int64 and int128 suffice; otherwise lifts and minors stay below 2^125 and
// the terms below 2^250, in 256 bits.
constexpr int kSmallBits = 30;
constexpr int kFixedBits = 62;

// Two's complement, least significant limb first.
using Int256 = std::array<std::uint64_t, 4>;

Int256 multiply(UInt128 a, UInt128 b) {
  const auto low = [](UInt128 v) { return static_cast<std::uint64_t>(v); };
  const auto high = [](UInt128 v) { return static_cast<std::uint64_t>(v >> 64); };
  const UInt128 p00 = UInt128{low(a)} * low(b);
  const UInt128 p01 = UInt128{low(a)} * high(b);
  const UInt128 p10 = UInt128{high(a)} * low(b);
  const UInt128 p11 = UInt128{high(a)} * high(b);
  const UInt128 middle = UInt128{high(p00)} + low(p01) + low(p10);  // < 3 * 2^64
  const UInt128 top = p11 + high(p01) + high(p10) + high(middle);   // product < 2^256
  return {low(p00), low(middle), low(top), high(top)};
}

// -v if negate, else v, without branches (the sign of a minor is data-dependent).
Int256 negated_if(const Int256& v, bool negate) {
  const std::uint64_t mask = negate ? ~std::uint64_t{0} : 0;
  Int256 result;
  std::uint64_t carry = mask & 1;
  for (std::size_t i = 0; i < 4; ++i) {
    const UInt128 sum = UInt128{v[i] ^ mask} + carry;
    result[i] = static_cast<std::uint64_t>(sum);
    carry = static_cast<std::uint64_t>(sum >> 64);
  }
  return result;
}

Int256 operator+(const Int256& a, const Int256& b) {
  Int256 result;
  std::uint64_t carry = 0;
  for (std::size_t i = 0; i < 4; ++i) {
    const UInt128 sum = UInt128{a[i]} + b[i] + carry;
    result[i] = static_cast<std::uint64_t>(sum);
    carry = static_cast<std::uint64_t>(sum >> 64);
  }
  return result;
}

int sign_of_fixed(const Int256& v) {
  const bool negative = (v[3] >> 63) != 0;
  const bool nonzero = (v[0] | v[1] | v[2] | v[3]) != 0;
  return nonzero - 2 * negative;
}

// lift * minor for lift >= 0.
Int256 fixed_term(Int128 lift, Int128 minor) {
  const bool negative = minor < 0;
  const auto magnitude = static_cast<UInt128>(negative ? -minor : minor);
  return negated_if(multiply(static_cast<UInt128>(lift), magnitude), negative);
}

// Stage 1a, first try: differences that, in units of 2^k where 2^(k + 12) exceeds the largest,
// are all integers (below 2^12 then): the local cells of a lattice or grid, which every
// insertion tests and which are cocircular. The plain double evaluation is then exact: products
// below 2^24 units^2, lifts and minors below 2^25, terms below 2^50 units^4 and their sum below
// 2^52, all integers; the range check of stage 1 keeps 2^(4k) and 2^52 * 2^(4k) normal.
int incircle_differences_as_small_integers(const IncircleDifferences& d) {
  const std::array<double, 6> values{d.adx, d.ady, d.bdx, d.bdy, d.cdx, d.cdy};
  const double largest = d.largest;
  if (largest == 0) return 0;  // all four points coincide
  // largest in [2^e, 2^(e + 1)), e = biased - 1023; the unit is 2^(e - 11), so 1 / unit has the
  // biased exponent 1023 - (e - 11) = 2057 - biased (in [794, 1234] for the range of stage 1).
  const auto biased = (std::bit_cast<std::uint64_t>(largest) >> 52) & 0x7ff;
  const auto to_units = std::bit_cast<double>((2057 - biased) << 52);
  bool integers = true;
  for (const double value : values) {
    const double units = value * to_units;  // exact: a power of two, no underflow
    integers &= units == static_cast<double>(static_cast<std::int32_t>(units));
  }
  if (!integers) return kNotApplicable;
  const double alift = d.adx * d.adx + d.ady * d.ady;
  const double blift = d.bdx * d.bdx + d.bdy * d.bdy;
  const double clift = d.cdx * d.cdx + d.cdy * d.cdy;
  return sign_of(alift * (d.bdx * d.cdy - d.cdx * d.bdy) + blift * (d.cdx * d.ady - d.adx * d.cdy) +
                 clift * (d.adx * d.bdy - d.bdx * d.ady));
}

int incircle_differences_as_integers(const IncircleDifferences& d) {
  const std::array<double, 6> values{d.adx, d.ady, d.bdx, d.bdy, d.cdx, d.cdy};
  // Lowest set bit and leading bit over the nonzero values (all normal: range-checked), without
  // data-dependent branches: lattice differences are often zero.
  int lowest = std::numeric_limits<int>::max();
  int highest = std::numeric_limits<int>::min();
  for (const double value : values) {
    const auto bits = std::bit_cast<std::uint64_t>(value);
    const bool nonzero = (bits << 1) != 0;
    const int unit_exponent = static_cast<int>((bits >> 52) & 0x7ff) - 1075;
    const int lowest_bit = unit_exponent + std::countr_zero(bits | (std::uint64_t{1} << 52));
    lowest = std::min(lowest, nonzero ? lowest_bit : std::numeric_limits<int>::max());
    highest = std::max(highest, nonzero ? unit_exponent + 52 : std::numeric_limits<int>::min());
  }
  if (highest == std::numeric_limits<int>::min()) return 0;  // all differences zero
  // In units of 2^lowest every value is an integer below 2^(span + 1).
  const int span = highest - lowest;
  if (span >= kFixedBits) return kNotApplicable;
  // lowest is in [-252, 240] (range check), so 2^-lowest is a normal double and scaling by it is
  // exact; the results are integers below 2^62.
  const auto to_units = std::bit_cast<double>(static_cast<std::uint64_t>(1023 - lowest) << 52);
  std::array<std::int64_t, 6> v;
  for (std::size_t i = 0; i < 6; ++i) v[i] = static_cast<std::int64_t>(values[i] * to_units);
  const auto [adx, ady, bdx, bdy, cdx, cdy] = v;

  if (span < kSmallBits) {
    // |v| < 2^30: lifts and minors below 2^61 fit int64, terms below 2^122 fit int128.
    const auto lift = [](std::int64_t x, std::int64_t y) { return x * x + y * y; };
    const auto minor = [](std::int64_t px, std::int64_t py, std::int64_t qx, std::int64_t qy) {
      return px * qy - qx * py;
    };
    const Int128 det = Int128{lift(adx, ady)} * minor(bdx, bdy, cdx, cdy) +
                       Int128{lift(bdx, bdy)} * minor(cdx, cdy, adx, ady) +
                       Int128{lift(cdx, cdy)} * minor(adx, ady, bdx, bdy);
    return (det > 0) - (det < 0);
  }
  const auto product = [](std::int64_t x, std::int64_t y) { return Int128{x} * y; };
  const Int256 det =
      fixed_term(product(adx, adx) + product(ady, ady), product(bdx, cdy) - product(cdx, bdy)) +
      fixed_term(product(bdx, bdx) + product(bdy, bdy), product(cdx, ady) - product(adx, cdy)) +
      fixed_term(product(cdx, cdx) + product(cdy, cdy), product(adx, bdy) - product(bdx, ady));
  return sign_of_fixed(det);
}

// Stage 1b: any exact differences in range, as expansions.
int incircle_differences_as_expansions(const IncircleDifferences& d) {
  // det = |a-d|^2 cross(b-d, c-d) + |b-d|^2 cross(c-d, a-d) + |c-d|^2 cross(a-d, b-d).
  const Expansion<32> a_term = squared_norm(d.adx, d.ady) * cross(d.bdx, d.bdy, d.cdx, d.cdy);
  const Expansion<32> b_term = squared_norm(d.bdx, d.bdy) * cross(d.cdx, d.cdy, d.adx, d.ady);
  const Expansion<32> c_term = squared_norm(d.cdx, d.cdy) * cross(d.adx, d.ady, d.bdx, d.bdy);
  return (a_term + b_term + c_term).sign();
}

}  // namespace

int incircle_from_exact_differences(Point2 a, Point2 b, Point2 c, Point2 d) noexcept {
  const auto differences = exact_incircle_differences(a, b, c, d);
  if (!differences) return kNotApplicable;
  if (const int s = incircle_differences_as_small_integers(*differences); s != kNotApplicable)
    return s;
  if (const int s = incircle_differences_as_integers(*differences); s != kNotApplicable) return s;
  return incircle_differences_as_expansions(*differences);
}

int incircle_from_exact_differences_as_small_integers(Point2 a, Point2 b, Point2 c,
                                                      Point2 d) noexcept {
  const auto differences = exact_incircle_differences(a, b, c, d);
  return differences ? incircle_differences_as_small_integers(*differences) : kNotApplicable;
}

int incircle_from_exact_differences_as_integers(Point2 a, Point2 b, Point2 c, Point2 d) noexcept {
  const auto differences = exact_incircle_differences(a, b, c, d);
  return differences ? incircle_differences_as_integers(*differences) : kNotApplicable;
}

int incircle_from_exact_differences_as_expansions(Point2 a, Point2 b, Point2 c, Point2 d) noexcept {
  const auto differences = exact_incircle_differences(a, b, c, d);
  return differences ? incircle_differences_as_expansions(*differences) : kNotApplicable;
}

// ---------------------------------------------------------------------------------------------
// Stage 2.

// Out of line so that stage 1, the common fallback, keeps a small stack frame.
[[gnu::noinline]] int orient2d_by_expansions(Point2 a, Point2 b, Point2 c) noexcept {
  if (!all_in_range(kOrientLowest, kOrientHighest, a.x, a.y, b.x, b.y, c.x, c.y)) {
    return kNotApplicable;
  }
  // | ax ay 1 ; bx by 1 ; cx cy 1 | = cross(a, b) + cross(b, c) + cross(c, a).
  return (cross(a.x, a.y, b.x, b.y) + cross(b.x, b.y, c.x, c.y) + cross(c.x, c.y, a.x, a.y)).sign();
}

[[gnu::noinline]] int incircle_by_expansions(Point2 a, Point2 b, Point2 c, Point2 d) noexcept {
  if (!all_in_range(kIncircleLowest, kIncircleHighest, a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y)) {
    return kNotApplicable;
  }
  // The 4x4 determinant with rows (x, y, x^2 + y^2, 1), expanded along the lift column:
  // |a|^2 [bcd] - |b|^2 [cda] + |c|^2 [dab] - |d|^2 [abc], where [pqr] = cross(p,q) +
  // cross(q,r) + cross(r,p) is the orientation determinant. It equals the difference form.
  const Expansion<4> ab = cross(a.x, a.y, b.x, b.y);
  const Expansion<4> bc = cross(b.x, b.y, c.x, c.y);
  const Expansion<4> cd = cross(c.x, c.y, d.x, d.y);
  const Expansion<4> da = cross(d.x, d.y, a.x, a.y);
  const Expansion<4> ac = cross(a.x, a.y, c.x, c.y);
  const Expansion<4> bd = cross(b.x, b.y, d.x, d.y);
  const Expansion<12> abc = ab + bc - ac;
  const Expansion<12> bcd = bc + cd - bd;
  const Expansion<12> cda = cd + da + ac;
  const Expansion<12> dab = da + ab + bd;
  const Expansion<96> a_term = bcd * squared_norm(a.x, a.y);
  const Expansion<96> b_term = cda * squared_norm(b.x, b.y);
  const Expansion<96> c_term = dab * squared_norm(c.x, c.y);
  const Expansion<96> d_term = abc * squared_norm(d.x, d.y);
  return ((a_term - b_term) + (c_term - d_term)).sign();
}

// ---------------------------------------------------------------------------------------------
// Stage 3.

[[gnu::noinline, gnu::cold]] int orient2d_by_wide_integers(Point2 a, Point2 b, Point2 c) noexcept {
  const auto [ax, ay, bx, by, cx, cy] = to_common_scale(std::array{a.x, a.y, b.x, b.y, c.x, c.y});
  return ((ax - cx) * (by - cy) - (ay - cy) * (bx - cx)).sign();
}

[[gnu::noinline, gnu::cold]] int incircle_by_wide_integers(Point2 a, Point2 b, Point2 c,
                                                           Point2 d) noexcept {
  const auto [ax, ay, bx, by, cx, cy, dx, dy] =
      to_common_scale(std::array{a.x, a.y, b.x, b.y, c.x, c.y, d.x, d.y});
  const auto adx = ax - dx;
  const auto ady = ay - dy;
  const auto bdx = bx - dx;
  const auto bdy = by - dy;
  const auto cdx = cx - dx;
  const auto cdy = cy - dy;
  const auto a_term = (adx * adx + ady * ady) * (bdx * cdy - cdx * bdy);
  const auto b_term = (bdx * bdx + bdy * bdy) * (cdx * ady - adx * cdy);
  const auto c_term = (cdx * cdx + cdy * cdy) * (adx * bdy - bdx * ady);
  return (a_term + b_term + c_term).sign();
}

// ---------------------------------------------------------------------------------------------

int orient2d_exact(Point2 a, Point2 b, Point2 c) noexcept {
  if (const int s = orient2d_from_exact_differences(a, b, c); s != kNotApplicable) return s;
  if (const int s = orient2d_by_expansions(a, b, c); s != kNotApplicable) return s;
  return orient2d_by_wide_integers(a, b, c);
}

int incircle_exact(Point2 a, Point2 b, Point2 c, Point2 d) noexcept {
  if (const int s = incircle_from_exact_differences(a, b, c, d); s != kNotApplicable) return s;
  if (const int s = incircle_by_expansions(a, b, c, d); s != kNotApplicable) return s;
  return incircle_by_wide_integers(a, b, c, d);
}

// The tie: the cofactors of the lifts, in decreasing lexicographic order of their points (see
// incircle_perturbed() in predicates.hpp for the derivation).
namespace {

bool lex_greater(Point2 p, Point2 q) {
  return p.x > q.x || (p.x == q.x && p.y > q.y);
}

// The cofactor of the lift of point i (0..3 for a, b, c, d): (-1)^i times the orientation of the
// other three, in their order.
int lift_cofactor(int i, Point2 a, Point2 b, Point2 c, Point2 d) {
  switch (i) {
    case 0:
      return orient2d(b, c, d);
    case 1:
      return -orient2d(a, c, d);
    case 2:
      return orient2d(a, b, d);
    default:
      return -orient2d(a, b, c);
  }
}

// Three of the points collinear (a degenerate call): the cofactors after the largest point's.
[[gnu::noinline, gnu::cold]] int later_cofactors(Point2 a, Point2 b, Point2 c, Point2 d) {
  const std::array<Point2, 4> p{a, b, c, d};
  std::array<int, 4> order{0, 1, 2, 3};
  std::sort(order.begin(), order.end(), [&](int i, int j) { return lex_greater(p[i], p[j]); });
  for (std::size_t k = 1; k < 4; ++k)
    if (const int s = lift_cofactor(order[k], a, b, c, d); s != 0) return s;
  return 0;  // all four on one line
}

}  // namespace

[[gnu::noinline]] int incircle_perturbed_exact(Point2 a, Point2 b, Point2 c, Point2 d) noexcept {
  if (const int s = incircle_exact(a, b, c, d); s != 0) return s;
  // Four distinct points on one circle: the largest point's cofactor is never 0. (This runs for
  // every cocircular test of a lattice, so it takes no sort.)
  const bool b_over_a = lex_greater(b, a), d_over_c = lex_greater(d, c);
  const Point2 ab = b_over_a ? b : a, cd = d_over_c ? d : c;
  const int largest = lex_greater(cd, ab) ? 2 + d_over_c : b_over_a;
  if (const int s = lift_cofactor(largest, a, b, c, d); s != 0) return s;
  return later_cofactors(a, b, c, d);
}

}  // namespace tincdt::predicates::detail
