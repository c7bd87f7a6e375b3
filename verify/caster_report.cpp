// check --caster --out: the report of whole casters beside rayproof's own (verify/caster_report.h).
#include "verify/caster_report.h"

#include <fmt/core.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "rayproof/scene/mesh_caster.h"

namespace rayproof::verify {

namespace {

template <class Method>
CasterReportRow builtin(const char* name, const CasterMesh& mesh, const CasterRays& rays, const CasterJudge& judge,
                        const CasterCheckOptions& opt) {
  const MeshCaster<Method> caster(VertexArray(&mesh.vertices[0].x, mesh.vertices.size()),
                                  IndexArray{mesh.triangles[0].data(), mesh.triangles.size()});
  std::vector<MeshHit> hits(rays.rays.size());
  const TRange range{std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::infinity()};
  caster.closest(rays.rays, {&range, 1}, hits, opt.threads);
  std::vector<CasterAnswer> answers(rays.rays.size());
  for (std::size_t i = 0; i < hits.size(); ++i) {
    answers[i].t = hits[i].hit() ? hits[i].t : std::numeric_limits<double>::infinity();
    answers[i].triangle = hits[i].hit() ? std::int64_t(hits[i].triangle) : -1;
  }
  return {fmt::format("rayproof {}", name), "built-in", mesh.name, mesh.triangles.size(),
          judge.judge(rays, answers, opt), {}};
}

std::string html_escape(const std::string& s) {
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

}  // namespace

std::vector<CasterReportRow> builtin_caster_rows(const CasterMesh& mesh, const CasterRays& rays, const CasterJudge& judge,
                                                 const CasterCheckOptions& opt) {
  if (mesh.triangles.empty()) return {};
  std::vector<CasterReportRow> rows;
  rows.push_back(builtin<cast::Float>("float", mesh, rays, judge, opt));
  rows.push_back(builtin<cast::Robust>("robust", mesh, rays, judge, opt));
  rows.push_back(builtin<cast::Certified>("certified", mesh, rays, judge, opt));
  return rows;
}

void write_caster_report(const std::string& dir, const std::vector<CasterReportRow>& rows, const std::string& precision) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  const std::string intro = fmt::format(
      "Whole casters judged exactly on meshes (`rayproof check --caster`, docs/check.md): each caster's closest "
      "hit per ray against rayproof's certified caster and exact per-triangle tests, crossings at t > 0, t errors "
      "in {} ulps. rayproof's own float, robust and certified casters answer the same rays, judged the same way.",
      precision) +
      (precision == "double"
           ? " rayproof's float and robust casters round each ray and the mesh to float: judged on the rays as "
             "given, in double, they are charged with what that rounding changes (run with --caster-precision float "
             "to judge them on float rays)."
           : std::string());
  std::string md = "# Casters under the exact test\n\n" + intro + "\n\n| caster | mesh |";
  std::string html =
      "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>Casters under the exact test</title>\n"
      "<style>body{font-family:sans-serif;max-width:80em;margin:2em auto}table{border-collapse:collapse}"
      "td,th{border:1px solid #bbb;padding:.2em .5em;text-align:right}td:first-child,td:nth-child(2){text-align:left}"
      "tr.builtin{color:#555}pre{white-space:pre-wrap;font-size:85%}</style></head><body>\n"
      "<h1>Casters under the exact test</h1>\n<p>" +
      html_escape(intro) + "</p>\n<table>\n<tr><th>caster</th><th>mesh</th>";
  std::string sep = "|---|---|";
  for (const CasterCounter& counter : kCasterCounters) {
    if (!counter.report_column) continue;
    md += fmt::format(" {} |", column_label(counter));
    sep += "---|";
    html += fmt::format("<th>{}</th>", html_escape(std::string(column_label(counter))));
  }
  md += "\n" + sep + "\n";
  html += "</tr>\n";
  for (const auto& r : rows) {
    const bool is_builtin = r.command == "built-in";
    md += fmt::format("| {} | {} |", is_builtin ? r.caster : "**" + r.caster + "**", r.mesh);
    html += fmt::format("<tr{}><td>{}</td><td>{}</td>", is_builtin ? " class=\"builtin\"" : "",
                        html_escape(is_builtin ? r.caster : r.caster + " (" + r.command + ")"), html_escape(r.mesh));
    for (const CasterCounter& counter : kCasterCounters) {
      if (!counter.report_column) continue;
      md += fmt::format(" {} |", count_of(r.tally, counter));
      html += fmt::format("<td>{}</td>", count_of(r.tally, counter));
    }
    md += "\n";
    html += "</tr>\n";
  }
  html += "</table>\n";
  md += "\n## Reproducers and events\n";
  html += "<h2>Reproducers and events</h2>\n";
  for (const auto& r : rows) {
    if (r.tally.reproducers.empty() && r.events.empty() && r.tally.notes.empty()) continue;
    md += fmt::format("\n### {} on {}\n\n```\n", r.caster, r.mesh);
    html += fmt::format("<h3>{} on {}</h3>\n<pre>", html_escape(r.caster), html_escape(r.mesh));
    for (const auto& e : r.events) md += "event: " + e + "\n", html += html_escape("event: " + e) + "\n";
    for (const auto& n : r.tally.notes) md += "note: " + n + "\n", html += html_escape("note: " + n) + "\n";
    for (const auto& p : r.tally.reproducers) md += p.line + "\n", html += html_escape(p.line) + "\n";
    md += "```\n";
    html += "</pre>\n";
  }
  html += "</body></html>\n";
  for (const auto& [name, text] : {std::pair<std::string, const std::string*>{"report.md", &md}, {"report.html", &html}}) {
    const auto path = std::filesystem::path(dir) / name;
    std::ofstream out(path, std::ios::binary);
    out << *text;
    if (!out) throw std::runtime_error("cannot write " + path.string());
  }
}

}  // namespace rayproof::verify
