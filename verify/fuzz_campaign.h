#pragma once
/// Differential fuzz campaigns: generate cases from the families round after round, run every
/// chosen method, compare with exact, minimize what disagrees. Round r of family f always holds the
/// same cases for the same seed, so a campaign is reproducible on any machine: a run stops only at
/// round boundaries and says how many rounds it did.
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "gen/families.h"
#include "methods/method.h"
#include "verify/differential.h"
#include "verify/fuzz_tally.h"

namespace rayproof::verify {

struct FuzzProgress {
  double seconds = 0;
  std::size_t cases = 0;
  std::vector<std::pair<std::string, std::size_t>> mismatches;  ///< per method
};

struct FuzzOptions {
  std::vector<const Method*> methods;
  std::vector<const gen::Family*> families;
  double seconds = 0;        ///< stop after this long (at a round boundary); 0: use max_cases
  std::size_t max_cases = 0; ///< stop once this many cases are done (rounded up to whole rounds)
  std::uint64_t seed = 1;
  int jobs = 1;
  std::size_t batch = 64;              ///< cases per family per round
  std::size_t keep_per_group = 50;     ///< findings kept per method x family
  std::size_t minimize_per_group = 10; ///< of those, how many are minimized (kernel failures never are)
  std::function<void(const FuzzProgress&)> progress;  ///< called about every progress_seconds
  double progress_seconds = 1;
  /// Shard `shard_index` (0-based) of `shard_count` disjoint parts of the campaign: the rounds r with
  /// r % shard_count == shard_index (round r holds the same cases in every shard and in the whole
  /// run), so the shards of a --cases campaign add up to exactly the whole run.
  std::size_t shard_index = 0, shard_count = 1;
};

struct FuzzFinding {
  std::string method, family;
  std::size_t round = 0;
  io::Case input;      ///< as the method saw it, minimized when `minimized`
  io::CaseResult got, want;
  Verdict verdict = Verdict::agree;
  std::uint64_t ulps = 0;
  bool minimized = false;
};

/// What a campaign holds does not grow with its length: the tallies are fixed in size, findings are
/// kept only up to keep_per_group per method x family (the rest are counted in `mismatches`), and
/// finished rounds are folded in round order as soon as the rounds before them are done (a worker
/// waits rather than run more than a few rounds ahead of the oldest unfinished one).
struct FuzzResult {
  std::size_t rounds = 0, cases = 0;  ///< rounds and cases this run (or shard) did
  double seconds = 0;
  double cpu_seconds = 0;  ///< CPU time of the process (all threads) during the run
  FuzzTallies stats;       ///< (method, family)
  std::map<std::pair<std::string, std::string>, std::size_t> mismatches;
  std::vector<FuzzFinding> findings;  ///< the first keep_per_group per method x family, by method, family, round
  /// What user kernels (methods with take_failures) reported: crash, hang, early exit, unreadable
  /// answer, each with its case; (method, failure), in method order.
  std::vector<std::pair<std::string, KernelFailure>> kernel_failures;
  /// Methods that broke a promise they declare (Method::promises), in (method, family) order.
  [[nodiscard]] std::vector<std::string> broken_promises() const;
};

/// Methods with a broken promise (Stats::promise_broken > 0) in a tally, each once.
[[nodiscard]] std::vector<std::string> broken_promises(const std::map<std::pair<std::string, std::string>, Stats>& stats);

/// Does this judged answer count as a mismatch for the method? (a class error; or a t error beyond
/// the tolerance the method promises on the case's kind)
[[nodiscard]] bool is_mismatch(const Method& m, const Judged& j);

[[nodiscard]] FuzzResult run_fuzz(const FuzzOptions& opt);

/// Shrinks a disagreeing case while it keeps the same verdict for the method: fewer significant
/// bits per field, magnitudes scaled toward 1 by a common power of two. Bounded work. A method with
/// classify_batch (a user kernel) gets the tries of one field in one batch: about 30 calls per case.
[[nodiscard]] io::Case minimize_case(const Method& m, const io::Case& input, Verdict verdict);

/// Whether each variant still fails as the input it was made from (`owner[v]` indexes the inputs).
using StillFails = std::function<std::vector<bool>(const std::vector<io::Case>& variants,
                                                   const std::vector<std::size_t>& owner)>;
/// The shrinking of minimize_case for many inputs at once: every step's variants of all the inputs
/// are judged by one call of `still` (a batch for a kernel behind a pipe: 31 calls in all). Each
/// input ends where minimize_case would take it.
[[nodiscard]] std::vector<io::Case> minimize_cases(const std::vector<io::Case>& inputs, const StillFails& still);

}  // namespace rayproof::verify
