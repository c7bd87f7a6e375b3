// check --contains: containment functions (programs speaking the line protocol of docs/check.md)
// judged on meshes against rayproof's exact contains (verify/contains_exec.h,
// rayproof/verify/contains_check.h).
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>

#include "cli/judge_cli.h"
#include "cli/mesh_modes.h"
#include "mesh/mesh.h"
#include "rayproof/verify/contains_check.h"
#include "verify/contains_exec.h"

namespace rayproof::cli {

namespace {

/// One function's run on one mesh, as `--json` prints it: every count (by its key), the rule,
/// per-set counts and costs, events, reproducers and notes.
nlohmann::json contains_run_json(const NamedCommand& fn, const JudgedMesh& mesh, const verify::ContainsTally& tally,
                                 const verify::ExecContainsRun& run) {
  nlohmann::json out = judged_run_json("function", fn, mesh, tally, run.events, run.starts, verify::kContainsCounters,
                                       [](const auto&) { return true; });
  out["rule"] = to_string(tally.rule);
  out["sets"] = set_costs_json(tally.sets);
  out["judge_seconds"] = tally.judge_seconds;
  out["contains_seconds"] = tally.contains_seconds;
  out["cost_ratio"] = ratio_json(tally.judge_seconds, tally.contains_seconds);
  return out;
}

std::optional<ContainsRule> judged_rule_named(const std::string& s) {
  for (ContainsRule r : {ContainsRule::automatic, ContainsRule::nonzero, ContainsRule::parity, ContainsRule::winding})
    if (s == to_string(r)) return r;
  return std::nullopt;
}

}  // namespace

int run_contains_check(const CheckCliOptions& o) {
  const auto functions = named_commands(o.contains, "--contains");
  if (!functions) return 2;
  if (kernel_options_given(o) || !o.caster.empty()) {
    fmt::print(stderr, "rayproof check: --contains takes --mesh, --json, --out, --seed, --reproducers and the "
                       "--contains-* options; --caster, --exec, --plugin, --glsl, --opencl, --method, --families, "
                       "--expect and --max-ulps apply to other checks\n");
    return 2;
  }
  if (o.mesh.empty()) {
    fmt::print(stderr, "rayproof check: --contains needs --mesh MESH... (mesh files, or `generated`)\n");
    return 2;
  }
  verify::ContainsCheckOptions opt;
  const auto rule = judged_rule_named(o.contains_rule);
  if (!rule) {
    fmt::print(stderr, "rayproof check: --contains-rule '{}' is not automatic, nonzero, parity or winding\n",
               o.contains_rule);
    return 2;
  }
  if (!positive_seconds(o.contains_timeout, "--contains-timeout")) return 2;
  if (o.contains_precision == "float") opt.precision = verify::ContainsPrecision::float32;
  else if (o.contains_precision != "double") {
    fmt::print(stderr, "rayproof check: --contains-precision '{}' is neither float nor double\n", o.contains_precision);
    return 2;
  }
  opt.rule = *rule;
  opt.seed = o.seed;
  opt.random_points = o.contains_points;
  opt.max_points_per_set = o.contains_max_per_set;
  opt.reproducers = o.reproducers;
  opt.sets = o.contains_sets;
  if (!report_dir_ready(o.out)) return 2;

  const auto scale = scale_exponent(o.contains_scale, "--contains-scale");
  if (!scale) return 2;
  auto judged = judged_meshes(o);
  if (!judged) return 2;
  if (!scale_meshes(*judged, *scale, opt.precision == verify::ContainsPrecision::float32, "--contains-scale")) return 2;
  const std::vector<JudgedMesh>& meshes = *judged;

  verify::ExecContainsOptions exec_opt;
  exec_opt.timeout_seconds = o.contains_timeout;
  exec_opt.batch = o.contains_batch;
  bool any_finding = false;
  nlohmann::json json_runs = nlohmann::json::array();
  if (!o.json)
    fmt::print("rayproof check --contains: rule {}, {} precision{}; each point's side judged against rayproof's exact "
               "contains (docs/check.md)\n",
               o.contains_rule, o.contains_precision,
               *scale != 0 ? fmt::format(", the mesh times 2^{}", *scale) : std::string());
  // --out: every function's row, then rayproof's own exact contains on each mesh's points.
  verify::JudgeReport report = verify::contains_report(opt);
  std::vector<verify::JudgeReportRow> builtin_rows;
  struct Prepared {
    verify::ContainsMesh mesh;
    verify::ContainsPoints points;
    verify::ContainsJudge judge;
  };
  const bool prepared = for_each_mesh_and_function(
      meshes, *functions,
      [&](const JudgedMesh& m) {
        const verify::ContainsMesh mesh{m.mesh.vertices, m.mesh.triangles, m.name};
        Prepared p{mesh, verify::contains_points(mesh, opt), verify::ContainsJudge(mesh, opt.rule)};
        if (!o.out.empty()) builtin_rows.push_back(verify::builtin_contains_row(p.mesh, p.points, p.judge, opt));
        return p;
      },
      [&](const NamedCommand& fn, const JudgedMesh& m, const Prepared& p) {
        fmt::print(stderr, "[contains] {} on {}: {} points\n", fn.name, m.name, p.points.points.size());
        const verify::ExecContainsRun run = verify::run_exec_contains(fn.command, p.mesh, p.points, exec_opt);
        const verify::ContainsTally tally = p.judge.judge(p.points, run.answers, opt);
        any_finding = any_finding || tally.findings() > 0;
        if (!o.out.empty())
          report.rows.push_back(verify::report_row(verify::program_run(fn.name, fn.command, run), p.mesh, tally));
        if (o.json) json_runs.push_back(contains_run_json(fn, m, tally, run));
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
