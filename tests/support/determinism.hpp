// What the determinism tests of the Delaunay and constraint stages share: the ways of running
// the Delaunay stage, and bit-for-bit comparison of two triangulations.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <limits>
#include <vector>

#include "mesh/triangulation.hpp"

namespace tincdt::test {

// How to run the Delaunay stage: the size from which it splits the points in two halves (kNever:
// the sequential path), and its threads.
struct DelaunayWay {
  const char* name;
  std::size_t parallel_min_points;
  unsigned threads;
};
inline constexpr std::size_t kNever = std::numeric_limits<std::size_t>::max();
inline constexpr DelaunayWay kSequential{"sequential", kNever, 0};
inline constexpr DelaunayWay kHalvesOneThread{"halves, 1 thread", 0, 1};
inline constexpr DelaunayWay kHalvesTwoThreads{"halves, 2 threads", 0, 2};

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

// Vertex coordinates and heights, and triangle corners (so also their order and rotation), bit
// for bit.
inline ::testing::AssertionResult same_vertices_and_corners(const mesh::Triangulation& a,
                                                            const mesh::Triangulation& b) {
  if (!same_bytes(a.points(), b.points()))
    return ::testing::AssertionFailure() << "vertices differ";
  if (!same_bytes(a.heights(), b.heights())) return ::testing::AssertionFailure() << "z differs";
  if (a.corners() != b.corners()) return ::testing::AssertionFailure() << "triangles differ";
  return ::testing::AssertionSuccess();
}

}  // namespace tincdt::test
