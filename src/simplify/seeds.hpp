// A greedy run from seeds: the insertions of the same run on a thinned subset of the points,
// which are nearly its own first ones at a fraction of their cost (see seeds.cpp).
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/progress.hpp"
#include "simplify/simplifier.hpp"

namespace tincdt::simplify::detail {

// A greedy run before finish(): its state, and the points it inserted, seeds first, in order.
struct Unfinished {
  std::unique_ptr<Simplifier> run;
  std::vector<std::uint32_t> order;
};

// The greedy run on the points of `set`, from the seeds a coarse run finds (depth: of coarse
// runs; 0 for the caller's), in `arena` (empty: its own).
Unfinished run_greedy(const PointSet& set, std::span<const std::uint32_t> kept,
                      std::span<const constraints::Segment> segments,
                      const SimplifyOptions& options, const ProgressFn* progress, int depth,
                      std::span<std::uint32_t> arena = {});

}  // namespace tincdt::simplify::detail
