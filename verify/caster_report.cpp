// check --caster --out: the report of whole casters beside rayproof's own (verify/caster_report.h).
#include "verify/caster_report.h"

#include <fmt/core.h>

#include <limits>
#include <utility>

#include "rayproof/scene/mesh_caster.h"
#include "verify/judge_report.h"

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
  ReportPages page("Casters under the exact test", intro);
  std::vector<std::string> header{"caster", "mesh"};
  for (const CasterCounter& counter : kCasterCounters)
    if (counter.report_column) header.emplace_back(column_label(counter));
  std::vector<ReportTableRow> table;
  for (const auto& r : rows) {
    const bool is_builtin = r.command == "built-in";
    ReportTableRow t{{is_builtin ? r.caster : "**" + r.caster + "**", r.mesh},
                     is_builtin ? std::string() : r.caster + " (" + r.command + ")", is_builtin};
    for (const CasterCounter& counter : kCasterCounters)
      if (counter.report_column) t.cells.push_back(fmt::format("{}", count_of(r.tally, counter)));
    table.push_back(std::move(t));
  }
  page.table(header, table);
  page.heading(2, "Reproducers and events");
  for (const auto& r : rows) {
    if (r.tally.reproducers.empty() && r.events.empty() && r.tally.notes.empty()) continue;
    page.heading(3, fmt::format("{} on {}", r.caster, r.mesh));
    std::vector<std::string> lines;
    for (const auto& e : r.events) lines.push_back("event: " + e);
    for (const auto& n : r.tally.notes) lines.push_back("note: " + n);
    for (const auto& p : r.tally.reproducers) lines.push_back(p.line);
    page.block(lines);
  }
  page.write(dir);
}

}  // namespace rayproof::verify
