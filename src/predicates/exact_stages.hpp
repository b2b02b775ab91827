// The stages of the exact fallbacks, exposed so that tests can check each one on its own.
// Not for use outside src/predicates and tests/predicates: call orient2d / incircle.
#pragma once

#include "core/types.hpp"

namespace tincdt::predicates::detail {

// Returned by a stage whose preconditions do not hold for the given input.
inline constexpr int kNotApplicable = 2;

// Stage 1: the coordinate differences relative to the last point are exact doubles (Sterbenz:
// nearby points of similar magnitude, e.g. projected terrain data) and lie within a range where
// exact products cannot overflow or underflow. The determinant of those differences is then the
// exact determinant. orient2d compares the two exact products. incircle tries 1a, then 1b:
//   1a. the differences, in units of their lowest set bit, are integers below 2^62 (lattices,
//       and UTM-like data within kilometres): int64/int128 or 256-bit integers, tens of ns;
//       first of all, integers below 2^12 in units of 2^-11 times the largest (the cells of a
//       lattice or grid): the double evaluation itself is exact;
//   1b. otherwise, expansions of the difference determinant (as in Shewchuk's stage B).
int orient2d_from_exact_differences(Point2 a, Point2 b, Point2 c) noexcept;
int incircle_from_exact_differences(Point2 a, Point2 b, Point2 c, Point2 d) noexcept;
int incircle_from_exact_differences_as_small_integers(Point2 a, Point2 b, Point2 c,
                                                      Point2 d) noexcept;
int incircle_from_exact_differences_as_integers(Point2 a, Point2 b, Point2 c, Point2 d) noexcept;
int incircle_from_exact_differences_as_expansions(Point2 a, Point2 b, Point2 c, Point2 d) noexcept;

// Stage 2: any coordinates within a range where expansion arithmetic on products of up to two
// (orient2d) or four (incircle) coordinates is exact: the determinant, expanded in the raw
// coordinates, as an exact floating-point expansion.
int orient2d_by_expansions(Point2 a, Point2 b, Point2 c) noexcept;
int incircle_by_expansions(Point2 a, Point2 b, Point2 c, Point2 d) noexcept;

// Stage 3: always applicable. Every coordinate is an integer multiple of a common power of two;
// the determinant of those integers is evaluated in fixed-size wide integers (up to 8,700 bits
// when the input mixes 2^-1074 with 2^1023).
int orient2d_by_wide_integers(Point2 a, Point2 b, Point2 c) noexcept;
int incircle_by_wide_integers(Point2 a, Point2 b, Point2 c, Point2 d) noexcept;

}  // namespace tincdt::predicates::detail
