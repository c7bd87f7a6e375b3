#pragma once
/// Differential comparison: every method against `exact`, per method x family. Float methods are
/// judged on their float-rounded inputs (the reference is exact on those), and their t error is
/// counted in float ulps (docs/cases.md, "What correct means").
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"

namespace rayproof::verify {

/// True when the class says the ray touches the primitive at some t >= 0 (a coplanar triangle
/// counts when it has a range).
[[nodiscard]] bool touches(const io::CaseResult& r);

/// How a method's answer relates to the exact one (a full answer: by class).
/// `kernel_failure`: a user kernel (a method with take_failures) crashed, hung or answered garbage
/// on the case; not a class error.
enum class Verdict { agree, false_hit, false_miss, wrong_hit_class, wrong_class, kernel_failure };
[[nodiscard]] Verdict judge_class(const io::CaseResult& got, const io::CaseResult& want);

/// Largest ulp distance of T and T2 in precision p; 0 when the class carries no t.
/// A t present on one side only counts as the maximum.
[[nodiscard]] std::uint64_t t_error_ulps(const io::CaseResult& got, const io::CaseResult& want, Precision p);

/// The exact first contact at t >= 0 that a coarse `hit T` is compared with: T2 for `inside` (the
/// origin is inside the quadric or box: the ray meets the surface at T2 >= 0), T for the other
/// touching classes (a coplanar triangle: where its range starts); nothing when the ray does not
/// touch the primitive.
[[nodiscard]] std::optional<double> first_contact_t(const io::CaseResult& exact);

struct Stats {
  std::size_t cases = 0;
  std::size_t false_hit = 0, false_miss = 0, wrong_hit_class = 0, wrong_class = 0;
  std::uint64_t fallbacks = 0;         ///< exact fallbacks (methods that count them)
  std::vector<std::uint64_t> ulps;     ///< t error of every class-correct case that carries t
  std::size_t kernel_failures = 0;     ///< a user kernel crashed, hung or answered garbage (not a class error)
  std::size_t coarse = 0;              ///< answered coarsely (hit/miss, t, barycentrics; docs/kernel_protocol.md)
  std::vector<double> bary_errors;     ///< coarse triangle hits with barycentrics: max |b - exact b| of b1, b2
  std::size_t promised = 0;            ///< cases on which the method promised something (Method::promises)
  std::size_t promise_broken = 0;      ///< of those, the answers that broke the promise
  /// Coarse (meets-or-not) answers to triangle pairs whose exact class is `degenerate` or `invalid`:
  /// the class does not say whether such a pair meets (docs/tritri.md), so they are not judged and
  /// not counted in `cases`.
  std::size_t unjudged = 0;
  /// The class-correct answer with the largest t error (the first one met), to show beside "max".
  struct Worst {
    std::uint64_t ulps = 0;
    io::Case input;
    io::CaseResult got, want;
  };
  std::optional<Worst> worst{};
  [[nodiscard]] std::size_t class_errors() const { return false_hit + false_miss + wrong_hit_class + wrong_class; }
  [[nodiscard]] double class_error_rate() const { return cases ? double(class_errors()) / double(cases) : 0.0; }
  /// q-quantile of the t errors (0 when none), nearest-rank.
  [[nodiscard]] std::uint64_t ulp_quantile(double q) const;
  void merge(const Stats& o);
};

struct Mismatch {
  std::string method;
  io::Case input;          ///< as the method saw it (float-rounded for float methods)
  io::CaseResult got, want;
  Verdict verdict = Verdict::agree;
  std::uint64_t ulps = 0;
};

/// One method's answer on one case, judged against exact.
struct Judged {
  io::Case input;  ///< as the method saw it (float-rounded for float methods)
  io::CaseResult got, want;
  Verdict verdict = Verdict::agree;
  std::uint64_t ulps = 0;
  std::optional<double> bary_error{};  ///< coarse triangle hits with barycentrics: max |b - exact b|
};

/// Does the judged answer break `p`? (a class error under exact_class; a false miss under
/// no_false_miss, `ahead` excepting an exact first contact at t <= 0 or a coplanar ray; a
/// class-correct t beyond t_ulps). A kernel failure breaks nothing.
[[nodiscard]] bool breaks_promise(const Promise& p, Verdict v, std::uint64_t ulps, const io::CaseResult& want);

/// "kept on N", "broken on N of M" or "none made" (no case of a kind the method promises anything on):
/// the promise column of verify, report and fuzz.
[[nodiscard]] std::string promise_status(const Stats& s);

/// Judges `j.got`, the answer of `m` on `j.input`, against `j.want`, the exact answer on that input,
/// and adds it to `s` (fills j.verdict, j.ulps, j.bary_error). A full answer is judged by class; a
/// coarse one (io::AnswerForm::coarse) by hit or miss against touches(want), its t against
/// first_contact_t(want) and its barycentrics against the exact ones. Contact::error from a method
/// with take_failures is a kernel failure: counted in `cases` and `kernel_failures`, not as a class
/// error. A coarse answer to a triangle pair whose exact class is degenerate or invalid is not
/// judged (Stats::unjudged; verdict agree, not in `cases`). Exact fallbacks are not counted here. Counts `promised` and `promise_broken` against
/// m.promise(kind) and keeps the worst t error.
void judge_answer(const Method& m, Judged& j, Stats& s);

/// Runs `m` on `c` (float-rounded first for float methods), judges the answer against the exact
/// answer for what the method saw, and adds it to `s`: the case, its class error or t error, and
/// the exact fallbacks it took.
Judged run_and_tally(const Method& m, const io::Case& c, const io::CaseResult& exact_as_given,
                     const io::CaseResult& exact_float_rounded, Stats& s);

/// Per method x group (the `# family` name, else the kind).
struct Comparison {
  std::vector<std::string> methods;                                  ///< in registry order
  std::vector<std::string> groups;                                   ///< in first-seen order
  std::map<std::pair<std::string, std::string>, Stats> stats;        ///< (method, group)
  std::vector<Mismatch> mismatches;  ///< the first max_mismatches of each method
  [[nodiscard]] Stats total(const std::string& method) const;
};

/// The exact answers for a list of cases, computed once and shared by every method: [0] on the
/// inputs as given, [1] on the float-rounded inputs.
struct ExactAnswers {
  std::vector<io::CaseResult> as_given, float_rounded;
};
[[nodiscard]] ExactAnswers exact_answers(const std::vector<io::Case>& cases);

/// The group a case is reported under.
[[nodiscard]] std::string group_of(const io::Case& c);

/// Runs every method on every case it supports: one Method::classify_many call per method over all
/// the cases it supports (per run of consecutive cases of one group for methods that count exact
/// fallbacks, so that they are counted per group). A class mismatch, or a t error above
/// `ulp_tolerance`, is listed in `mismatches` (the first max_mismatches per method).
[[nodiscard]] Comparison compare(const std::vector<io::Case>& cases, const ExactAnswers& exact,
                                 const std::vector<const Method*>& methods, std::size_t max_mismatches,
                                 std::uint64_t ulp_tolerance = 1);

[[nodiscard]] std::string to_string(Verdict v);

}  // namespace rayproof::verify
