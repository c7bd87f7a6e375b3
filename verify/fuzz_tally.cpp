#include "verify/fuzz_tally.h"

#include <algorithm>
#include <cmath>

namespace rayproof::verify {

void FuzzTally::add(const Stats& s) {
  for (const std::uint64_t u : s.ulps) ulps.add(u);
  for (const double e : s.bary_errors) {
    ++bary_count;
    if (std::isnan(e) || e > bary_max) bary_max = std::isnan(e) ? INFINITY : e;
  }
  // The counters and the worst case, without copying the per-case vectors.
  Stats c;
  c.cases = s.cases, c.false_hit = s.false_hit, c.false_miss = s.false_miss;
  c.wrong_hit_class = s.wrong_hit_class, c.wrong_class = s.wrong_class, c.fallbacks = s.fallbacks;
  c.kernel_failures = s.kernel_failures, c.coarse = s.coarse;
  c.promised = s.promised, c.promise_broken = s.promise_broken;
  counts.merge(c);
  if (s.worst && (!counts.worst || s.worst->ulps > counts.worst->ulps)) counts.worst = s.worst;
}

void FuzzTally::merge(const FuzzTally& o) {
  counts.merge(o.counts);
  ulps.merge(o.ulps);
  bary_count += o.bary_count;
  bary_max = std::max(bary_max, o.bary_max);
}

std::size_t FuzzTally::bytes() const {
  std::size_t n = sizeof(*this) - sizeof(ulps) + ulps.bytes();
  if (counts.worst) n += counts.worst->input.family.capacity();
  return n;
}

std::vector<std::string> broken_promises(const FuzzTallies& tallies) {
  std::vector<std::string> out;
  for (const auto& [key, t] : tallies)
    if (t.counts.promise_broken > 0 && std::find(out.begin(), out.end(), key.first) == out.end()) out.push_back(key.first);
  return out;
}

}  // namespace rayproof::verify
