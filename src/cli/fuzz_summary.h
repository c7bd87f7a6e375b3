#pragma once
/// Summaries of fuzz campaigns as JSON (`fuzz --summary FILE.json`) and their merge
/// (`fuzz merge SUMMARY...`): the shards of one seeded campaign add up to exactly the counts of the
/// unsharded run. A summary names its campaign (seed, methods, families, cases per round, the
/// requested case count) and its shard, and holds every method x family tally with the t errors as
/// an UlpHistogram (exact counts in log-spaced buckets), so that the merge's histograms, and the
/// quantiles printed from them, are the whole run's bit for bit.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "verify/fuzz_campaign.h"

namespace rayproof::cli {

struct FuzzCampaign {
  std::uint64_t seed = 1;
  std::vector<std::string> methods, families;
  std::size_t batch = 64;         ///< cases per family per round
  std::size_t max_cases = 0;      ///< --cases (0: the run was bounded by --seconds)
  std::size_t shard_count = 1;
  friend bool operator==(const FuzzCampaign&, const FuzzCampaign&) = default;
};

struct FuzzSummary {
  FuzzCampaign campaign;
  std::vector<std::size_t> shards;  ///< 0-based shard indices this summary covers
  std::size_t rounds = 0, cases = 0;
  double seconds = 0;      ///< wall time (of a merge: the slowest shard's)
  double cpu_seconds = 0;  ///< CPU time (of a merge: the shards' sum)
  verify::FuzzTallies stats;  ///< (method, family)
  std::map<std::pair<std::string, std::string>, std::size_t> mismatches;
};

[[nodiscard]] FuzzSummary summarize(const FuzzCampaign& c, std::size_t shard_index, const verify::FuzzResult& r);

[[nodiscard]] std::string to_json(const FuzzSummary& s);
/// Reads a summary; an error message (naming the file) on malformed or foreign JSON.
[[nodiscard]] std::optional<FuzzSummary> summary_from_json(const std::string& text, const std::string& file,
                                                           std::string& error);

/// Adds summaries of one campaign. Errors (as a message): different campaigns (naming the field
/// that differs), a shard given twice, shards missing.
[[nodiscard]] std::optional<FuzzSummary> merge_summaries(const std::vector<FuzzSummary>& parts,
                                                         const std::vector<std::string>& files, std::string& error);

/// The table fuzz prints: per method x family cases, mismatches, rate, fallbacks, the t error's
/// median, 99th percentile and maximum in ulps, and the promise, then (all). A percentile known only
/// to its histogram bucket is printed as "<=" the bucket's upper bound, and a note under the table
/// says what that bound means.
[[nodiscard]] std::string fuzz_table(const std::vector<std::string>& methods, const std::vector<std::string>& families,
                                     const verify::FuzzTallies& stats,
                                     const std::map<std::pair<std::string, std::string>, std::size_t>& mismatches);

/// A t error quantile as the table prints it: the number when exact ("NaN t" for a t on one side
/// only), "<=HI" when only its bucket [lo, hi] is known.
[[nodiscard]] std::string quantile_text(const verify::UlpHistogram::Range& r);

/// "N cases in S s: R cases/s on J jobs, R/J per job; C per CPU second": the speed line of fuzz and
/// fuzz merge (per CPU second left out when no CPU time was measured).
[[nodiscard]] std::string speed_text(std::size_t cases, double seconds, double cpu_seconds, int jobs);

/// Parses "K/N" (1 <= K <= N <= 1000000) into a 0-based index and a count; nothing on bad text.
[[nodiscard]] std::optional<std::pair<std::size_t, std::size_t>> parse_shard(const std::string& text);

}  // namespace rayproof::cli
