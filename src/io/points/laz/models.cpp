#include "io/points/laz/models.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cassert>

namespace tincdt::io::laz {

namespace {
// Counts are halved once their total passes these, so that the models keep adapting.
constexpr std::uint32_t kBitCountLimit = 1u << BitModel::kProbabilityBits;
constexpr std::uint32_t kSymbolCountLimit = 1u << SymbolModel::kDistributionBits;
constexpr std::uint32_t kBitCycleLimit = 64;
}  // namespace

void BitModel::reset() {
  zero_count_ = 1;
  bit_count_ = 2;
  zero_probability_ = 1u << (kProbabilityBits - 1);
  cycle_ = 4;  // frequent updates while the model knows little
  until_update_ = cycle_;
}

void BitModel::update() {
  bit_count_ += cycle_;
  if (bit_count_ > kBitCountLimit) {
    bit_count_ = (bit_count_ + 1) >> 1;
    zero_count_ = (zero_count_ + 1) >> 1;
    if (zero_count_ == bit_count_) ++bit_count_;  // a 1 must stay possible
  }
  const std::uint32_t scale = 0x80000000u / bit_count_;
  zero_probability_ = (zero_count_ * scale) >> (31 - kProbabilityBits);
  cycle_ = (5 * cycle_) >> 2;
  if (cycle_ > kBitCycleLimit) cycle_ = kBitCycleLimit;
  until_update_ = cycle_;
}

// The state every model of a size starts each chunk in, computed once per size: resetting is then
// one copy, which matters for the hundreds of models a chunk may start (and for small chunks).
const SymbolModel& SymbolModel::fresh(std::uint32_t symbols) {
  static std::array<std::atomic<const SymbolModel*>, kMaxSymbols + 1> cache{};
  const SymbolModel* model = cache[symbols].load(std::memory_order_acquire);
  if (model != nullptr) return *model;
  auto* made = new SymbolModel(symbols, Counted{});
  if (cache[symbols].compare_exchange_strong(model, made, std::memory_order_acq_rel)) return *made;
  delete made;  // another thread was first
  return *model;
}

SymbolModel::SymbolModel(std::uint32_t symbols) : symbols_(symbols) {
  allocate();
  reset();
}

SymbolModel::SymbolModel(std::uint32_t symbols, Counted) : symbols_(symbols) {
  allocate();
  count_from_scratch();
}

void SymbolModel::allocate() {
  assert(symbols_ >= 2 && symbols_ <= kMaxSymbols);  // the format's models are all in range
  if (symbols_ > 16) {
    // A table of 2^bits entries, with bits growing with the alphabet (8 entries up to 32 symbols).
    unsigned table_bits = 3;
    while (symbols_ > (1u << (table_bits + 2))) ++table_bits;
    table_size_ = 1u << table_bits;
    table_shift_ = kDistributionBits - table_bits;
  }
  storage_.assign(2 * std::size_t{symbols_} + (table_shift_ != 0 ? table_size_ + 2 : 0), 0);
}

void SymbolModel::reset() {
  const SymbolModel& start = fresh(symbols_);
  std::copy(start.storage_.begin(), start.storage_.end(), storage_.begin());
  total_count_ = start.total_count_;
  cycle_ = start.cycle_;
  until_update_ = start.until_update_;
}

void SymbolModel::count_from_scratch() {
  std::uint32_t* counts = storage_.data() + symbols_;
  for (std::uint32_t s = 0; s < symbols_; ++s) counts[s] = 1;
  total_count_ = 0;
  cycle_ = symbols_;
  update();
  cycle_ = (symbols_ + 6) >> 1;
  until_update_ = cycle_;
}

void SymbolModel::update() {
  std::uint32_t* distribution = storage_.data();
  std::uint32_t* counts = distribution + symbols_;
  total_count_ += cycle_;
  if (total_count_ > kSymbolCountLimit) {
    total_count_ = 0;
    for (std::uint32_t s = 0; s < symbols_; ++s) {
      counts[s] = (counts[s] + 1) >> 1;
      total_count_ += counts[s];
    }
  }
  const std::uint32_t scale = 0x80000000u / total_count_;
  std::uint32_t sum = 0;
  if (table_shift_ == 0) {
    for (std::uint32_t s = 0; s < symbols_; ++s) {
      distribution[s] = (scale * sum) >> (31 - kDistributionBits);
      sum += counts[s];
    }
  } else {
    std::uint32_t* table = counts + symbols_;
    std::uint32_t filled = 0;  // table entries 1..filled are set
    for (std::uint32_t s = 0; s < symbols_; ++s) {
      distribution[s] = (scale * sum) >> (31 - kDistributionBits);
      sum += counts[s];
      const std::uint32_t top = distribution[s] >> table_shift_;
      while (filled < top) table[++filled] = s - 1;
    }
    table[0] = 0;
    while (filled <= table_size_) table[++filled] = symbols_ - 1;
  }
  cycle_ = (5 * cycle_) >> 2;
  const std::uint32_t max_cycle = (symbols_ + 6) << 3;
  if (cycle_ > max_cycle) cycle_ = max_cycle;
  until_update_ = cycle_;
}

}  // namespace tincdt::io::laz
