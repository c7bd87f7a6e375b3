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
  if (kernel_options_given(o) || !o.caster.empty() || !o.out.empty()) {
    fmt::print(stderr, "rayproof check: --contains takes --mesh, --json, --seed, --reproducers and the --contains-* "
                       "options; --caster, --exec, --plugin, --glsl, --opencl, --method, --families, --expect, "
                       "--max-ulps and --out apply to other checks\n");
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

  const auto judged = judged_meshes(o);
  if (!judged) return 2;
  const std::vector<JudgedMesh>& meshes = *judged;

  verify::ExecContainsOptions exec_opt;
  exec_opt.timeout_seconds = o.contains_timeout;
  exec_opt.batch = o.contains_batch;
  bool any_finding = false;
  nlohmann::json json_runs = nlohmann::json::array();
  if (!o.json)
    fmt::print("rayproof check --contains: rule {}, {} precision; each point's side judged against rayproof's exact "
               "contains (docs/check.md)\n",
               o.contains_rule, o.contains_precision);
  struct Prepared {
    verify::ContainsMesh mesh;
    verify::ContainsPoints points;
    verify::ContainsJudge judge;
  };
  const bool prepared = for_each_mesh_and_function(
      meshes, *functions,
      [&](const JudgedMesh& m) {
        const verify::ContainsMesh mesh{m.mesh.vertices, m.mesh.triangles, m.name};
        return Prepared{mesh, verify::contains_points(mesh, opt), verify::ContainsJudge(mesh, opt.rule)};
      },
      [&](const NamedCommand& fn, const JudgedMesh& m, const Prepared& p) {
        fmt::print(stderr, "[contains] {} on {}: {} points\n", fn.name, m.name, p.points.points.size());
        const verify::ExecContainsRun run = verify::run_exec_contains(fn.command, p.mesh, p.points, exec_opt);
        const verify::ContainsTally tally = p.judge.judge(p.points, run.answers, opt);
        any_finding = any_finding || tally.findings() > 0;
        if (o.json) json_runs.push_back(contains_run_json(fn, m, tally, run));
        else
          print_judged_run({"function", "points", fn, m, tally.points, tally.findings(), run.starts,
                            verify::summary_text(tally), run.events, " as exact arithmetic does"});
      });
  if (!prepared) return 2;
  if (o.json) fmt::print("{}\n", nlohmann::json{{"functions", json_runs}, {"findings", any_finding}}.dump(1));
  return any_finding ? 1 : 0;
}

}  // namespace rayproof::cli
