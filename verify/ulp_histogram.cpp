#include "verify/ulp_histogram.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

namespace rayproof::verify {

namespace {
constexpr std::uint64_t kMax = std::numeric_limits<std::uint64_t>::max();
constexpr std::size_t kSub = std::size_t{1} << UlpHistogram::kSubBits;  // 128
constexpr std::size_t kMaxBucket = UlpHistogram::kBuckets - 1;          // UINT64_MAX alone
}  // namespace

std::size_t UlpHistogram::bucket_of(std::uint64_t u) {
  if (u < kExactBelow) return static_cast<std::size_t>(u);
  if (u == kMax) return kMaxBucket;
  const int e = 63 - std::countl_zero(u);  // 2^e <= u < 2^(e+1), e >= 8
  const std::size_t sub = static_cast<std::size_t>(u >> (e - kSubBits)) - kSub;
  return kExactBelow + static_cast<std::size_t>(e - 8) * kSub + sub;
}

std::uint64_t UlpHistogram::bucket_lo(std::size_t b) {
  if (b < kExactBelow) return b;
  if (b >= kMaxBucket) return kMax;
  const std::size_t k = b - kExactBelow;
  const int e = 8 + static_cast<int>(k / kSub);
  return (kSub + k % kSub) << (e - kSubBits);
}

std::uint64_t UlpHistogram::bucket_hi(std::size_t b) {
  if (b < kExactBelow || b >= kMaxBucket) return bucket_lo(b);
  const int e = 8 + static_cast<int>((b - kExactBelow) / kSub);
  const std::uint64_t hi = bucket_lo(b) + ((std::uint64_t{1} << (e - kSubBits)) - 1);
  return hi == kMax ? kMax - 1 : hi;  // UINT64_MAX has its own bucket
}

void UlpHistogram::add(std::uint64_t u, std::uint64_t n) {
  if (n == 0) return;
  if (counts_.empty()) counts_.assign(kBuckets, 0);
  counts_[bucket_of(u)] += n;
  min_ = total_ ? std::min(min_, u) : u;
  max_ = total_ ? std::max(max_, u) : u;
  total_ += n;
}

void UlpHistogram::merge(const UlpHistogram& o) {
  if (o.total_ == 0) return;
  if (counts_.empty()) counts_.assign(kBuckets, 0);
  for (std::size_t b = 0; b < kBuckets; ++b) counts_[b] += o.counts_[b];
  min_ = total_ ? std::min(min_, o.min_) : o.min_;
  max_ = total_ ? std::max(max_, o.max_) : o.max_;
  total_ += o.total_;
}

std::optional<std::uint64_t> UlpHistogram::count_of(std::uint64_t u) const {
  const std::size_t b = bucket_of(u);
  if (bucket_lo(b) != bucket_hi(b)) return std::nullopt;
  return b < counts_.size() ? counts_[b] : 0;
}

UlpHistogram::Range UlpHistogram::quantile(double q) const {
  if (total_ == 0) return {};
  const double want = std::ceil(std::clamp(q, 0.0, 1.0) * static_cast<double>(total_));
  const std::uint64_t rank = std::clamp<std::uint64_t>(static_cast<std::uint64_t>(want), 1, total_);
  if (rank == total_) return {max_, max_};
  if (rank == 1) return {min_, min_};
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < counts_.size(); ++b) {
    seen += counts_[b];
    if (seen >= rank) return {std::max(bucket_lo(b), min_), std::min(bucket_hi(b), max_)};
  }
  return {max_, max_};  // not reached: the counts add up to total_
}

std::vector<UlpHistogram::Bucket> UlpHistogram::buckets() const {
  std::vector<Bucket> out;
  for (std::size_t b = 0; b < counts_.size(); ++b)
    if (counts_[b]) out.push_back({bucket_lo(b), bucket_hi(b), counts_[b]});
  return out;
}

std::optional<UlpHistogram> UlpHistogram::from_buckets(const std::vector<Bucket>& bs, std::uint64_t min,
                                                       std::uint64_t max, const char*& error) {
  UlpHistogram h;
  std::optional<std::size_t> last;
  for (const auto& x : bs) {
    const std::size_t b = bucket_of(x.lo);
    if (bucket_lo(b) != x.lo || bucket_hi(b) != x.hi) return error = "a t error bucket is not a bucket", std::nullopt;
    if (last && b <= *last) return error = "the t error buckets are not in ascending order", std::nullopt;
    if (x.count == 0) return error = "a t error bucket is empty", std::nullopt;
    if (h.total_ > kMax - x.count) return error = "the t error counts overflow", std::nullopt;
    last = b;
    if (h.counts_.empty()) h.counts_.assign(kBuckets, 0);
    h.counts_[b] = x.count;
    h.total_ += x.count;
  }
  if (h.total_ == 0) return h;
  if (min > max || bucket_of(min) != bucket_of(bs.front().lo) || bucket_of(max) != bucket_of(bs.back().lo))
    return error = "the smallest or largest t error is not in the first or last bucket", std::nullopt;
  if (h.total_ == 1 && min != max) return error = "one t error with different smallest and largest", std::nullopt;
  h.min_ = min, h.max_ = max;
  return h;
}

bool operator==(const UlpHistogram& a, const UlpHistogram& b) {
  if (a.total_ != b.total_ || a.min() != b.min() || a.max() != b.max()) return false;
  return a.total_ == 0 || a.counts_ == b.counts_;
}

}  // namespace rayproof::verify
