// check --caster: whole casters (programs speaking the line protocol of docs/check.md) judged on
// meshes against exact answers (verify/caster_exec.h, rayproof/verify/caster_check.h).
#include <fmt/core.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>

#include "cli/judge_cli.h"
#include "cli/mesh_modes.h"
#include "cli/scene_input.h"
#include "mesh/mesh.h"
#include "rayproof/verify/caster_check.h"
#include "verify/caster_exec.h"
#include "verify/caster_report.h"
#include "verify/mesh_check.h"

namespace rayproof::cli {

namespace {

/// One caster's run on one mesh, as `--json` prints it: every count of the tally shown (by its
/// key), per-set counts, events, reproducers and notes.
nlohmann::json run_json(const NamedCommand& caster, const JudgedMesh& mesh, const verify::CasterTally& tally,
                        const verify::ExecCasterRun& run) {
  nlohmann::json out = judged_run_json("caster", caster, mesh, tally, run.events, run.starts, verify::kCasterCounters,
                                       [&](const verify::CasterCounter& c) { return verify::shown(tally, c); });
  nlohmann::json sets = nlohmann::json::object();
  for (const auto& s : tally.sets) sets[s.set] = {{"rays", s.rays}, {"findings", s.findings}, {"false_miss", s.false_miss}};
  out["sets"] = sets;
  return out;
}

}  // namespace

std::optional<std::vector<JudgedMesh>> judged_meshes(const CheckCliOptions& o) {
  std::vector<JudgedMesh> meshes;
  for (const auto& name : o.mesh) {
    if (name == "generated") {
      verify::MeshFuzzOptions gen_opt;
      gen_opt.seed = o.seed;
      for (std::size_t i = 0; i < o.meshes; ++i) {
        verify::MeshUnderTest mt = verify::generated_mesh(gen_opt, i);
        meshes.push_back({mt.name, std::move(mt.mesh)});
      }
      continue;
    }
    try {
      meshes.push_back({name, mesh::read_mesh(name)});
      fmt::print(stderr, "rayproof check: {}: {} triangles{}\n", name, meshes.back().mesh.triangles.size(),
                 reader_note(name));
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof check: {}\n", e.what());
      return std::nullopt;
    }
  }
  return meshes;
}

int run_caster_check(const CheckCliOptions& o) {
  const auto casters = named_commands(o.caster, "--caster");
  if (!casters) return 2;
  if (kernel_options_given(o)) {
    fmt::print(stderr, "rayproof check: --caster takes --mesh, --out and the --caster-* options; --exec, --plugin, "
                       "--glsl, --opencl, --method, --families, --expect and --max-ulps apply to kernels\n");
    return 2;
  }
  if (o.mesh.empty()) {
    fmt::print(stderr, "rayproof check: --caster needs --mesh MESH... (mesh files, or `generated`)\n");
    return 2;
  }
  verify::CasterCheckOptions opt;
  if (o.caster_precision == "float") opt.precision = verify::CasterPrecision::float32;
  else if (o.caster_precision != "double") {
    fmt::print(stderr, "rayproof check: --caster-precision '{}' is neither float nor double\n", o.caster_precision);
    return 2;
  }
  if (!positive_seconds(o.caster_timeout, "--caster-timeout")) return 2;
  opt.seed = o.seed;
  opt.random_rays = o.caster_rays;
  opt.max_rays_per_set = o.caster_max_per_set;
  opt.reproducers = o.reproducers;
  opt.sets = o.caster_sets;

  const auto judged = judged_meshes(o);
  if (!judged) return 2;
  const std::vector<JudgedMesh>& meshes = *judged;

  verify::ExecCasterOptions exec_opt;
  exec_opt.timeout_seconds = o.caster_timeout;
  exec_opt.batch = o.caster_batch;
  bool any_finding = false;
  nlohmann::json json_runs = nlohmann::json::array();
  std::vector<verify::CasterReportRow> report_rows;
  if (!o.json)
    fmt::print("rayproof check --caster: {} precision; crossings at t > 0 judged against rayproof's certified caster "
               "and exact per-triangle tests (docs/check.md)\n",
               o.caster_precision);
  struct Prepared {
    verify::CasterMesh mesh;
    verify::CasterRays rays;
    verify::CasterJudge judge;
  };
  const bool prepared = for_each_mesh_and_function(
      meshes, *casters,
      [&](const JudgedMesh& m) {
        const verify::CasterMesh caster_mesh{m.mesh.vertices, m.mesh.triangles, m.name};
        return Prepared{caster_mesh, verify::caster_rays(caster_mesh, opt), verify::CasterJudge(caster_mesh)};
      },
      [&](const NamedCommand& caster, const JudgedMesh& m, const Prepared& p) {
        fmt::print(stderr, "[caster] {} on {}: {} rays\n", caster.name, m.name, p.rays.rays.size());
        const verify::ExecCasterRun run = verify::run_exec_caster(caster.command, p.mesh, p.rays, exec_opt);
        const verify::CasterTally tally = p.judge.judge(p.rays, run.answers, opt);
        any_finding = any_finding || tally.findings() > 0;
        if (!o.out.empty())
          report_rows.push_back({caster.name, caster.command, m.name, m.mesh.triangles.size(), tally, run.events});
        if (o.json) json_runs.push_back(run_json(caster, m, tally, run));
        else
          print_judged_run({"caster", "rays", caster, m, tally.rays, tally.findings(), run.starts,
                            verify::summary_text(tally), run.events, " as exact arithmetic does (t within 1 ulp)"});
      });
  if (!prepared) return 2;
  if (!o.out.empty()) {
    // rayproof's own casters on the same rays, beside the casters under test.
    for (const auto& m : meshes) {
      const verify::CasterMesh caster_mesh{m.mesh.vertices, m.mesh.triangles, m.name};
      const verify::CasterRays rays = verify::caster_rays(caster_mesh, opt);
      const verify::CasterJudge judge(caster_mesh);
      for (auto& row : verify::builtin_caster_rows(caster_mesh, rays, judge, opt))
        report_rows.push_back(std::move(row));
    }
    try {
      verify::write_caster_report(o.out, report_rows, o.caster_precision);
      fmt::print(stderr, "rayproof check: wrote {}/report.md and {}/report.html\n", o.out, o.out);
    } catch (const std::exception& e) {
      fmt::print(stderr, "rayproof check: {}\n", e.what());
      return 2;
    }
  }
  if (o.json) fmt::print("{}\n", nlohmann::json{{"casters", json_runs}, {"findings", any_finding}}.dump(1));
  return any_finding ? 1 : 0;
}

}  // namespace rayproof::cli
