// The regions' runs: large inputs simplified first in the cells of a grid, on all threads at
// once, to seed the run on all points (see regions.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/progress.hpp"
#include "simplify/seeds.hpp"

namespace tincdt::simplify::detail {

// The share of the stage's progress the regions take (the last run has the rest).
constexpr double kRegionProgress = 0.9;

// The regions' runs and what they hand on to the last run. The regions' runs and the last run
// share one arena, so that the last run takes the triangles it adopts as they are, in memory
// already written (fresh pages cost more than their use): each region's arena (arena_slots() of
// its points) in turn, then the regions' point lists, which the last run's new ranges overwrite
// once adopt() has read them.
struct Regions {
  std::unique_ptr<std::uint32_t[]> arena;
  std::size_t arena_size = 0;
  std::vector<std::span<const std::uint32_t>> members;  // each region's points, ascending
  std::vector<Unfinished> runs;                         // each region's, or none
  std::vector<std::uint32_t> seeds;  // all they inserted but near the seams, ascending
};

// The regions' runs, or none when the input is too small or the regions do not apply. `kept`
// holds the corners of the points' hull, so it spans their box.
Regions run_regions(const PointSet& set, std::span<const std::uint32_t> kept,
                    std::span<const constraints::Segment> segments, const SimplifyOptions& options,
                    const ProgressFn* progress);

}  // namespace tincdt::simplify::detail
