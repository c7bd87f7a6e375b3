// check --distance: distance functions (programs speaking the line protocol of docs/check.md)
// judged on meshes against rayproof's exact distances (verify/contains_exec.h,
// rayproof/verify/distance_check.h).
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>

#include "cli/judge_cli.h"
#include "cli/mesh_modes.h"
#include "rayproof/verify/distance_check.h"
#include "verify/contains_exec.h"

namespace rayproof::cli {

namespace {

nlohmann::json distance_run_json(const NamedCommand& fn, const JudgedMesh& mesh, const verify::DistanceTally& tally,
                                 const verify::ExecDistanceRun& run) {
  nlohmann::json out = judged_run_json("function", fn, mesh, tally, run.events, run.starts, verify::kDistanceCounters,
                                       [](const auto&) { return true; });
  out["signed"] = tally.signed_distance;
  out["precision"] = tally.precision == verify::ContainsPrecision::float32 ? "float" : "double";
  out["rel_tol"] = tally.rel_tol;
  out["max_rel_error"] = tally.max_rel_error;
  out["sets"] = set_costs_json(tally.sets);
  out["judge_seconds"] = tally.judge_seconds;
  out["closest_seconds"] = tally.closest_seconds;
  out["cost_ratio"] = ratio_json(tally.judge_seconds, tally.closest_seconds);
  return out;
}

}  // namespace

int run_distance_check(const CheckCliOptions& o) {
  const auto functions = named_commands(o.distance, "--distance");
  if (!functions) return 2;
  if (kernel_options_given(o) || !o.caster.empty() || !o.contains.empty()) {
    fmt::print(stderr, "rayproof check: --distance takes --mesh, --json, --out, --seed, --reproducers and the "
                       "--distance-* options; --caster, --contains, --exec, --plugin, --glsl, --opencl, --method, "
                       "--families, --expect and --max-ulps apply to other checks\n");
    return 2;
  }
  if (o.mesh.empty()) {
    fmt::print(stderr, "rayproof check: --distance needs --mesh MESH... (mesh files, or `generated`)\n");
    return 2;
  }
  if (!positive_seconds(o.distance_timeout, "--distance-timeout")) return 2;
  if (!(o.distance_rel_tol >= 0) || !std::isfinite(o.distance_rel_tol)) {
    fmt::print(stderr, "rayproof check: --distance-rel-tol must be a finite number >= 0\n");
    return 2;
  }
  verify::DistanceCheckOptions opt;
  if (o.distance_precision == "float") opt.precision = verify::ContainsPrecision::float32;
  else if (o.distance_precision != "double") {
    fmt::print(stderr, "rayproof check: --distance-precision '{}' is neither float nor double\n", o.distance_precision);
    return 2;
  }
  opt.signed_distance = o.distance_signed;
  opt.rel_tol = o.distance_rel_tol;
  opt.seed = o.seed;
  opt.random_points = o.distance_points;
  opt.max_points_per_set = o.distance_max_per_set;
  opt.reproducers = o.reproducers;
  opt.sets = o.distance_sets;
  if (!report_dir_ready(o.out)) return 2;
  const auto scale = scale_exponent(o.distance_scale, "--distance-scale");
  if (!scale) return 2;
  auto judged = judged_meshes(o);
  if (!judged) return 2;
  if (!scale_meshes(*judged, *scale, opt.precision == verify::ContainsPrecision::float32, "--distance-scale")) return 2;

  verify::ExecContainsOptions exec_opt;
  exec_opt.timeout_seconds = o.distance_timeout;
  exec_opt.batch = o.distance_batch;
  bool any_finding = false;
  nlohmann::json json_runs = nlohmann::json::array();
  if (!o.json)
    fmt::print("rayproof check --distance: {} distances{} judged against rayproof's exact distance, correctly rounded "
               "(docs/check.md){}\n",
               o.distance_signed ? "signed" : "unsigned",
               *scale != 0 ? fmt::format(" on the mesh times 2^{}", *scale) : std::string(),
               opt.precision == verify::ContainsPrecision::float32
                   ? "; float: the mesh and the points rounded to float, errors in float ulps"
                   : "");
  struct Prepared {
    std::vector<Vec3<double>> rounded;  // the mesh's vertices rounded to float (float precision); `mesh` views them
    verify::ContainsMesh mesh;
    verify::ContainsPoints points;
    verify::DistanceJudge judge;
  };
  // --out: every function's row, then rayproof's own exact distance on each mesh's points.
  verify::JudgeReport report = verify::distance_report(opt);
  std::vector<verify::JudgeReportRow> builtin_rows;
  const bool prepared = for_each_mesh_and_function(
      *judged, *functions,
      [&](const JudgedMesh& m) {
        const bool float32 = opt.precision == verify::ContainsPrecision::float32;
        std::vector<Vec3<double>> rounded = float32 ? verify::float_vertices(m.mesh.vertices) : std::vector<Vec3<double>>();
        // A vector's move keeps its buffer: `mesh` stays a view of Prepared's own `rounded`.
        const verify::ContainsMesh mesh{float32 ? std::span<const Vec3<double>>(rounded) : m.mesh.vertices, m.mesh.triangles,
                                        m.name};
        Prepared p{std::move(rounded), mesh, verify::distance_points(mesh, opt), verify::DistanceJudge(mesh)};
        if (!o.out.empty()) builtin_rows.push_back(verify::builtin_distance_row(p.mesh, p.points, p.judge, opt));
        return p;
      },
      [&](const NamedCommand& fn, const JudgedMesh& m, const Prepared& p) {
        fmt::print(stderr, "[distance] {} on {}: {} points\n", fn.name, m.name, p.points.points.size());
        const verify::ExecDistanceRun run = verify::run_exec_distance(fn.command, p.mesh, p.points, exec_opt);
        const verify::DistanceTally tally = p.judge.judge(p.points, run.answers, opt);
        any_finding = any_finding || tally.findings() > 0;
        if (!o.out.empty())
          report.rows.push_back(verify::report_row(verify::program_run(fn.name, fn.command, run), p.mesh, tally));
        if (o.json) json_runs.push_back(distance_run_json(fn, m, tally, run));
        else
          print_judged_run({"function", "points", fn, m, tally.points, tally.findings(), run.starts,
                            verify::summary_text(tally), run.events, report.agreed});
      });
  if (!prepared) return 2;
  if (!o.out.empty()) {
    report.rows.insert(report.rows.end(), builtin_rows.begin(), builtin_rows.end());
    if (!write_report(o.out, report)) return 2;
  }
  if (o.json) fmt::print("{}\n", nlohmann::json{{"functions", json_runs}, {"findings", any_finding}}.dump(1));
  return any_finding ? 1 : 0;
}

}  // namespace rayproof::cli
