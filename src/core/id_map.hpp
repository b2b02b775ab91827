// 64-bit keys to 32-bit ids in open addressing (linear probing, at most half full): for the few
// entries of something large (edges that are constrained, points that are vertices), where an
// array over all of it would cost memory and a std::map a heap node per entry.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/types.hpp"

namespace tincdt {

class IdMap {
 public:
  // Sets the id of KEY (kNoId is not an id).
  void insert(std::uint64_t key, std::uint32_t id) {
    if (2 * (count_ + 1) > slots_.size()) grow();
    std::size_t i = slot_of(key);
    while (slots_[i].id != kNoId && slots_[i].key != key) i = (i + 1) & (slots_.size() - 1);
    if (slots_[i].id == kNoId) ++count_;
    slots_[i] = {key, id};
  }
  // The id of KEY, or kNoId.
  std::uint32_t find(std::uint64_t key) const {
    if (slots_.empty()) return kNoId;
    for (std::size_t i = slot_of(key);; i = (i + 1) & (slots_.size() - 1)) {
      if (slots_[i].id == kNoId) return kNoId;
      if (slots_[i].key == key) return slots_[i].id;
    }
  }

 private:
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t id = kNoId;
  };
  std::size_t slot_of(std::uint64_t key) const {
    return static_cast<std::size_t>((key * 0x9e3779b97f4a7c15ULL) >> 20) & (slots_.size() - 1);
  }
  void grow() {
    std::vector<Slot> old = std::move(slots_);
    slots_.assign(std::max<std::size_t>(1024, old.size() * 2), Slot{});
    count_ = 0;
    for (const Slot& s : old)
      if (s.id != kNoId) insert(s.key, s.id);
  }
  std::vector<Slot> slots_;
  std::size_t count_ = 0;
};

}  // namespace tincdt
