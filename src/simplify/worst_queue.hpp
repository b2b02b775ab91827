// The queue of the greedy loop: which triangle holds the worst point not yet within the
// tolerance.
#pragma once

#include <algorithm>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/types.hpp"
#include "simplify/measure.hpp"

namespace tincdt::simplify::detail {

// A triangle's worst point, as the queue holds it.
struct Entry {
  double error;
  std::uint32_t point;
  TriangleId tri;
};

// The triangles beyond the tolerance, largest error first (equal errors by the points' x, then
// y), as a 4-ary heap that knows where each triangle is: an insertion updates or removes the
// entries of the slots it reused, so the heap holds one entry per unsettled triangle and never
// a stale one. (A lazy heap of duplicates grew to twice the triangle count, and its sift-downs
// were cache misses.) Four children are one or two cache lines, and half the levels of a
// binary heap.
class WorstQueue {
 public:
  explicit WorstQueue(const Point2* xy) : xy_(xy) {}

  bool empty() const { return heap_.empty(); }
  const Entry& top() const {
    assert(!heap_.empty());
    return heap_.front();
  }
  void grow(std::size_t slots) {
    if (pos_.size() < slots) pos_.resize(slots, kNoId);
  }

  // Adds an entry (its slot absent) without ordering; build() orders them all.
  void append(const Entry& e) {
    assert(e.tri < pos_.size() && pos_[e.tri] == kNoId);
    pos_[e.tri] = static_cast<std::uint32_t>(heap_.size());
    heap_.push_back(e);
  }
  void build() {
    for (std::size_t i = heap_.size() / 4 + 1; i-- > 0;)
      if (i < heap_.size()) down(static_cast<std::uint32_t>(i));
  }

  // The entry of e.tri becomes e (added if absent).
  void set(const Entry& e) {
    assert(e.tri < pos_.size());
    std::uint32_t i = pos_[e.tri];
    if (i == kNoId) {
      i = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back(e);
      up(i);
      return;
    }
    const bool rises = before(e, heap_[i]);
    heap_[i] = e;
    if (rises)
      up(i);
    else
      down(i);
  }

  void erase(TriangleId t) {
    const std::uint32_t i = pos_[t];
    if (i == kNoId) return;
    assert(i < heap_.size() && heap_[i].tri == t);
    pos_[t] = kNoId;
    const Entry last = heap_.back();
    heap_.pop_back();
    if (i == heap_.size()) return;
    heap_[i] = last;
    if (i > 0 && before(last, heap_[(i - 1) / 4]))
      up(i);
    else
      down(i);
  }

 private:
  bool before(const Entry& a, const Entry& b) const {
    if (a.error != b.error) return a.error > b.error;
    return xy_less(xy_[a.point], xy_[b.point]);
  }
  void up(std::uint32_t i) {
    const Entry e = heap_[i];
    while (i > 0) {
      const std::uint32_t parent = (i - 1) / 4;
      if (!before(e, heap_[parent])) break;
      heap_[i] = heap_[parent];
      pos_[heap_[i].tri] = i;
      i = parent;
    }
    heap_[i] = e;
    pos_[e.tri] = i;
  }
  void down(std::uint32_t i) {
    const Entry e = heap_[i];
    const auto n = static_cast<std::uint32_t>(heap_.size());
    for (;;) {
      const std::uint32_t first = 4 * i + 1;
      if (first >= n) break;
      std::uint32_t best = first;
      for (std::uint32_t c = first + 1; c < std::min(first + 4, n); ++c)
        if (before(heap_[c], heap_[best])) best = c;
      if (!before(heap_[best], e)) break;
      heap_[i] = heap_[best];
      pos_[heap_[i].tri] = i;
      i = best;
    }
    heap_[i] = e;
    pos_[e.tri] = i;
  }

  const Point2* xy_;
  std::vector<Entry> heap_;
  std::vector<std::uint32_t> pos_;  // per triangle slot: its place in heap_, or kNoId
};

}  // namespace tincdt::simplify::detail
