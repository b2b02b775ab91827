// The points and segments handed to simplify(), gathered one point a place (x, y): the tiles of
// a tiled job and of a web-terrain pyramid each build one from their border, their lines and the
// candidates inside.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "constraints/constraints.hpp"
#include "core/types.hpp"

namespace tincdt::simplify {

struct SimplifyInput {
  std::vector<Point2> xy;
  std::vector<double> z;
  std::vector<std::uint32_t> kept;
  std::vector<constraints::Segment> segments;

  // The kept point at XY: the one there already, else a new kept point at height Z.
  std::uint32_t add_kept(Point2 at, double height) {
    const auto [it, added] =
        kept_at_.try_emplace({at.x, at.y}, static_cast<std::uint32_t>(xy.size()));
    if (added) {
      xy.push_back(at);
      z.push_back(height);
      kept.push_back(it->second);
    }
    return it->second;
  }
  // A candidate point at XY, unless a kept point is there already (then that one). Candidates
  // are not looked up: the caller gives each place once.
  std::uint32_t add_candidate(Point2 at, double height) {
    if (const std::uint32_t id = find(at); id != kNoId) return id;
    xy.push_back(at);
    z.push_back(height);
    return static_cast<std::uint32_t>(xy.size() - 1);
  }
  // The kept point at XY, or kNoId.
  std::uint32_t find(Point2 at) const {
    const auto it = kept_at_.find({at.x, at.y});
    return it == kept_at_.end() ? kNoId : it->second;
  }

 private:
  std::map<std::pair<double, double>, std::uint32_t> kept_at_;
};

}  // namespace tincdt::simplify
