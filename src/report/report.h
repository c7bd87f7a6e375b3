#pragma once
/// The error-against-run-time report: every method on every case family, compared with exact,
/// timed side by side in one run; written as report.md, report.csv and error_vs_time.svg.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "io/case_file.h"
#include "methods/method.h"
#include "verify/differential.h"

namespace rayproof::report {

/// One method on one family: the comparison with exact and the run time.
struct Row {
  std::string method;
  std::string group;
  io::Kind kind = io::Kind::plane;
  Precision precision = Precision::float64;
  verify::Stats stats;
  double ns_per_case = 0;
  Promise promise;  ///< what the method promises on this kind
};

/// One method over all it answers: one point of the chart.
struct Point {
  std::string method;
  double ns_per_case = 0;     ///< mean over the kinds it answers, each kind weighted by its cases
  double class_error_rate = 0;
  std::uint64_t max_ulps = 0;
  double fallback_rate = 0;
  Precision precision = Precision::float64;
  std::size_t promised = 0, promise_broken = 0;  ///< cases under a promise; of those, broken
  bool pareto = false;        ///< no other method is at least as fast and at least as accurate
};

struct Report {
  std::string title;
  std::vector<std::string> notes;  ///< run parameters, one line each
  std::vector<Row> rows;
  std::vector<Point> points;
  /// What user kernels reported while being compared (not while timed): (method, failure).
  std::vector<std::pair<std::string, KernelFailure>> kernel_failures;
  /// Error-free: no class error and every t within the method's promised tolerance, else this.
  std::uint64_t ulp_tolerance = 1;
  std::string highlight;  ///< a method drawn marked in the chart (the kernel `rayproof check` checks)
  /// Case-file lines that reproduce a disagreement, each with a `# method: ...` comment: the first
  /// kReproducersPerMethod of each method in `build_report`; `rayproof check` puts its worst cases here.
  std::vector<std::string> reproducers;
  std::string reproducers_intro;  ///< the sentence above them: which cases they are
};

inline constexpr std::size_t kReproducersPerMethod = 3;

/// Compares and times `methods` on `cases` (grouped by family); `progress` gets one line now and then.
[[nodiscard]] Report build_report(const std::vector<io::Case>& cases, const std::vector<const Method*>& methods,
                                  const std::function<void(const std::string&)>& progress);

/// Marks the points that no other point dominates in (time, error): lower is better in both.
[[nodiscard]] std::vector<bool> pareto_front(const std::vector<double>& time, const std::vector<double>& err);

[[nodiscard]] std::string to_markdown(const Report& r);
[[nodiscard]] std::string to_csv(const Report& r);
[[nodiscard]] std::string to_svg(const Report& r);

/// Writes report.md, report.csv and error_vs_time.svg into `dir` (created if needed); returns an
/// error message or "". report.html is rendered from the finished report.md (report/html.h).
[[nodiscard]] std::string write_report(const Report& r, const std::string& dir);

/// Writes each (name, text) into `dir` (created when missing); "" on success, else what failed.
[[nodiscard]] std::string write_files(const std::string& dir, std::span<const std::pair<const char*, std::string>> files);

}  // namespace rayproof::report
