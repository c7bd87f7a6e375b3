#pragma once
/// Exact counts of integer errors (t errors in ulps) in log-spaced buckets, after HdrHistogram:
/// every value below 256 has a bucket of its own; above, each power of two [2^e, 2^(e+1)) is cut
/// into 128 equal sub-buckets, so a bucket is at most 1/128 of its lower bound wide (the upper bound
/// is within 0.79% of every value in the bucket); UINT64_MAX (a t on one side only) has a bucket of
/// its own. The smallest and the largest value are kept exactly. At most kBuckets counters, however
/// many values are added; merging is addition, so any split of a run adds up bit for bit to the
/// whole run's histogram, in any order.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

namespace rayproof::verify {

class UlpHistogram {
 public:
  static constexpr int kSubBits = 7;                                 ///< 2^7 sub-buckets per power of two
  static constexpr std::uint64_t kExactBelow = std::uint64_t{2} << kSubBits;  ///< 256: exact values below
  static constexpr std::size_t kBuckets = 256 + (64 - 8) * 128 + 1;  ///< 7425, the last one UINT64_MAX
  /// The largest relative width of a bucket: (hi - lo) / lo < 1/128 for every bucket.
  static constexpr double kRelativeWidth = 1.0 / 128;

  /// The bucket holding u, and its bounds (lo <= u <= hi; lo == hi below 256 and for UINT64_MAX).
  [[nodiscard]] static std::size_t bucket_of(std::uint64_t u);
  [[nodiscard]] static std::uint64_t bucket_lo(std::size_t b);
  [[nodiscard]] static std::uint64_t bucket_hi(std::size_t b);

  void add(std::uint64_t u, std::uint64_t n = 1);
  void merge(const UlpHistogram& o);

  [[nodiscard]] std::uint64_t count() const { return total_; }
  [[nodiscard]] bool empty() const { return total_ == 0; }
  [[nodiscard]] std::uint64_t min() const { return total_ ? min_ : 0; }  ///< exact; 0 when empty
  [[nodiscard]] std::uint64_t max() const { return total_ ? max_ : 0; }  ///< exact; 0 when empty
  /// How many values equal u exactly (u below 256 or UINT64_MAX), else nothing: a bucket's count
  /// does not say how many of its values are u.
  [[nodiscard]] std::optional<std::uint64_t> count_of(std::uint64_t u) const;

  /// The nearest-rank q-quantile (the value of rank max(1, ceil(q n)) in ascending order) lies in
  /// [lo, hi]: its bucket, narrowed to [min, max]. lo == hi when it is known exactly (a value below
  /// 256, UINT64_MAX, or the quantile is the min or max). {0, 0} when empty.
  struct Range {
    std::uint64_t lo = 0, hi = 0;
    [[nodiscard]] bool exact() const { return lo == hi; }
    friend bool operator==(const Range&, const Range&) = default;
  };
  [[nodiscard]] Range quantile(double q) const;

  struct Bucket {
    std::uint64_t lo = 0, hi = 0, count = 0;
    friend bool operator==(const Bucket&, const Bucket&) = default;
  };
  /// The buckets that hold something, in ascending order.
  [[nodiscard]] std::vector<Bucket> buckets() const;
  /// Rebuilds a histogram from buckets() and the exact min and max (as written to a summary); an
  /// error message on buckets that are not buckets, out of order, or disagree with min and max.
  [[nodiscard]] static std::optional<UlpHistogram> from_buckets(const std::vector<Bucket>& b, std::uint64_t min,
                                                                std::uint64_t max, const char*& error);

  /// Bytes held (the object and its counters): sizeof(UlpHistogram) while empty, then
  /// sizeof(UlpHistogram) + 8 kBuckets (the counters are allocated whole at the first value).
  [[nodiscard]] std::size_t bytes() const { return sizeof(*this) + counts_.capacity() * sizeof(std::uint64_t); }

  friend bool operator==(const UlpHistogram& a, const UlpHistogram& b);

 private:
  std::vector<std::uint64_t> counts_;  ///< kBuckets counters, or none while empty
  std::uint64_t total_ = 0, min_ = 0, max_ = 0;
};

}  // namespace rayproof::verify
