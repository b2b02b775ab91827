// The LAZ arithmetic decoder, models and integer decompressor against an independent encoder
// (laz_test_encoder.hpp): random streams of every kind of symbol must come back exactly, and the
// decoder must read exactly the bytes the encoder wrote.

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "io/points/laz/arithmetic_decoder.hpp"
#include "io/points/laz/integer_decompressor.hpp"
#include "io/points/laz/models.hpp"
#include "io/points/laz/predictors.hpp"
#include "io/points/laz_test_encoder.hpp"

namespace tincdt::io::laz {
namespace {

using test::IntegerTestCompressor;
using test::LazTestEncoder;

// One coded value of a mixed stream: which coder call, its model and its value.
struct Step {
  int kind;  // 0 bit, 1 symbol, 2 raw bits, 3 integer
  unsigned model;
  std::uint32_t value;
  std::int32_t prediction;
};

// Skewed values, as real data gives the adaptive models something to learn.
std::uint32_t skewed(std::mt19937& rng, std::uint32_t n) {
  std::geometric_distribution<std::uint32_t> geo(0.3);
  return std::uniform_int_distribution<int>(0, 3)(rng) == 0
             ? std::uniform_int_distribution<std::uint32_t>(0, n - 1)(rng)
             : geo(rng) % n;
}

class CoderRoundTrip : public ::testing::TestWithParam<std::uint32_t> {};

TEST_P(CoderRoundTrip, MixedStreamsDecodeToWhatWasEncoded) {
  std::mt19937 rng(GetParam());
  // Alphabet sizes on both sides of the lookup-table threshold (16) and up to the largest.
  const std::vector<std::uint32_t> sizes = {2, 3, 5, 16, 17, 33, 64, 128, 256, 515, 2048};
  const unsigned steps = 20000;
  std::vector<Step> script;
  for (unsigned i = 0; i < steps; ++i) {
    Step s{};
    s.kind = std::uniform_int_distribution<int>(0, 3)(rng);
    switch (s.kind) {
      case 0:
        s.model = std::uniform_int_distribution<unsigned>(0, 2)(rng);
        s.value = skewed(rng, 2);
        break;
      case 1:
        s.model = std::uniform_int_distribution<unsigned>(
            0, static_cast<unsigned>(sizes.size()) - 1)(rng);
        s.value = skewed(rng, sizes[s.model]);
        break;
      case 2:
        s.model = std::uniform_int_distribution<unsigned>(1, 32)(rng);  // bit count
        s.value = static_cast<std::uint32_t>(rng()) >> (32 - s.model);
        break;
      default: {
        s.model = std::uniform_int_distribution<unsigned>(0, 3)(rng);  // context
        s.prediction = static_cast<std::int32_t>(rng());
        const int spread = std::uniform_int_distribution<int>(0, 31)(rng);
        const auto delta = static_cast<std::int32_t>(rng() >> (31 - spread % 31)) -
                           (std::int32_t{1} << (spread % 31));
        s.value = static_cast<std::uint32_t>(s.prediction) + static_cast<std::uint32_t>(delta);
        if (i % 97 == 0)
          s.value = static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::min());
        break;
      }
    }
    script.push_back(s);
  }

  std::vector<BitModel> enc_bits(3);
  std::vector<SymbolModel> enc_symbols;
  for (std::uint32_t n : sizes) enc_symbols.emplace_back(n);
  IntegerTestCompressor enc_ic(32, 4);
  LazTestEncoder enc;
  for (const Step& s : script) {
    switch (s.kind) {
      case 0:
        enc.encode_bit(enc_bits[s.model], s.value);
        break;
      case 1:
        enc.encode_symbol(enc_symbols[s.model], s.value);
        break;
      case 2:
        enc.write_bits(s.model, s.value);
        break;
      default:
        enc_ic.compress(enc, s.prediction, static_cast<std::int32_t>(s.value), s.model);
    }
  }
  const std::vector<std::uint8_t> bytes = enc.finish();

  std::vector<BitModel> bits(3);
  std::vector<SymbolModel> symbols;
  for (std::uint32_t n : sizes) symbols.emplace_back(n);
  IntegerDecompressor ic(32, 4);
  ic.reset();
  ArithmeticDecoder dec(bytes.data(), bytes.size());
  for (std::size_t i = 0; i < script.size(); ++i) {
    const Step& s = script[i];
    std::uint32_t got;
    switch (s.kind) {
      case 0:
        got = dec.decode_bit(bits[s.model]);
        break;
      case 1:
        got = dec.decode_symbol(symbols[s.model]);
        break;
      case 2:
        got = dec.read_bits(s.model);
        break;
      default:
        got = static_cast<std::uint32_t>(ic.decompress(dec, s.prediction, s.model));
    }
    ASSERT_EQ(got, s.value) << "step " << i << " kind " << s.kind;
  }
  EXPECT_FALSE(dec.failed());
  // The encoder's padding keeps the decoder in step: it ends exactly at the last byte.
  EXPECT_EQ(dec.consumed(), bytes.size());
}

INSTANTIATE_TEST_SUITE_P(Seeds, CoderRoundTrip, ::testing::Values(1u, 2u, 3u, 20240601u));

TEST(IntegerDecompressor, SixteenBitValuesWrapLikeTheEncoder) {
  std::mt19937 rng(7);
  IntegerTestCompressor enc_ic(16, 2);
  LazTestEncoder enc;
  std::vector<std::pair<std::int32_t, std::int32_t>> pairs;  // prediction, value
  for (int i = 0; i < 5000; ++i) {
    // Values in [0, 65535] (intensity, point source) and predictions that may be negative
    // (scan angles are signed 16-bit).
    const std::int32_t value = std::uniform_int_distribution<std::int32_t>(0, 65535)(rng);
    const std::int32_t prediction = std::uniform_int_distribution<std::int32_t>(-32768, 65535)(rng);
    pairs.emplace_back(prediction, value);
    enc_ic.compress(enc, prediction, value, static_cast<unsigned>(i & 1));
  }
  const std::vector<std::uint8_t> bytes = enc.finish();
  IntegerDecompressor ic(16, 2);
  ic.reset();
  ArithmeticDecoder dec(bytes.data(), bytes.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    ASSERT_EQ(ic.decompress(dec, pairs[i].first, static_cast<unsigned>(i & 1)), pairs[i].second)
        << i;
  }
  EXPECT_EQ(dec.consumed(), bytes.size());
}

TEST(ArithmeticDecoder, ReportsDataThatEndsEarly) {
  LazTestEncoder enc;
  SymbolModel m(256);
  std::mt19937 rng(3);
  for (int i = 0; i < 4000; ++i) enc.encode_symbol(m, rng() % 256);
  std::vector<std::uint8_t> bytes = enc.finish();
  bytes.resize(bytes.size() / 2);
  SymbolModel d(256);
  ArithmeticDecoder dec(bytes.data(), bytes.size());
  for (int i = 0; i < 4000; ++i) dec.decode_symbol(d);
  EXPECT_TRUE(dec.failed());
  EXPECT_GT(dec.consumed(), bytes.size());
}

TEST(ArithmeticDecoder, RefusesAStartNoEncoderWrites) {
  const std::uint8_t ones[] = {0xFF, 0xFF, 0xFF, 0xFF, 0x00};
  ArithmeticDecoder dec(ones, sizeof ones);
  EXPECT_TRUE(dec.failed());
  const std::uint8_t fine[] = {0xFF, 0xFF, 0xFF, 0xFE, 0x00};
  EXPECT_FALSE(ArithmeticDecoder(fine, sizeof fine).failed());
}

TEST(ArithmeticDecoder, GarbageNeverLeavesTheModelsBounds) {
  // Whatever the bytes, decoded symbols stay in their alphabets (the tables index with them).
  std::mt19937 rng(11);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<std::uint8_t> bytes(64);
    for (auto& b : bytes) b = static_cast<std::uint8_t>(rng());
    std::vector<SymbolModel> models;
    for (std::uint32_t n : {2u, 16u, 17u, 256u, 2048u}) models.emplace_back(n);
    BitModel bit;
    ArithmeticDecoder dec(bytes.data(), bytes.size());
    if (dec.failed()) continue;
    for (int i = 0; i < 500; ++i) {
      SymbolModel& m = models[static_cast<std::size_t>(i) % models.size()];
      ASSERT_LT(dec.decode_symbol(m), m.symbols());
      ASSERT_LE(dec.decode_bit(bit), 1u);
    }
  }
}

// laz_fuzz found a damaged point14 chunk whose value grew past the interval length mid-stream:
// the symbol lookup then indexed past the model's table (AddressSanitizer). Streams of mostly
// 0xFF bytes keep the value near the top; every lookup must stay inside the model.
TEST(ArithmeticDecoder, AValueAboveTheLengthStaysInsideTheTable) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<std::uint8_t> bytes(256);
    for (auto& b : bytes) b = rng() % 8 == 0 ? static_cast<std::uint8_t>(rng()) : 0xFF;
    bytes[3] = 0xFE;  // a start an encoder could write
    std::vector<SymbolModel> models;
    for (std::uint32_t n : {17u, 256u, 2048u}) models.emplace_back(n);
    ArithmeticDecoder dec(bytes.data(), bytes.size());
    for (int i = 0; i < 2000 && !dec.failed(); ++i) {
      SymbolModel& m = models[static_cast<std::size_t>(i) % models.size()];
      ASSERT_LT(dec.decode_symbol(m), m.symbols());
    }
  }
}

TEST(Median5, IsTheMiddleOfAWindowThatAlternatesEnds) {
  // The sorted window after each value, as the format defines it.
  Median5 m;
  m.reset();
  EXPECT_EQ(m.get(), 0);
  m.add(5);  // high end replaced: {0,0,0,0,5}
  EXPECT_EQ(m.get(), 0);
  m.add(7);  // low end replaced: {0,0,0,5,7}
  EXPECT_EQ(m.get(), 0);
  m.add(9);  // {0,0,5,7,9}
  EXPECT_EQ(m.get(), 5);
  m.add(8);  // low: {0,5,7,8,9}
  EXPECT_EQ(m.get(), 7);
  m.add(-3);  // {-3,5,7,8,9}: below the median, so the low end goes
  EXPECT_EQ(m.get(), 7);
  m.add(1);  // high end dropped: {-3,1,5,7,8}
  EXPECT_EQ(m.get(), 5);
}

TEST(ReturnContexts, LevelIsTheDistanceToTheLastReturnCappedAtSeven) {
  EXPECT_EQ(return_level(1, 1), 0u);
  EXPECT_EQ(return_level(3, 1), 2u);
  EXPECT_EQ(return_level(15, 0), 7u);
  EXPECT_EQ(return_level(0, 9), 7u);
  // The valid (n, r) pairs of formats 0-5 get the first 15 contexts, in order.
  unsigned expected = 0;
  for (unsigned n = 1; n <= 5; ++n) {
    for (unsigned r = 1; r <= n; ++r) EXPECT_EQ(kReturnMap8[n][r], expected++) << n << "," << r;
  }
}

}  // namespace
}  // namespace tincdt::io::laz
