// check --distance: distance functions (programs speaking the line protocol of docs/check.md)
// judged on meshes against rayproof's exact distances (verify/contains_exec.h,
// rayproof/verify/distance_check.h).
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>

#include "cli/mesh_modes.h"
#include "rayproof/verify/distance_check.h"
#include "verify/contains_exec.h"

namespace rayproof::cli {

namespace {

struct NamedDistanceFunction {
  std::string name, command;
};

nlohmann::json distance_run_json(const NamedDistanceFunction& fn, const JudgedMesh& mesh,
                                 const verify::DistanceTally& tally, const verify::ExecDistanceRun& run) {
  auto ratio = [](double judge, double base) { return base > 0 ? nlohmann::json(judge / base) : nullptr; };
  nlohmann::json sets = nlohmann::json::object();
  for (const auto& s : tally.sets)
    sets[s.set] = {{"points", s.points}, {"findings", s.findings}, {"cost_ratio", ratio(s.judge_seconds, s.contains_seconds)}};
  nlohmann::json reproducers = nlohmann::json::array();
  for (const auto& r : tally.reproducers) reproducers.push_back(r.line);
  nlohmann::json out = {{"function", fn.name}, {"command", fn.command}, {"mesh", mesh.name},
                        {"triangles", mesh.mesh.triangles.size()}, {"signed", tally.signed_distance},
                        {"rel_tol", tally.rel_tol}, {"max_rel_error", tally.max_rel_error}, {"sets", sets},
                        {"events", run.events}, {"starts", run.starts}, {"reproducers", reproducers},
                        {"notes", tally.notes}, {"judge_seconds", tally.judge_seconds},
                        {"closest_seconds", tally.closest_seconds},
                        {"cost_ratio", ratio(tally.judge_seconds, tally.closest_seconds)}};
  for (const verify::DistanceCounter& counter : verify::kDistanceCounters)
    out[std::string(counter.key)] = verify::count_of(tally, counter);
  return out;
}

}  // namespace

int run_distance_check(const CheckCliOptions& o) {
  std::vector<NamedDistanceFunction> functions;
  for (const auto& spec : o.distance) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) {
      fmt::print(stderr, "rayproof check: --distance '{}' is not NAME=COMMAND\n", spec);
      return 2;
    }
    functions.push_back({spec.substr(0, eq), spec.substr(eq + 1)});
  }
  const std::size_t others = o.user.exec.size() + o.user.plugin.size() + o.user.opencl.size() + o.user.glsl.size() +
                             (o.method.empty() ? 0 : 1);
  if (others > 0 || !o.caster.empty() || !o.contains.empty() || !o.families.empty() || !o.expect.empty() ||
      o.max_ulps || !o.out.empty()) {
    fmt::print(stderr, "rayproof check: --distance takes --mesh, --json, --seed, --reproducers and the --distance-* "
                       "options; --caster, --contains, --exec, --plugin, --glsl, --opencl, --method, --families, "
                       "--expect, --max-ulps and --out apply to other checks\n");
    return 2;
  }
  if (o.mesh.empty()) {
    fmt::print(stderr, "rayproof check: --distance needs --mesh MESH... (mesh files, or `generated`)\n");
    return 2;
  }
  if (!(o.distance_timeout > 0) || !std::isfinite(o.distance_timeout)) {
    fmt::print(stderr, "rayproof check: --distance-timeout must be a positive number of seconds\n");
    return 2;
  }
  if (!(o.distance_rel_tol >= 0) || !std::isfinite(o.distance_rel_tol)) {
    fmt::print(stderr, "rayproof check: --distance-rel-tol must be a finite number >= 0\n");
    return 2;
  }
  verify::DistanceCheckOptions opt;
  opt.signed_distance = o.distance_signed;
  opt.rel_tol = o.distance_rel_tol;
  opt.seed = o.seed;
  opt.random_points = o.distance_points;
  opt.max_points_per_set = o.distance_max_per_set;
  opt.reproducers = o.reproducers;
  opt.sets = o.distance_sets;
  const auto judged = judged_meshes(o);
  if (!judged) return 2;

  verify::ExecContainsOptions exec_opt;
  exec_opt.timeout_seconds = o.distance_timeout;
  exec_opt.batch = o.distance_batch;
  bool any_finding = false;
  nlohmann::json json_runs = nlohmann::json::array();
  if (!o.json)
    fmt::print("rayproof check --distance: {} distances judged against rayproof's exact distance, correctly rounded "
               "(docs/check.md)\n",
               o.distance_signed ? "signed" : "unsigned");
  for (const auto& m : *judged) {
    const verify::ContainsMesh mesh{m.mesh.vertices, m.mesh.triangles, m.name};
    verify::ContainsPoints points;
    std::optional<verify::DistanceJudge> judge;
    try {
      points = verify::distance_points(mesh, opt);
      judge.emplace(mesh);
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof check: {}: {}\n", m.name, e.what());
      return 2;
    }
    for (const auto& fn : functions) {
      fmt::print(stderr, "[distance] {} on {}: {} points\n", fn.name, m.name, points.points.size());
      const verify::ExecDistanceRun run = verify::run_exec_distance(fn.command, mesh, points, exec_opt);
      const verify::DistanceTally tally = judge->judge(points, run.answers, opt);
      any_finding = any_finding || tally.findings() > 0;
      if (o.json) {
        json_runs.push_back(distance_run_json(fn, m, tally, run));
        continue;
      }
      fmt::print("\nfunction '{}' ({}) on {} ({} triangles): {} points, started {} time{}\n", fn.name, fn.command,
                 m.name, m.mesh.triangles.size(), tally.points, run.starts, run.starts == 1 ? "" : "s");
      fmt::print("{}", verify::summary_text(tally));
      for (const auto& e : run.events) fmt::print("event: {}\n", e);
      if (tally.findings() == 0)
        fmt::print("function '{}' answered all {} points on {} within 1 ulp{}\n", fn.name, tally.points, m.name,
                   opt.rel_tol > 0 ? fmt::format(" or a relative {}", opt.rel_tol) : std::string());
      else
        fmt::print("function '{}' differs from exact on {} of {} points on {}\n", fn.name, tally.findings(),
                   tally.points, m.name);
    }
  }
  if (o.json) fmt::print("{}\n", nlohmann::json{{"functions", json_runs}, {"findings", any_finding}}.dump(1));
  return any_finding ? 1 : 0;
}

}  // namespace rayproof::cli
