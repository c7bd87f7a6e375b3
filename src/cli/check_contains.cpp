// check --contains: containment functions (programs speaking the line protocol of docs/check.md)
// judged on meshes against rayproof's exact contains (verify/contains_exec.h,
// rayproof/verify/contains_check.h).
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>

#include "cli/mesh_modes.h"
#include "mesh/mesh.h"
#include "rayproof/verify/contains_check.h"
#include "verify/contains_exec.h"

namespace rayproof::cli {

namespace {

struct NamedContainsFunction {
  std::string name, command;
};

/// One function's run on one mesh, as `--json` prints it: every count (by its key), the rule,
/// per-set counts and costs, events, reproducers and notes.
nlohmann::json contains_run_json(const NamedContainsFunction& fn, const JudgedMesh& mesh, const verify::ContainsTally& tally,
                        const verify::ExecContainsRun& run) {
  auto ratio = [](double judge, double contains) { return contains > 0 ? nlohmann::json(judge / contains) : nullptr; };
  nlohmann::json sets = nlohmann::json::object();
  for (const auto& s : tally.sets)
    sets[s.set] = {{"points", s.points}, {"findings", s.findings}, {"cost_ratio", ratio(s.judge_seconds, s.contains_seconds)}};
  nlohmann::json reproducers = nlohmann::json::array();
  for (const auto& r : tally.reproducers) reproducers.push_back(r.line);
  nlohmann::json out = {{"function", fn.name}, {"command", fn.command}, {"mesh", mesh.name},
                        {"triangles", mesh.mesh.triangles.size()}, {"rule", to_string(tally.rule)},
                        {"sets", sets}, {"events", run.events}, {"starts", run.starts},
                        {"reproducers", reproducers}, {"notes", tally.notes},
                        {"judge_seconds", tally.judge_seconds}, {"contains_seconds", tally.contains_seconds},
                        {"cost_ratio", ratio(tally.judge_seconds, tally.contains_seconds)}};
  for (const verify::ContainsCounter& counter : verify::kContainsCounters)
    out[std::string(counter.key)] = verify::count_of(tally, counter);
  return out;
}

std::optional<ContainsRule> judged_rule_named(const std::string& s) {
  for (ContainsRule r : {ContainsRule::automatic, ContainsRule::nonzero, ContainsRule::parity, ContainsRule::winding})
    if (s == to_string(r)) return r;
  return std::nullopt;
}

}  // namespace

int run_contains_check(const CheckCliOptions& o) {
  std::vector<NamedContainsFunction> functions;
  for (const auto& spec : o.contains) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
      fmt::print(stderr, "rayproof check: --contains '{}' is not NAME=COMMAND\n", spec);
      return 2;
    }
    functions.push_back({spec.substr(0, eq), spec.substr(eq + 1)});
  }
  const std::size_t others = o.user.exec.size() + o.user.plugin.size() + o.user.opencl.size() + o.user.glsl.size() +
                             (o.method.empty() ? 0 : 1);
  if (others > 0 || !o.caster.empty() || !o.families.empty() || !o.expect.empty() || o.max_ulps || !o.out.empty()) {
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
  if (!(o.contains_timeout > 0) || !std::isfinite(o.contains_timeout)) {
    fmt::print(stderr, "rayproof check: --contains-timeout must be a positive number of seconds\n");
    return 2;
  }
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
  for (const auto& m : meshes) {
    const verify::ContainsMesh contains_mesh{m.mesh.vertices, m.mesh.triangles, m.name};
    verify::ContainsPoints points;
    std::optional<verify::ContainsJudge> judge;
    try {
      points = verify::contains_points(contains_mesh, opt);
      judge.emplace(contains_mesh, opt.rule);
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof check: {}: {}\n", m.name, e.what());
      return 2;
    }
    for (const auto& fn : functions) {
      fmt::print(stderr, "[contains] {} on {}: {} points\n", fn.name, m.name, points.points.size());
      const verify::ExecContainsRun run = verify::run_exec_contains(fn.command, contains_mesh, points, exec_opt);
      const verify::ContainsTally tally = judge->judge(points, run.answers, opt);
      any_finding = any_finding || tally.findings() > 0;
      if (o.json) {
        json_runs.push_back(contains_run_json(fn, m, tally, run));
        continue;
      }
      fmt::print("\nfunction '{}' ({}) on {} ({} triangles): {} points, started {} time{}\n", fn.name, fn.command,
                 m.name, m.mesh.triangles.size(), tally.points, run.starts, run.starts == 1 ? "" : "s");
      fmt::print("{}", verify::summary_text(tally));
      for (const auto& e : run.events) fmt::print("event: {}\n", e);
      if (tally.findings() == 0)
        fmt::print("function '{}' answered all {} points on {} as exact arithmetic does\n", fn.name, tally.points,
                   m.name);
      else
        fmt::print("function '{}' differs from exact on {} of {} points on {}\n", fn.name, tally.findings(),
                   tally.points, m.name);
    }
  }
  if (o.json) fmt::print("{}\n", nlohmann::json{{"functions", json_runs}, {"findings", any_finding}}.dump(1));
  return any_finding ? 1 : 0;
}

}  // namespace rayproof::cli
