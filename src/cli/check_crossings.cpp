// check --crossings: all-hits functions (programs speaking the line protocol of docs/check.md, "All
// hits") judged on meshes against rayproof's exact crossings (verify/crossings_exec.h,
// rayproof/verify/crossings_check.h). Its options are registered here (add_crossings_check_options).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <optional>

#include "cli/judge_cli.h"
#include "cli/mesh_modes.h"
#include "rayproof/verify/crossings_check.h"
#include "verify/crossings_exec.h"

namespace rayproof::cli {

namespace {

nlohmann::json crossings_run_json(const NamedCommand& fn, const JudgedMesh& mesh, const verify::CrossingsTally& tally,
                                  const verify::ExecCrossingsRun& run) {
  nlohmann::json out = judged_run_json("function", fn, mesh, tally, run.events, run.starts, verify::kCrossingsCounters,
                                       [](const auto&) { return true; });
  out["precision"] = tally.precision == verify::CasterPrecision::float32 ? "float" : "double";
  out["tolerance_ulps"] = tally.tolerance_ulps;
  out["rays_with_findings"] = tally.rays_with_findings;
  nlohmann::json sets = nlohmann::json::object();
  for (const auto& s : tally.sets)
    sets[s.set] = {{"rays", s.points}, {"findings", s.findings}, {"cost_ratio", ratio_json(s.judge_seconds, s.contains_seconds)}};
  out["sets"] = sets;
  out["judge_seconds"] = tally.judge_seconds;
  out["crossings_seconds"] = tally.crossings_seconds;
  out["cost_ratio"] = ratio_json(tally.judge_seconds, tally.crossings_seconds);
  return out;
}

}  // namespace

void add_crossings_check_options(CLI::App& sub, CheckCliOptions& o) {
  sub.add_option("--crossings", o.crossings,
                 "NAME=COMMAND: an all-hits function judged on --mesh: it reads the mesh, then batches of rays, and "
                 "answers every hit of each ray as (t, triangle) pairs (docs/check.md); repeatable. With --out: report.md "
                 "and report.html, rayproof's own crossings beside");
  sub.add_option("--crossings-precision", o.crossings_precision,
                 "The function's precision: float (float rays, t in float ulps) or double")
      ->capture_default_str();
  sub.add_option("--crossings-max-ulps", o.crossings_max_ulps, "t error allowed, in ulps of the precision")
      ->capture_default_str();
  sub.add_option("--crossings-timeout", o.crossings_timeout, "Seconds the function may take per answer line")
      ->capture_default_str();
  sub.add_option("--crossings-batch", o.crossings_batch, "Rays per batch sent to the function")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}))
      ->capture_default_str();
  sub.add_option("--crossings-rays", o.crossings_rays, "Random rays per mesh (the other sets follow the mesh)")
      ->capture_default_str();
  sub.add_option("--crossings-max-per-set", o.crossings_max_per_set, "Rays per set at most (evenly subsampled)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000000}))
      ->capture_default_str();
  sub.add_option("--crossings-sets", o.crossings_sets,
                 "Ray sets: leak, graze, face, surface, random, extreme, invalid (default: all)")
      ->delimiter(',')->allow_extra_args(false);
}

int run_crossings_check(const CheckCliOptions& o) {
  const auto functions = named_commands(o.crossings, "--crossings");
  if (!functions) return 2;
  if (kernel_options_given(o) || !o.caster.empty() || !o.contains.empty() || !o.distance.empty()) {
    fmt::print(stderr, "rayproof check: --crossings takes --mesh, --json, --out, --seed, --reproducers and the "
                       "--crossings-* options; --caster, --contains, --distance, --exec, --plugin, --glsl, --opencl, "
                       "--method, --families, --expect and --max-ulps apply to other checks\n");
    return 2;
  }
  if (o.mesh.empty()) {
    fmt::print(stderr, "rayproof check: --crossings needs --mesh MESH... (mesh files, or `generated`)\n");
    return 2;
  }
  verify::CrossingsCheckOptions opt;
  if (o.crossings_precision == "float") opt.precision = verify::CasterPrecision::float32;
  else if (o.crossings_precision != "double") {
    fmt::print(stderr, "rayproof check: --crossings-precision '{}' is neither float nor double\n", o.crossings_precision);
    return 2;
  }
  if (!positive_seconds(o.crossings_timeout, "--crossings-timeout")) return 2;
  opt.max_ulps = o.crossings_max_ulps;
  opt.seed = o.seed;
  opt.random_rays = o.crossings_rays;
  opt.max_rays_per_set = o.crossings_max_per_set;
  opt.reproducers = o.reproducers;
  opt.sets = o.crossings_sets;
  if (!report_dir_ready(o.out)) return 2;
  const auto judged = judged_meshes(o);
  if (!judged) return 2;

  verify::ExecCrossingsOptions exec_opt;
  exec_opt.timeout_seconds = o.crossings_timeout;
  exec_opt.batch = o.crossings_batch;
  bool any_finding = false;
  nlohmann::json json_runs = nlohmann::json::array();
  if (!o.json)
    fmt::print("rayproof check --crossings: every hit of each ray judged against rayproof's exact crossings "
               "({} precision, t within {} ulp{}; docs/check.md)\n",
               o.crossings_precision, opt.max_ulps, opt.max_ulps == 1 ? "" : "s");
  // --out: every function's row, then rayproof's own exact crossings on each mesh's rays.
  verify::JudgeReport report = verify::crossings_report(opt);
  std::vector<verify::JudgeReportRow> builtin_rows;
  struct Prepared {
    verify::CasterMesh mesh;
    verify::CasterRays rays;
    verify::CrossingsJudge judge;
  };
  const bool prepared = for_each_mesh_and_function(
      *judged, *functions,
      [&](const JudgedMesh& m) {
        const verify::CasterMesh mesh{m.mesh.vertices, m.mesh.triangles, m.name};
        Prepared p{mesh, verify::crossings_rays(mesh, opt), verify::CrossingsJudge(mesh)};
        if (!o.out.empty()) builtin_rows.push_back(verify::builtin_crossings_row(p.mesh, p.rays, p.judge, opt));
        return p;
      },
      [&](const NamedCommand& fn, const JudgedMesh& m, const Prepared& p) {
        fmt::print(stderr, "[crossings] {} on {}: {} rays\n", fn.name, m.name, p.rays.rays.size());
        const verify::ExecCrossingsRun run = verify::run_exec_crossings(fn.command, p.mesh, p.rays, exec_opt);
        const verify::CrossingsTally tally = p.judge.judge(p.rays, run.answers, opt);
        any_finding = any_finding || tally.findings() > 0;
        if (!o.out.empty())
          report.rows.push_back(verify::report_row(verify::program_run(fn.name, fn.command, run), p.mesh, tally));
        if (o.json) json_runs.push_back(crossings_run_json(fn, m, tally, run));
        else
          print_judged_run({"function", "rays", fn, m, tally.rays, tally.rays_with_findings, run.starts,
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
