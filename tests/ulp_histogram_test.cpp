// UlpHistogram (verify/ulp_histogram.h): buckets, exact counts, quantile bounds, merge by addition.
#include "verify/ulp_histogram.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

using rayproof::verify::UlpHistogram;

namespace {
constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();

/// The nearest-rank q-quantile of the values, computed from the sorted values.
std::uint64_t exact_quantile(std::vector<std::uint64_t> v, double q) {
  std::sort(v.begin(), v.end());
  const auto rank = std::clamp<std::uint64_t>(static_cast<std::uint64_t>(std::ceil(q * double(v.size()))), 1, v.size());
  return v[rank - 1];
}
}  // namespace

TEST(UlpHistogram, BucketsTileTheRangeAndAreNarrow) {
  EXPECT_EQ(UlpHistogram::bucket_of(0), 0u);
  EXPECT_EQ(UlpHistogram::bucket_of(255), 255u);
  EXPECT_EQ(UlpHistogram::bucket_of(256), 256u);
  EXPECT_EQ(UlpHistogram::bucket_of(257), 256u);  // [256, 257]: width 2
  EXPECT_EQ(UlpHistogram::bucket_of(kMax), UlpHistogram::kBuckets - 1);
  EXPECT_EQ(UlpHistogram::bucket_of(kMax - 1), UlpHistogram::kBuckets - 2);
  // Consecutive buckets touch, every bucket maps back to itself, widths stay under 1/128.
  for (std::size_t b = 0; b < UlpHistogram::kBuckets; ++b) {
    const auto lo = UlpHistogram::bucket_lo(b), hi = UlpHistogram::bucket_hi(b);
    ASSERT_LE(lo, hi) << b;
    EXPECT_EQ(UlpHistogram::bucket_of(lo), b);
    EXPECT_EQ(UlpHistogram::bucket_of(hi), b);
    if (b + 1 < UlpHistogram::kBuckets) {
      EXPECT_EQ(hi + 1, UlpHistogram::bucket_lo(b + 1)) << b;
    }
    if (b < UlpHistogram::kExactBelow || b + 1 == UlpHistogram::kBuckets) {
      EXPECT_EQ(lo, hi) << b;
    } else {
      EXPECT_LT(hi - lo, lo >> UlpHistogram::kSubBits) << b;  // (hi - lo) / lo < 1/128
    }
  }
}

TEST(UlpHistogram, QuantilesBracketTheExactOnesAndAreExactWhereTheySaySo) {
  std::mt19937_64 rng(3);
  std::vector<std::uint64_t> v;
  UlpHistogram h;
  for (int i = 0; i < 20000; ++i) {
    // Mostly small, some large, a few one-sided (UINT64_MAX).
    const int kind = static_cast<int>(rng() % 10);
    const std::uint64_t u = kind < 6 ? rng() % 4 : kind < 9 ? rng() >> (rng() % 64) : kMax;
    v.push_back(u);
    h.add(u);
  }
  EXPECT_EQ(h.count(), v.size());
  EXPECT_EQ(h.max(), kMax);
  EXPECT_EQ(h.min(), 0u);
  for (double q : {0.0, 0.1, 0.5, 0.6, 0.75, 0.9, 0.95, 0.99, 0.999, 1.0}) {
    const auto r = h.quantile(q);
    const auto want = exact_quantile(v, q);
    EXPECT_LE(r.lo, want) << q;
    EXPECT_GE(r.hi, want) << q;
    if (r.exact()) {
      EXPECT_EQ(r.lo, want) << q;
    } else {
      EXPECT_LE(double(r.hi - r.lo), UlpHistogram::kRelativeWidth * double(r.lo)) << q;
    }
  }
  EXPECT_EQ(h.quantile(1.0), (UlpHistogram::Range{kMax, kMax}));
  EXPECT_EQ(h.count_of(kMax), std::count(v.begin(), v.end(), kMax));
  EXPECT_EQ(h.count_of(2), std::count(v.begin(), v.end(), 2u));
  EXPECT_FALSE(h.count_of(1000).has_value()) << "a bucket of width > 1 cannot say";
}

TEST(UlpHistogram, KnownTallies) {
  UlpHistogram h;
  h.add(0, 98);
  h.add(1000);  // bucket [1000, 1003]
  h.add(5000);
  EXPECT_EQ(h.quantile(0.5), (UlpHistogram::Range{0, 0}));
  EXPECT_EQ(h.quantile(0.99), (UlpHistogram::Range{1000, 1003}));  // rank 99 of 100
  EXPECT_EQ(h.quantile(1.0), (UlpHistogram::Range{5000, 5000}));   // the max is exact
  UlpHistogram one;
  one.add(1001, 3);
  EXPECT_EQ(one.quantile(0.5), (UlpHistogram::Range{1001, 1001})) << "narrowed to [min, max]";
  EXPECT_EQ(UlpHistogram{}.quantile(0.5), (UlpHistogram::Range{0, 0}));
  EXPECT_EQ(UlpHistogram{}.max(), 0u);
}

TEST(UlpHistogram, MergeIsAdditionInAnyOrderAndMemoryIsBounded) {
  std::mt19937_64 rng(9);
  UlpHistogram whole, parts[3];
  for (int i = 0; i < 30000; ++i) {
    const std::uint64_t u = rng() >> (rng() % 64);
    whole.add(u);
    parts[i % 3].add(u);
  }
  UlpHistogram a = parts[2], b = parts[0];
  a.merge(parts[0]), a.merge(parts[1]);
  b.merge(parts[1]), b.merge(parts[2]);
  EXPECT_EQ(a, whole);
  EXPECT_EQ(b, whole);
  EXPECT_EQ(a.buckets(), whole.buckets());
  EXPECT_EQ(UlpHistogram{}.bytes(), sizeof(UlpHistogram));
  const std::size_t full = sizeof(UlpHistogram) + 8 * UlpHistogram::kBuckets;
  EXPECT_EQ(whole.bytes(), full);
  whole.add(kMax, 1000000);  // a million values more: the same counters
  EXPECT_EQ(whole.bytes(), full);
}

TEST(UlpHistogram, RoundTripsThroughItsBucketsAndRejectsOthers) {
  UlpHistogram h;
  for (std::uint64_t u : {0ull, 3ull, 3ull, 300ull, 70000ull, 1ull << 40, ~0ull}) h.add(u);
  const char* error = nullptr;
  auto back = UlpHistogram::from_buckets(h.buckets(), h.min(), h.max(), error);
  ASSERT_TRUE(back) << error;
  EXPECT_EQ(*back, h);
  auto bs = h.buckets();
  bs[3].lo += 1;  // not a bucket's lower bound
  EXPECT_FALSE(UlpHistogram::from_buckets(bs, h.min(), h.max(), error));
  bs = h.buckets();
  std::swap(bs[0], bs[1]);
  EXPECT_FALSE(UlpHistogram::from_buckets(bs, h.min(), h.max(), error));
  EXPECT_FALSE(UlpHistogram::from_buckets(h.buckets(), 5, h.max(), error)) << "min outside the first bucket";
  EXPECT_FALSE(UlpHistogram::from_buckets(h.buckets(), 0, 1000, error)) << "max outside the last bucket";
  EXPECT_TRUE(UlpHistogram::from_buckets({}, 0, 0, error));
}
