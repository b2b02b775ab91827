// The adaptive probability models of the LAZ arithmetic coder (LAZ specification 1.4; the coder
// is A. Said's "FastAC": 32-bit interval, counts refreshed periodically rather than on every
// symbol). A model learns from what it decodes, so the encoder and the decoder must make exactly
// the same updates at exactly the same moments: every constant below is part of the format.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace tincdt::io::laz {

// A two-symbol model: the probability of a 0 in 13-bit fixed point.
class BitModel {
 public:
  static constexpr unsigned kProbabilityBits = 13;

  BitModel() { reset(); }
  // Back to "0 and 1 equally likely", as at the start of every chunk.
  void reset();

  std::uint32_t zero_probability() const { return zero_probability_; }
  // Counts a decoded bit; refreshes the probability when its cycle is over.
  [[gnu::always_inline]] void count(std::uint32_t bit) {
    if (bit == 0) ++zero_count_;
    if (--until_update_ == 0) update();
  }

 private:
  [[gnu::noinline]] void update();

  std::uint32_t zero_probability_ = 0;
  std::uint32_t zero_count_ = 0;
  std::uint32_t bit_count_ = 0;
  std::uint32_t cycle_ = 0;
  std::uint32_t until_update_ = 0;
};

// A model of `symbols` symbols (2 to 2048): a cumulative distribution in 15-bit fixed point, and
// above 16 symbols a coarse lookup table that narrows the search for a decoded value.
class SymbolModel {
 public:
  static constexpr unsigned kDistributionBits = 15;
  static constexpr std::uint32_t kMaxSymbols = 2048;

  explicit SymbolModel(std::uint32_t symbols);
  // Every symbol equally likely, as at the start of every chunk.
  void reset();

  std::uint32_t symbols() const { return symbols_; }
  std::uint32_t last_symbol() const { return symbols_ - 1; }
  bool has_table() const { return table_shift_ != 0; }
  unsigned table_shift() const { return table_shift_; }
  // Start of symbol s's interval, s < symbols.
  std::uint32_t cumulative(std::uint32_t s) const { return storage_[s]; }
  // The lookup table: entry t is the first symbol whose interval can hold a value whose top
  // bits are t (entries 0 to table size + 1).
  std::uint32_t table(std::uint32_t t) const { return storage_[2 * symbols_ + t]; }

  [[gnu::always_inline]] void count(std::uint32_t symbol) {
    ++storage_[symbols_ + symbol];
    if (--until_update_ == 0) update();
  }

 private:
  struct Counted {};  // the constructor that computes the start state rather than copying it
  SymbolModel(std::uint32_t symbols, Counted);
  static const SymbolModel& fresh(std::uint32_t symbols);
  void allocate();
  void count_from_scratch();
  [[gnu::noinline]] void update();

  std::uint32_t symbols_;
  unsigned table_shift_ = 0;  // 0: no table (16 symbols or fewer)
  std::uint32_t table_size_ = 0;
  std::uint32_t total_count_ = 0;
  std::uint32_t cycle_ = 0;
  std::uint32_t until_update_ = 0;
  // One block: cumulative distribution (symbols), counts (symbols), table (table_size + 2).
  std::vector<std::uint32_t> storage_;
};

// N symbol models of one size that the format creates on first use (one per value of a context
// such as the previous classification): each is allocated when first needed and reset when first
// used in a chunk, so a chunk pays only for the contexts it meets.
template <std::size_t N>
class LazyModels {
 public:
  explicit LazyModels(std::uint32_t symbols) : symbols_(symbols) {}

  // The next chunk starts: every model is due for a reset before its next use.
  void new_chunk() { ++chunk_; }

  SymbolModel& operator[](std::size_t i) {
    Slot& slot = slots_[i];
    if (slot.chunk != chunk_) {
      if (slot.model) {
        slot.model->reset();
      } else {
        slot.model = std::make_unique<SymbolModel>(symbols_);
      }
      slot.chunk = chunk_;
    }
    return *slot.model;
  }

 private:
  struct Slot {
    std::unique_ptr<SymbolModel> model;
    std::uint64_t chunk = 0;
  };
  std::array<Slot, N> slots_{};
  std::uint32_t symbols_;
  std::uint64_t chunk_ = 1;
};

}  // namespace tincdt::io::laz
