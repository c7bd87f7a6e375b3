#pragma once
/// The checker behind `rayproof check` and the library's `rayproof::verify::check`: one method (a
/// user's kernel or a built-in one) over every built-in case family of the kinds it answers, with a
/// fixed seed and count, judged against exact by the judgement of verify (run_and_tally), with the
/// promises the user states (watertight, exact class, a t error bound) kept or broken.
///
/// Cases: per family, count/2 built in float precision and the rest in double (as `report` does),
/// all from `seed`; the method answers them in batches (Method::classify_many), float methods on
/// the float-rounded inputs. Nothing here prints: progress goes to a callback.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "gen/families.h"
#include "methods/method.h"
#include "verify/differential.h"

namespace rayproof::verify {

/// The promises a user states about a kernel.
struct Promises {
  bool watertight = false;               ///< no false miss on the edge and vertex families (and no failure there)
  bool exact_class = false;              ///< no class error, and no kernel failure, on any family
  std::optional<std::uint64_t> max_ulps; ///< every class-correct t within this many ulps of exact
  /// No false miss (for triangle pairs: no pair that meets called disjoint), and no kernel failure,
  /// on any family. Last, so that {watertight, exact_class, max_ulps} initializers keep their meaning.
  bool no_false_negative = false;
};

struct CheckProgress {
  std::size_t families_done = 0, families_total = 0;
  std::size_t cases_done = 0;
  std::string family;  ///< the family just finished
};

struct CheckOptions {
  std::vector<const gen::Family*> families;  ///< empty: every built-in family with a kind the method answers
  std::size_t count = 2000;                  ///< cases per family (half float-built, half double-built)
  std::uint64_t seed = 1;
  std::uint64_t ulp_tolerance = 1;           ///< t errors above this are counted as over tolerance
  std::size_t batch = 1024;                  ///< cases per classify_many call
  std::size_t reproducers = 3;               ///< worst cases kept per family
  bool minimize = true;                      ///< shrink class-error reproducers as fuzz does
  Promises promises;
  std::function<void(const CheckProgress&)> progress{};
};

/// One bad case of the method: how it answered, what exact says.
struct Reproducer {
  std::string family;
  Judged judged;  ///< input as the method saw it (minimized when `minimized`), its answer, exact's
  bool minimized = false;
};

struct FamilyCheck {
  std::string family;
  io::Kind kind = io::Kind::triangle;
  Stats stats;
  std::size_t over_tolerance = 0;          ///< class-correct cases with t error > ulp_tolerance
  std::vector<KernelFailure> failures;     ///< crashes, hangs, unreadable answers (user kernels)
  std::vector<Reproducer> worst;           ///< class errors first (false miss, false hit, wrong class), then largest t error
};

struct PromiseCheck {
  std::string promise;  ///< "watertight", "exact-class", "max-ulps N"
  bool kept = true;
  std::size_t violations = 0;  ///< cases that break it
};

struct CheckResult {
  std::string method;
  Precision precision = Precision::float64;
  std::uint64_t seed = 1;
  std::size_t count = 0;
  std::uint64_t ulp_tolerance = 1;
  std::vector<FamilyCheck> families;
  std::vector<PromiseCheck> promises;  ///< only the ones stated in the options
  [[nodiscard]] Stats total() const;
  [[nodiscard]] std::size_t over_tolerance() const;
  [[nodiscard]] std::size_t failures() const;
  [[nodiscard]] bool promises_kept() const;
};

/// The families whose false misses break `watertight`: exact hits on an edge or a vertex.
[[nodiscard]] bool is_watertight_family(const std::string& family);

/// Runs the check. The method's take_failures (if any) is drained after every batch.
[[nodiscard]] CheckResult check(const Method& m, const CheckOptions& opt);

/// The same for a plain callable (a C++ kernel): `classify` gets each case as a float32 kernel
/// must see it (already rounded) and answers it; `kinds` are the kinds it answers.
[[nodiscard]] CheckResult check(std::function<io::CaseResult(const io::Case&)> classify, Precision precision,
                                std::vector<io::Kind> kinds, const CheckOptions& opt, std::string name = "kernel");

}  // namespace rayproof::verify
