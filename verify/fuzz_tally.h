#pragma once
/// The streaming tally of one method x family in a fuzz campaign: Stats' counters and worst case,
/// the t errors as an UlpHistogram and the barycentric errors as a count and a maximum. Its size is
/// fixed however many cases it counts, and merging is addition (and max), so the tallies of a
/// campaign's rounds, jobs or shards add up to the whole run's exactly.
#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "verify/differential.h"
#include "verify/ulp_histogram.h"

namespace rayproof::verify {

struct FuzzTally {
  Stats counts;        ///< every counter and the worst case; its per-case vectors stay empty
  UlpHistogram ulps;   ///< t error of every class-correct case that carries t
  std::size_t bary_count = 0;  ///< coarse triangle hits with barycentrics
  double bary_max = 0;         ///< the largest max |b - exact b| among them (INFINITY for a NaN b)

  /// Adds a round's Stats: its counters, worst case and per-case t and barycentric errors.
  void add(const Stats& s);
  void merge(const FuzzTally& o);
  /// Bytes held (the object, its histogram, the worst case's strings): bounded, not per case.
  [[nodiscard]] std::size_t bytes() const;
};

using FuzzTallies = std::map<std::pair<std::string, std::string>, FuzzTally>;  ///< (method, family)

/// Methods with a broken promise (promise_broken > 0) in a campaign's tallies, each once.
[[nodiscard]] std::vector<std::string> broken_promises(const FuzzTallies& tallies);

}  // namespace rayproof::verify
