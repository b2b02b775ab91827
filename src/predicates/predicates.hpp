// Exact geometric predicates: the sign is correct for every finite double input.
// (Contract fixed; implementation: a fast floating-point filter inline here, exact fallback in
// predicates.cpp.)
//
// Valid input: any finite doubles (subnormals included; no magnitude limit: intermediate
// overflow or underflow only sends the call to a slower exact path). NaN or infinite
// coordinates give an unspecified result.
//
// The filter is Shewchuk's stage A (J. R. Shewchuk, "Adaptive Precision Floating-Point
// Arithmetic and Fast Robust Geometric Predicates", 1997): the determinant in doubles, relative
// to the last point, accepted when its magnitude exceeds a bound on its rounding error. Its error
// analysis needs IEEE double rounding of every operation: no -ffast-math, no FMA contraction
// (the build sets -ffp-contract=off), no x87 excess precision.
#pragma once

#include <cmath>

#include "core/types.hpp"

#if defined(__FAST_MATH__)
#error "tincdt predicates need IEEE arithmetic: do not build with -ffast-math"
#endif

namespace tincdt::predicates {

namespace detail {

// Exact sign of the same determinants, for the calls the filter cannot decide.
int orient2d_exact(Point2 a, Point2 b, Point2 c) noexcept;
int incircle_exact(Point2 a, Point2 b, Point2 c, Point2 d) noexcept;
// incircle_exact(), with a tie (0) decided by the symbolic perturbation of incircle_perturbed().
int incircle_perturbed_exact(Point2 a, Point2 b, Point2 c, Point2 d) noexcept;

// Half an ulp of 1.0: the relative rounding error of one correctly rounded operation.
inline constexpr double kEpsilon = 0x1p-53;
// Shewchuk's stage-A bounds: |computed det - exact det| <= k * permanent, where the permanent is
// the determinant's expansion with every term taken in absolute value (computed in doubles too;
// the epsilon^2 terms pay for that).
inline constexpr double kOrientErrorBound = (3.0 + 16.0 * kEpsilon) * kEpsilon;
inline constexpr double kIncircleErrorBound = (10.0 + 96.0 * kEpsilon) * kEpsilon;
// Stage A assumes no underflow. A product that lands in the subnormal range is off by up to
// 2^-1075 absolutely, and incircle multiplies such errors once more by a lift or a 2x2 minor.
// Adding a few times 2^-1075 per unit of those factors keeps the bound valid for all finite
// inputs. Any guard >= 2^-1070 will do; 2^-1000 keeps the guard term a normal number (a
// subnormal result costs a ~100-cycle microcode assist on x86) and is still negligible next to
// the rounding term for any data whose coordinate differences exceed ~1e-70.
inline constexpr double kUnderflowGuard = 0x1p-1000;

inline int sign_of(double value) noexcept {
  return (value > 0.0) - (value < 0.0);
}

}  // namespace detail

// +1 if a, b, c turn counter-clockwise, -1 if clockwise, 0 if collinear.
inline int orient2d(Point2 a, Point2 b, Point2 c) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  const double det = left - right;
  // One bound for all sign combinations: when left and right differ in sign the bound is
  // loose but |det| ~ |left| + |right| clears it anyway, so no branches on the signs.
  const double bound =
      detail::kOrientErrorBound * (std::fabs(left) + std::fabs(right)) + detail::kUnderflowGuard;
  // Overflow makes det or bound inf/NaN, which fails this test and goes to the exact path.
  if (std::fabs(det) > bound) [[likely]]
    return detail::sign_of(det);
  return detail::orient2d_exact(a, b, c);
}

namespace detail {

// Stage A of incircle and incircle_perturbed below: the sign of the determinant when the
// floating-point filter can decide it, else Exact(a, b, c, d).
template <int (*Exact)(Point2, Point2, Point2, Point2) noexcept>
inline int incircle_filtered(Point2 a, Point2 b, Point2 c, Point2 d) {
  const double adx = a.x - d.x;
  const double ady = a.y - d.y;
  const double bdx = b.x - d.x;
  const double bdy = b.y - d.y;
  const double cdx = c.x - d.x;
  const double cdy = c.y - d.y;

  const double bdxcdy = bdx * cdy;
  const double cdxbdy = cdx * bdy;
  const double alift = adx * adx + ady * ady;
  const double cdxady = cdx * ady;
  const double adxcdy = adx * cdy;
  const double blift = bdx * bdx + bdy * bdy;
  const double adxbdy = adx * bdy;
  const double bdxady = bdx * ady;
  const double clift = cdx * cdx + cdy * cdy;

  const double det =
      alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);

  const double a_minor_abs = std::fabs(bdxcdy) + std::fabs(cdxbdy);
  const double b_minor_abs = std::fabs(cdxady) + std::fabs(adxcdy);
  const double c_minor_abs = std::fabs(adxbdy) + std::fabs(bdxady);
  const double permanent = a_minor_abs * alift + b_minor_abs * blift + c_minor_abs * clift;
  // Underflow errors are multiplied by at most one lift or one minor (see kUnderflowGuard).
  const double guard_scale =
      (alift + blift + clift) + (a_minor_abs + b_minor_abs + c_minor_abs) + 1.0;
  const double bound = kIncircleErrorBound * permanent + kUnderflowGuard * guard_scale;
  if (std::fabs(det) > bound) [[likely]]
    return sign_of(det);
  return Exact(a, b, c, d);
}

}  // namespace detail

// For a, b, c counter-clockwise: +1 if d lies strictly inside their circumcircle, -1 if strictly
// outside, 0 if on it. (For a, b, c clockwise the sign is reversed, as the determinant is.)
inline int incircle(Point2 a, Point2 b, Point2 c, Point2 d) {
  return detail::incircle_filtered<detail::incircle_exact>(a, b, c, d);
}

// incircle() with every tie broken by a rule of the four points alone, so that the Delaunay
// triangulation of any point set is unique: a LiDAR lattice or grid, whose every cell is
// cocircular, then triangulates the same whatever the insertion order, thread count or tiling.
//
// The rule is a symbolic perturbation (Edelsbrunner and Muecke's Simulation of Simplicity, here
// on the lifting map as in Devillers and Teillaud, "Perturbations for Delaunay and weighted
// Delaunay 3D triangulations", 2011). incircle is the sign of the 4x4 determinant with rows
// (x, y, x^2 + y^2, 1) for a, b, c, d. Each point p is lifted by an extra infinitesimal eps_p,
// and the lexicographically larger a point (by x, then y) the larger its eps: with points
// p1 > p2 > ... in that order, eps_p1 >> eps_p2 >> ... > 0. The determinant is linear in the
// lifts, so it becomes det + sum over p of eps_p * C_p, where C_p is the cofactor of p's lift:
//   C_a = +orient(b, c, d), C_b = -orient(a, c, d), C_c = +orient(a, b, d), C_d = -orient(a, b, c),
// and its sign is that of det, or when det == 0 that of the first nonzero C_p in decreasing
// lexicographic order of p. Four distinct cocircular points have no three collinear, so the
// first cofactor already decides: the lexicographically largest of the four counts as lying just
// outside the circle through the other three.
//
// Properties the triangulation code relies on:
//  - It is the sign of one determinant of perturbed points, so permuting a, b, c, d changes it
//    as it changes the determinant: seen from either triangle of an edge, the "locally Delaunay"
//    test agrees, and after a flip the new edge is locally Delaunay. Lawson's flips cannot cycle.
//  - Only the lifts move, never x or y: orient2d stays exact and unperturbed, so the convex hull,
//    collinear points on it and every orientation decision are the exact ones; the perturbed
//    points are the corners of a lower convex hull in general position (no four lifted points
//    coplanar), whose projection is the unique perturbed Delaunay triangulation.
//  - It refines incircle(): whenever incircle() is nonzero, both agree. A perturbed Delaunay
//    triangulation is a Delaunay triangulation.
// Returns 0 only when all four points lie on one line. Costs nothing more than incircle() unless
// the exact determinant is 0.
inline int incircle_perturbed(Point2 a, Point2 b, Point2 c, Point2 d) {
  return detail::incircle_filtered<detail::incircle_perturbed_exact>(a, b, c, d);
}

}  // namespace tincdt::predicates
