// The random first edge of the stochastic walks (point location on triangulations that need not
// be Delaunay): Marsaglia's xorshift64, cheap and good enough to break the cycles a fixed edge
// order can fall into. The state must not be 0.
#pragma once

#include <cstdint>

namespace tincdt {

// Advances STATE and returns a number in 0..2: the edge a walk tests first.
inline unsigned random_edge(std::uint64_t& state) {
  state ^= state << 13;
  state ^= state >> 7;
  state ^= state << 17;
  return static_cast<unsigned>(state % 3);
}

}  // namespace tincdt
