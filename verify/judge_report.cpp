// The judges' --out report (verify/judge_report.h): rows made from the tallies, rayproof's own
// exact answers judged beside the functions, and the page written as markdown and HTML.
#include "verify/judge_report.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>

#include "rayproof/scene/distance.h"
#include "rayproof/scene/exact_mesh.h"
#include "rayproof/scene/mesh_caster.h"

namespace rayproof::verify {

namespace {

/// A markdown table cell: '|' escaped.
std::string report_md_cell(std::string_view s) {
  std::string o;
  for (char c : s) {
    if (c == '|') o += '\\';
    o += c;
  }
  return o;
}

constexpr std::string_view kReportStyle =
    "body{font-family:sans-serif;max-width:80em;margin:2em auto}table{border-collapse:collapse}"
    "td,th{border:1px solid #bbb;padding:.2em .5em;text-align:right}td:first-child,td:nth-child(2){text-align:left}"
    "tr.builtin{color:#555}pre{white-space:pre-wrap;font-size:85%}";

/// The column labels of a counter table (its report columns), and a tally's counts in them.
template <class Counts, std::size_t N>
std::vector<std::string> report_columns(const JudgeCounter<Counts> (&table)[N]) {
  std::vector<std::string> out;
  for (const JudgeCounter<Counts>& counter : table)
    if (counter.report_column) out.emplace_back(column_label(counter));
  return out;
}
template <class Counts, std::size_t N>
std::vector<std::uint64_t> report_counts(const JudgeCounter<Counts> (&table)[N], const std::type_identity_t<Counts>& c) {
  std::vector<std::uint64_t> out;
  for (const JudgeCounter<Counts>& counter : table)
    if (counter.report_column) out.push_back(count_of(c, counter));
  return out;
}

/// The fields every judge's tally gives alike.
template <class Tally>
JudgeReportRow row_of(const ProgramRun& run, std::string_view mesh, std::size_t triangles, const Tally& tally) {
  JudgeReportRow row;
  row.function = run.name;
  row.command = run.command;
  row.mesh = mesh;
  row.triangles = triangles;
  row.sets = tally.sets;
  row.answer_seconds = run.seconds;
  row.judge_seconds = tally.judge_seconds;
  row.starts = run.starts;
  row.events = run.events;
  row.notes = tally.notes;
  for (const auto& r : tally.reproducers) row.reproducers.push_back(r.line);
  return row;
}

/// rayproof's own answers are timed as the judges time theirs: after an untimed warm-up on the
/// first items (the query's tree is built on first use).
template <class Query>
double timed_after_warm_up(std::size_t n, Query&& query) {
  query(0, std::min<std::size_t>(n, 64));
  const auto start = std::chrono::steady_clock::now();
  query(0, n);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

template <class Mesh>
ExactMesh exact_mesh_of(const Mesh& m, ContainsRule rule = ContainsRule::automatic) {
  return ExactMesh(VertexArray(reinterpret_cast<const double*>(m.vertices.data()), m.vertices.size()),
                   IndexArray{m.triangles.empty() ? nullptr : m.triangles.data()->data(), m.triangles.size()}, rule);
}

const ProgramRun kBuiltin{"rayproof exact", "built-in", {}, 0, 0};

std::string time_per_query(double seconds, std::uint64_t items) {
  return items > 0 ? fmt::format("{:.3g} µs", seconds / static_cast<double>(items) * 1e6) : std::string("-");
}

}  // namespace

// ---- The page ----

std::string html_escape(std::string_view s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

ReportPages::ReportPages(const std::string& title, const std::string& intro) {
  md_ = "# " + title + "\n\n" + intro + "\n";
  html_ = fmt::format("<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>{0}</title>\n<style>{1}</style>"
                      "</head><body>\n<h1>{0}</h1>\n<p>{2}</p>\n",
                      html_escape(title), kReportStyle, html_escape(intro));
}

void ReportPages::heading(int level, const std::string& text) {
  md_ += fmt::format("\n{} {}\n", std::string(static_cast<std::size_t>(level), '#'), text);
  html_ += fmt::format("<h{0}>{1}</h{0}>\n", level, html_escape(text));
}

void ReportPages::paragraph(const std::string& text) {
  md_ += "\n" + text + "\n";
  html_ += "<p>" + html_escape(text) + "</p>\n";
}

void ReportPages::bullets(const std::vector<std::string>& items) {
  md_ += "\n";
  html_ += "<ul>\n";
  for (const auto& item : items) {
    md_ += "- " + item + "\n";
    html_ += "<li>" + html_escape(item) + "</li>\n";
  }
  html_ += "</ul>\n";
}

void ReportPages::table(const std::vector<std::string>& header, const std::vector<ReportTableRow>& rows) {
  md_ += "\n|";
  html_ += "<table>\n<tr>";
  std::string sep = "|";
  for (const auto& h : header) {
    md_ += " " + report_md_cell(h) + " |";
    sep += "---|";
    html_ += "<th>" + html_escape(h) + "</th>";
  }
  md_ += "\n" + sep + "\n";
  html_ += "</tr>\n";
  for (const auto& row : rows) {
    md_ += "|";
    html_ += row.builtin ? "<tr class=\"builtin\">" : "<tr>";
    for (std::size_t k = 0; k < row.cells.size(); ++k) {
      md_ += " " + report_md_cell(row.cells[k]) + " |";
      html_ += "<td>" + html_escape(k == 0 && !row.html_first.empty() ? row.html_first : row.cells[k]) + "</td>";
    }
    md_ += "\n";
    html_ += "</tr>\n";
  }
  html_ += "</table>\n";
}

void ReportPages::block(const std::vector<std::string>& lines) {
  md_ += "\n```\n";
  html_ += "<pre>";
  for (const auto& line : lines) {
    md_ += line + "\n";
    html_ += html_escape(line) + "\n";
  }
  md_ += "```\n";
  html_ += "</pre>\n";
}

void make_report_dir(const std::string& dir) {
  std::error_code made, is;
  std::filesystem::create_directories(dir, made);
  if (!std::filesystem::is_directory(dir, is))
    throw std::runtime_error(fmt::format("cannot write {}: {} is not a directory ({})",
                                         (std::filesystem::path(dir) / "report.md").string(), dir,
                                         made ? made.message() : is ? is.message() : std::string("a file is there")));
}

void ReportPages::write(const std::string& dir) const {
  make_report_dir(dir);
  for (const auto& [name, text] : {std::pair<std::string, const std::string*>{"report.md", &md_}, {"report.html", &html_}}) {
    const auto path = std::filesystem::path(dir) / name;
    std::ofstream out(path, std::ios::binary);
    out << *text << (text == &html_ ? "</body></html>\n" : "");
    if (!out) throw std::runtime_error("cannot write " + path.string());
  }
}

// ---- The judges' report ----

std::string judged_verdict(std::string_view role, std::string_view name, std::uint64_t differing, std::uint64_t items,
                           std::string_view noun, std::string_view mesh, std::string_view agreed) {
  if (differing == 0) return fmt::format("{} '{}' answered all {} {} on {}{}", role, name, items, noun, mesh, agreed);
  return fmt::format("{} '{}' differs from exact on {} of {} {} on {}", role, name, differing, items, noun, mesh);
}

void write_judge_report(const std::string& dir, const JudgeReport& r) {
  ReportPages page(r.title, r.intro);
  page.paragraph(fmt::format(
      "rayproof's own answer (row `{0}`, built-in) is judged on the same {1} by the same judge: it should have no "
      "finding. Time per query: a program's whole run over its {1} (its starts and the protocol's text included); "
      "rayproof's own, its query alone. Judge cost: the judgement's time over rayproof's {2} on the same {1}, timed in "
      "the same run.",
      kBuiltin.name, r.noun, r.baseline));
  std::vector<std::string> header{"function", "mesh"};
  header.insert(header.end(), r.columns.begin(), r.columns.end());
  for (const char* h : {"events", "time per query", "judge cost"}) header.emplace_back(h);
  std::vector<ReportTableRow> rows;
  for (const JudgeReportRow& row : r.rows) {
    ReportTableRow t;
    t.builtin = row.builtin();
    t.cells = {t.builtin ? row.function : "**" + row.function + "**", row.mesh};
    if (!t.builtin) t.html_first = row.function + " (" + row.command + ")";
    for (const std::uint64_t c : row.counts) t.cells.push_back(fmt::format("{}", c));
    t.cells.push_back(fmt::format("{}", row.events.size()));
    t.cells.push_back(time_per_query(row.answer_seconds, row.items));
    t.cells.push_back(ratio_text(row.judge_seconds, row.baseline_seconds));
    rows.push_back(std::move(t));
  }
  page.table(header, rows);

  page.heading(2, "Verdicts");
  std::vector<std::string> verdicts;
  for (const JudgeReportRow& row : r.rows)
    verdicts.push_back(judged_verdict("function", row.function, row.differing, row.items, r.noun, row.mesh, r.agreed));
  page.bullets(verdicts);

  // The sets, in the order they first appear.
  std::vector<std::string> sets;
  for (const JudgeReportRow& row : r.rows)
    for (const ContainsSetCounts& s : row.sets)
      if (std::find(sets.begin(), sets.end(), s.set) == sets.end()) sets.push_back(s.set);
  page.heading(2, "Per set");
  page.paragraph(fmt::format("Findings of the {0} judged in each set (`findings of {0}`), then the judge's cost in each "
                             "set (its time over rayproof's {1} on the set's {0}).",
                             r.noun, r.baseline));
  std::vector<std::string> set_header{"function", "mesh"};
  set_header.insert(set_header.end(), sets.begin(), sets.end());
  std::vector<ReportTableRow> counts, costs;
  for (const JudgeReportRow& row : r.rows) {
    ReportTableRow count{{row.function, row.mesh}, {}, row.builtin()}, cost = count;
    for (const std::string& name : sets) {
      const auto s = std::find_if(row.sets.begin(), row.sets.end(), [&](const ContainsSetCounts& c) { return c.set == name; });
      count.cells.push_back(s == row.sets.end() ? std::string("-") : fmt::format("{} of {}", s->findings, s->points));
      cost.cells.push_back(s == row.sets.end() ? std::string("-") : ratio_text(s->judge_seconds, s->contains_seconds));
    }
    counts.push_back(std::move(count));
    costs.push_back(std::move(cost));
  }
  page.table(set_header, counts);
  page.table(set_header, costs);

  page.heading(2, "Commands, events and reproducers");
  for (const JudgeReportRow& row : r.rows) {
    page.heading(3, row.function + " on " + row.mesh);
    std::vector<std::string> lines{"command: " + row.command};
    if (!row.builtin()) lines.push_back(fmt::format("started {} time{}", row.starts, row.starts == 1 ? "" : "s"));
    lines.push_back(judged_verdict("function", row.function, row.differing, row.items, r.noun, row.mesh, r.agreed));
    for (const auto& e : row.events) lines.push_back("event: " + e);
    for (const auto& n : row.notes) lines.push_back("note: " + n);
    lines.insert(lines.end(), row.reproducers.begin(), row.reproducers.end());
    page.block(lines);
  }
  page.write(dir);
}

// ---- Each judge's report and rows ----

std::string distance_agreed(const DistanceCheckOptions& opt) {
  return fmt::format(" within 1 ulp{}{}", opt.precision == ContainsPrecision::float32 ? " of float" : "",
                     opt.rel_tol > 0 ? fmt::format(" or a relative {}", opt.rel_tol) : std::string());
}

JudgeReport distance_report(const DistanceCheckOptions& opt) {
  const bool float32 = opt.precision == ContainsPrecision::float32;
  JudgeReport r;
  r.title = "Distance functions under the exact test";
  r.intro = fmt::format(
      "Distance functions judged exactly on meshes (`rayproof check --distance`, docs/check.md): each function's {} "
      "distance per point against rayproof's exact distance correctly rounded, errors in {} ulps{}; a distance more "
      "than 1 ulp off{} is a finding, as are the other counts docs/check.md marks so. Closest points and triangles, "
      "where a function answers them, are judged too.",
      opt.signed_distance ? "signed" : "unsigned", float32 ? "float" : "double",
      float32 ? " (the mesh and the points rounded to float)" : "",
      opt.rel_tol > 0 ? fmt::format(" and more than a relative {} off", opt.rel_tol) : std::string());
  r.baseline = "closest_points";
  r.agreed = distance_agreed(opt);
  r.columns = report_columns(kDistanceCounters);
  return r;
}

JudgeReport contains_report(const ContainsCheckOptions& opt) {
  JudgeReport r;
  r.title = "Containment functions under the exact test";
  r.intro = fmt::format(
      "Containment functions judged exactly on meshes (`rayproof check --contains`, docs/check.md): each function's "
      "side per point (0 outside, 1 inside, 2 on the surface) against rayproof's exact contains under the rule {}, "
      "{} precision{}. At a point exactly on the surface any answer is right (counted by what was answered).",
      rayproof::to_string(opt.rule), opt.precision == ContainsPrecision::float32 ? "float" : "double",
      opt.precision == ContainsPrecision::float32 ? " (the points rounded to float)" : "");
  r.baseline = "contains";
  r.agreed = " as exact arithmetic does";
  r.columns = report_columns(kContainsCounters);
  return r;
}

JudgeReport crossings_report(const CrossingsCheckOptions& opt) {
  JudgeReport r;
  r.title = "All-hits functions under the exact test";
  r.intro = fmt::format(
      "All-hits functions judged exactly on meshes (`rayproof check --crossings`, docs/check.md): each function's hits "
      "per ray (t > 0, in increasing t) against rayproof's exact crossings: each crossing wanted once, a touch not at "
      "all, t within {} ulp{} of {}{}. A ray differs when it has one finding or more.",
      opt.max_ulps, opt.max_ulps == 1 ? "" : "s", opt.precision == CasterPrecision::float32 ? "float" : "double",
      opt.precision == CasterPrecision::float32 ? " (the rays rounded to float)" : "");
  r.noun = "rays";
  r.baseline = "ray_crossings";
  r.agreed = " as exact arithmetic does";
  r.columns = report_columns(kCrossingsCounters);
  return r;
}

JudgeReportRow report_row(const ProgramRun& run, const ContainsMesh& mesh, const DistanceTally& tally) {
  JudgeReportRow row = row_of(run, mesh.name, mesh.triangles.size(), tally);
  row.counts = report_counts(kDistanceCounters, tally);
  row.items = tally.points;
  row.differing = tally.findings();
  row.baseline_seconds = tally.closest_seconds;
  return row;
}

JudgeReportRow report_row(const ProgramRun& run, const ContainsMesh& mesh, const ContainsTally& tally) {
  JudgeReportRow row = row_of(run, mesh.name, mesh.triangles.size(), tally);
  row.counts = report_counts(kContainsCounters, tally);
  row.items = tally.points;
  row.differing = tally.findings();
  row.baseline_seconds = tally.contains_seconds;
  return row;
}

JudgeReportRow report_row(const ProgramRun& run, const CasterMesh& mesh, const CrossingsTally& tally) {
  JudgeReportRow row = row_of(run, mesh.name, mesh.triangles.size(), tally);
  row.counts = report_counts(kCrossingsCounters, tally);
  row.items = tally.rays;
  row.differing = tally.rays_with_findings;
  row.baseline_seconds = tally.crossings_seconds;
  return row;
}

JudgeReportRow builtin_distance_row(const ContainsMesh& mesh, const ContainsPoints& points, const DistanceJudge& judge,
                                    const DistanceCheckOptions& opt) {
  const ExactMesh exact = exact_mesh_of(mesh);
  const std::size_t n = points.points.size();
  std::vector<ClosestPoint> closest(n);
  ProgramRun run = kBuiltin;
  run.seconds = timed_after_warm_up(n, [&](std::size_t b, std::size_t e) {
    exact.closest_points(std::span<const Vec3<double>>(points.points).subspan(b, e - b),
                         std::span<ClosestPoint>(closest).subspan(b, e - b), opt.signed_distance, opt.threads);
  });
  std::vector<DistanceAnswer> answers(n);
  for (std::size_t i = 0; i < n; ++i) {
    const ClosestPoint& c = closest[i];
    DistanceAnswer& a = answers[i];
    a.distance = opt.signed_distance ? c.signed_distance() : c.distance;
    if (finite(points.points[i]) && c.triangle != ClosestPoint::kNoTriangle) {
      a.point = c.point, a.has_point = true;
      a.triangle = c.triangle, a.has_triangle = true;
    }
  }
  return report_row(run, mesh, judge.judge(points, answers, opt));
}

JudgeReportRow builtin_contains_row(const ContainsMesh& mesh, const ContainsPoints& points, const ContainsJudge& judge,
                                    const ContainsCheckOptions& opt) {
  const ExactMesh exact = exact_mesh_of(mesh, opt.rule);
  const std::size_t n = points.points.size();
  std::vector<Side> sides(n);
  ProgramRun run = kBuiltin;
  run.seconds = timed_after_warm_up(n, [&](std::size_t b, std::size_t e) {
    exact.contains(std::span<const Vec3<double>>(points.points).subspan(b, e - b),
                   std::span<Side>(sides).subspan(b, e - b), opt.threads);
  });
  std::vector<ContainsAnswer> answers(n);
  for (std::size_t i = 0; i < n; ++i)
    answers[i].side = sides[i] == Side::inside ? 1 : sides[i] == Side::surface ? 2 : 0;  // invalid: any side is right
  return report_row(run, mesh, judge.judge(points, answers, opt));
}

JudgeReportRow builtin_crossings_row(const CasterMesh& mesh, const CasterRays& rays, const CrossingsJudge& judge,
                                     const CrossingsCheckOptions& opt) {
  const ExactMesh exact = exact_mesh_of(mesh);
  const std::size_t n = rays.rays.size();
  std::vector<RayCrossings> crossings(n);
  const TRange positive{std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::infinity()};
  ProgramRun run = kBuiltin;
  run.seconds = timed_after_warm_up(n, [&](std::size_t b, std::size_t e) {
    exact.ray_crossings(std::span<const Ray<double>>(rays.rays).subspan(b, e - b),
                        std::span<RayCrossings>(crossings).subspan(b, e - b), positive, opt.threads);
  });
  std::vector<CrossingsAnswer> answers(n);
  for (std::size_t i = 0; i < n; ++i)
    for (const Crossing& c : crossings[i].crossings) answers[i].hits.push_back({c.t, std::int64_t(c.triangle)});
  return report_row(run, mesh, judge.judge(rays, answers, opt));
}

}  // namespace rayproof::verify
