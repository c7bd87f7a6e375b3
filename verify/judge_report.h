#pragma once
/// `check --distance`, `--contains` and `--crossings` with `--out DIR`: every judged function beside
/// rayproof's own exact answer (judged by the same judge on the same items), as DIR/report.md and
/// DIR/report.html. Per row: every count of the judge's counter table (kDistanceCounters,
/// kContainsCounters, kCrossingsCounters), the events, per-set counts, the time per query and the
/// judge's cost ratio; per row the verdict sentence the CLI prints, made from the tally.
///
/// Also the page both files are written with (ReportPages), which the caster report
/// (verify/caster_report.h) writes its page with too.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "rayproof/verify/contains_check.h"
#include "rayproof/verify/crossings_check.h"
#include "rayproof/verify/distance_check.h"
#include "verify/judge_frame.h"

namespace rayproof::verify {

// ---- The page: markdown and HTML written side by side ----

/// s with & < > " escaped for HTML.
[[nodiscard]] std::string html_escape(std::string_view s);

/// A row of a report's table: markdown cells; the first cell may read otherwise in HTML.
struct ReportTableRow {
  std::vector<std::string> cells;  ///< as markdown shows them ('|' is escaped when written)
  std::string html_first;          ///< the first cell in HTML, when not cells[0] (empty: cells[0])
  bool builtin = false;            ///< rayproof's own: greyed in HTML
};

/// One page written twice, as report.md and report.html, piece by piece in the same order.
class ReportPages {
 public:
  /// The title (a first-level heading) and the introduction (a paragraph).
  ReportPages(const std::string& title, const std::string& intro);
  void heading(int level, const std::string& text);  ///< level 2 or 3
  void paragraph(const std::string& text);
  void bullets(const std::vector<std::string>& items);
  /// A table: its first two columns are text (left-aligned in HTML), the others numbers.
  void table(const std::vector<std::string>& header, const std::vector<ReportTableRow>& rows);
  /// Lines shown as they are (a fenced block; <pre> in HTML).
  void block(const std::vector<std::string>& lines);
  /// Writes DIR/report.md and DIR/report.html, DIR created. Throws std::runtime_error naming the
  /// file that could not be written.
  void write(const std::string& dir) const;

 private:
  std::string md_, html_;
};

/// Creates DIR (and its parents) for a report: std::runtime_error naming DIR/report.md when DIR
/// cannot be made a directory. Lets a run refuse a bad --out before it judges anything.
void make_report_dir(const std::string& dir);

// ---- The judges' report ----

/// "function 'NAME' answered all M points on MESH<agreed>" when nothing differs, else "function
/// 'NAME' differs from exact on N of M points on MESH": the sentence printed after a run, and each
/// row's in the report.
[[nodiscard]] std::string judged_verdict(std::string_view role, std::string_view name, std::uint64_t differing,
                                         std::uint64_t items, std::string_view noun, std::string_view mesh,
                                         std::string_view agreed);

/// One function on one mesh, as its report row shows it.
struct JudgeReportRow {
  std::string function;  ///< its name (rayproof's own: "rayproof exact")
  std::string command;   ///< what ran ("built-in" for rayproof's own)
  std::string mesh;
  std::size_t triangles = 0;
  std::vector<std::uint64_t> counts;  ///< one per report column of the judge's counter table, in its order
  std::uint64_t items = 0;      ///< points or rays judged
  std::uint64_t differing = 0;  ///< what the verdict counts: findings (crossings: rays with findings)
  std::vector<ContainsSetCounts> sets;  ///< per set: items, findings, the judge's and the baseline's seconds
  /// The function's time on the items: a program's run (wall time: its starts and the protocol's
  /// text included); rayproof's own, its query alone.
  double answer_seconds = 0;
  double judge_seconds = 0, baseline_seconds = 0;  ///< the judgement, rayproof's query timed beside it
  std::size_t starts = 0;  ///< times a program was started (0 for rayproof's own)
  std::vector<std::string> events, notes, reproducers;
  [[nodiscard]] bool builtin() const { return command == "built-in"; }
};

/// A judge's report: what the judge is, its columns and its rows.
struct JudgeReport {
  std::string title, intro;
  std::string noun = "points";  ///< what a query is asked of: "points", "rays"
  std::string baseline;         ///< rayproof's query the judge's cost is measured against: "closest_points"
  std::string agreed;           ///< the end of the verdict when nothing differs: " as exact arithmetic does"
  std::vector<std::string> columns;  ///< the counter table's column labels
  std::vector<JudgeReportRow> rows;
};

/// Writes the report as DIR/report.md and DIR/report.html (ReportPages::write).
void write_judge_report(const std::string& dir, const JudgeReport& report);

/// A program's run under a judge: its name and command, events, starts and wall time.
struct ProgramRun {
  std::string name, command;
  std::vector<std::string> events;
  std::size_t starts = 0;
  double seconds = 0;
};
template <class Answer>
[[nodiscard]] ProgramRun program_run(std::string name, std::string command, const ExecRun<Answer>& run) {
  return {std::move(name), std::move(command), run.events, run.starts, run.seconds};
}

/// The verdict's end when nothing was found: " within 1 ulp", " within 1 ulp of float or a relative
/// 1e-06" (check --distance).
[[nodiscard]] std::string distance_agreed(const DistanceCheckOptions& opt);
/// Each judge's report with its title, introduction and columns, and no rows.
[[nodiscard]] JudgeReport distance_report(const DistanceCheckOptions& opt);
[[nodiscard]] JudgeReport contains_report(const ContainsCheckOptions& opt);
[[nodiscard]] JudgeReport crossings_report(const CrossingsCheckOptions& opt);

/// A program's row from its tally.
[[nodiscard]] JudgeReportRow report_row(const ProgramRun& run, const ContainsMesh& mesh, const DistanceTally& tally);
[[nodiscard]] JudgeReportRow report_row(const ProgramRun& run, const ContainsMesh& mesh, const ContainsTally& tally);
[[nodiscard]] JudgeReportRow report_row(const ProgramRun& run, const CasterMesh& mesh, const CrossingsTally& tally);

/// rayproof's own answer on the same items, judged by the same judge with the same options: the
/// exact (signed) distance with its closest point and triangle (ExactMesh::closest_points); the
/// exact side under the options' rule (ExactMesh::contains: 0, 1, 2; 0 at invalid points); the
/// exact crossings at t > 0 (ExactMesh::ray_crossings: one hit (t, triangle) per crossing).
[[nodiscard]] JudgeReportRow builtin_distance_row(const ContainsMesh& mesh, const ContainsPoints& points,
                                                  const DistanceJudge& judge, const DistanceCheckOptions& opt);
[[nodiscard]] JudgeReportRow builtin_contains_row(const ContainsMesh& mesh, const ContainsPoints& points,
                                                  const ContainsJudge& judge, const ContainsCheckOptions& opt);
[[nodiscard]] JudgeReportRow builtin_crossings_row(const CasterMesh& mesh, const CasterRays& rays,
                                                   const CrossingsJudge& judge, const CrossingsCheckOptions& opt);

}  // namespace rayproof::verify
