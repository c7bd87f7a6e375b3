/// rayproof check: one kernel (--exec, --plugin, or a built-in --method) under the exact
/// differential test over every built-in family of the kinds it answers; a verdict per family, the
/// worst reproducers, the usual report with the kernel among the built-in methods, and an exit
/// status for the promises the user states (--expect watertight|exact-class, --max-ulps N).
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <fmt/format.h>

#include <chrono>
#include <memory>
#include <nlohmann/json.hpp>

#include "verify/build_compare.h"
#include "verify/check_text.h"
#include "cli/commands.h"
#include "cli/mesh_modes.h"
#include "cli/tool.h"
#include "registry/registry.h"
#include "cli/user_kernels.h"
#include "methods/plugin_kernel.h"
#include "report/report.h"
#include "report/html.h"
#include "verify/check.h"

namespace rayproof::cli {

namespace {

/// --compare-plugin: the --opencl kernel against the C build of its formula on the check's cases,
/// and the same kernel built without contraction (verify/build_compare.h). Nothing on a bad option
/// (the message is printed).
std::optional<verify::BuildComparison> compare_with_plugin(const CheckCliOptions& o, const Method& kernel,
                                                   const verify::CheckResult& res) {
  if (o.user.opencl.size() != 1) {
    fmt::print(stderr, "rayproof check: --compare-plugin compares an --opencl kernel with the C build of its formula\n");
    return std::nullopt;
  }
  auto loaded = load_plugin_method(o.compare_plugin, "");
  if (auto* why = std::get_if<std::string>(&loaded)) {
    fmt::print(stderr, "rayproof check: --compare-plugin: {}\n", *why);
    return std::nullopt;
  }
  const Method& c = std::get<Method>(loaded);
  if (c.precision != kernel.precision) {
    fmt::print(stderr, "rayproof check: --compare-plugin {} is {} precision, the kernel {}: compare like with like\n",
               o.compare_plugin, c.precision == Precision::float32 ? "float" : "double",
               kernel.precision == Precision::float32 ? "float" : "double");
    return std::nullopt;
  }
  OpenclDeviceReport rep;
  auto uncontracted = make_opencl_kernel("check", o.user.opencl.front(), o.user, true, &rep);
  if (!uncontracted) return std::nullopt;
  uncontracted->name = kernel.name + "-contract-off";
  std::vector<io::Case> cases;
  for (const auto& fc : res.families)
    for (auto p : {gen::Precision::float32, gen::Precision::float64}) {
      const std::size_t n = p == gen::Precision::float32 ? o.count / 2 : o.count - o.count / 2;
      for (auto& cs : gen::generate(*gen::find_family(fc.family), n, o.seed, p))
        if (kernel.supports(cs.kind) && c.supports(cs.kind))
          cases.push_back(kernel.precision == Precision::float32 ? io::round_to_float(cs) : cs);
    }
  auto r = verify::compare_builds(verify::DeviceLanguage::opencl, kernel, c, uncontracted.get(), cases, o.reproducers);
  if (kernel.precision == Precision::float32) {
    if (o.user.cl_options.find("-cl-denorms-are-zero") != std::string::npos)
      r.device_note = "asked to flush subnormal floats to zero (-cl-denorms-are-zero)";
    else if (!rep.float_denorms)
      r.device_note = "flushes subnormal floats to zero (no CL_FP_DENORM in CL_DEVICE_SINGLE_FP_CONFIG)";
    else
      r.device_note = "declares subnormal floats (CL_FP_DENORM)";
  }
  return r;
}

nlohmann::json ulps_json(std::uint64_t u) {
  if (u == std::numeric_limits<std::uint64_t>::max()) return nullptr;  // a NaN or missing t
  return u;
}

nlohmann::json result_json(const verify::CheckResult& r) {
  auto stats = [](const verify::Stats& s) {
    return nlohmann::json{{"cases", s.cases},
                          {"false_hit", s.false_hit},
                          {"false_miss", s.false_miss},
                          {"wrong_hit_class", s.wrong_hit_class},
                          {"wrong_class", s.wrong_class},
                          {"ulp_median", ulps_json(s.ulp_quantile(0.5))},
                          {"ulp_p99", ulps_json(s.ulp_quantile(0.99))},
                          {"ulp_max", ulps_json(s.ulp_quantile(1.0))},
                          {"fallbacks", s.fallbacks}};
  };
  nlohmann::json fams = nlohmann::json::array();
  for (const auto& f : r.families) {
    auto j = stats(f.stats);
    j["family"] = f.family;
    j["over_tolerance"] = f.over_tolerance;
    j["failures"] = f.failures.size();
    nlohmann::json worst = nlohmann::json::array();
    for (const auto& w : f.worst)
      worst.push_back({{"case", io::format_case(w.judged.input)}, {"verdict", verify::to_string(w.judged.verdict)},
                       {"got", io::format_result(w.judged.got)}, {"exact", io::format_result(w.judged.want)},
                       {"ulps", ulps_json(w.judged.ulps)}, {"minimized", w.minimized}});
    for (const auto& kf : f.failures)
      worst.push_back({{"case", io::format_case(kf.input)}, {"verdict", "kernel-failure"}, {"what", kf.what}});
    j["reproducers"] = worst;
    fams.push_back(j);
  }
  auto total = stats(r.total());
  total["over_tolerance"] = r.over_tolerance();
  total["failures"] = r.failures();
  nlohmann::json promises = nlohmann::json::array();
  for (const auto& p : r.promises) promises.push_back({{"promise", p.promise}, {"kept", p.kept}, {"violations", p.violations}});
  return {{"method", r.method},
          {"precision", r.precision == Precision::float32 ? "float" : "double"},
          {"seed", r.seed},
          {"count", r.count},
          {"ulp_tolerance", r.ulp_tolerance},
          {"families", fams},
          {"total", total},
          {"promises", promises},
          {"promises_kept", r.promises_kept()}};
}


int run_check(const CheckCliOptions& o) {
  if (!o.crossings.empty()) return run_crossings_check(o);
  if (!o.distance.empty()) return run_distance_check(o);
  if (!o.contains.empty()) return run_contains_check(o);
  if (!o.caster.empty()) return run_caster_check(o);
  // The kernel under test: exactly one of --exec, --plugin, --method.
  const std::size_t named =
      o.user.exec.size() + o.user.plugin.size() + o.user.opencl.size() + o.user.glsl.size() + (o.method.empty() ? 0 : 1);
  if (named != 1) {
    fmt::print(stderr, "rayproof check: name one kernel to check: --exec NAME=COMMAND, --plugin NAME=PATH.so, "
                       "--glsl NAME=FILE, --opencl NAME=FILE or --method NAME ({} given)\n", named);
    return 2;
  }
  if (!o.compare_plugin.empty() && ((o.user.glsl.empty() && o.user.opencl.empty()) || !o.mesh.empty())) {
    fmt::print(stderr, "rayproof check: --compare-plugin compares a --glsl or --opencl kernel with the C build of its "
                       "formula on the families (not with --mesh)\n");
    return 2;
  }
  std::vector<std::unique_ptr<Method>> owned;
  const Method* kernel = nullptr;
  if (!o.method.empty()) {
    kernel = registry::all_methods().find(o.method);
    if (!kernel) {
      fmt::print(stderr, "rayproof check: unknown method '{}' (known: {})\n", o.method, registry::all_methods().names());
      return 2;
    }
  } else {
    UserKernelOptions u = o.user;
    u.plugin_in_process = o.plugin_in_process;  // forked by default: a crashing plugin is a finding, not the end
    auto made = make_user_kernels("check", u);
    if (!made) return 2;
    if (made->size() != 1) {
      fmt::print(stderr, "rayproof check: the kernel could not be made\n");
      return 2;
    }
    owned = std::move(*made);
    kernel = owned.front().get();
  }
  if (kernel->kinds.empty()) {
    fmt::print(stderr, "rayproof check: kernel '{}' answers no kind of case\n", kernel->name);
    return 2;
  }
  if (!o.mesh.empty()) return run_mesh_check(o, *kernel);

  verify::CheckOptions opt;
  opt.count = o.count;
  opt.seed = o.seed;
  opt.reproducers = o.reproducers;
  for (const auto& name : o.families) {
    const gen::Family* f = gen::find_family(name);
    if (!f) {
      fmt::print(stderr, "rayproof check: unknown family '{}' (known: {})\n", name, gen::family_names());
      return 2;
    }
    if (!f->every_kind && !kernel->supports(f->kind)) {
      fmt::print(stderr, "rayproof check: family '{}' is of kind {}, which kernel '{}' does not answer\n", name,
                 io::to_string(f->kind), kernel->name);
      return 2;
    }
    opt.families.push_back(f);
  }
  for (const auto& e : o.expect) {
    if (e == "watertight") opt.promises.watertight = true;
    else if (e == "exact-class") opt.promises.exact_class = true;
    else if (e == "no-false-negative") opt.promises.no_false_negative = true;
    else {
      fmt::print(stderr, "rayproof check: unknown promise '{}' for --expect (known: watertight, exact-class, no-false-negative; "
                         "a t bound is --max-ulps N)\n", e);
      return 2;
    }
  }
  if (opt.promises.watertight) {
    const bool runs_them = opt.families.empty()
                               ? kernel->supports(io::Kind::triangle)
                               : std::any_of(opt.families.begin(), opt.families.end(),
                                             [](const gen::Family* f) { return verify::is_watertight_family(f->name); });
    if (!runs_them) {
      fmt::print(stderr, "rayproof check: --expect watertight is judged on the families tri_edge and tri_vertex, "
                         "which this run does not include{}\n",
                 kernel->supports(io::Kind::triangle) ? "" : " (the kernel answers no triangles)");
      return 2;
    }
  }
  opt.promises.max_ulps = o.max_ulps;
  if (o.max_ulps) opt.ulp_tolerance = *o.max_ulps;
  const auto start = std::chrono::steady_clock::now();
  opt.progress = [&](const verify::CheckProgress& p) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fmt::print(stderr, "[{:6.1f}s] {}/{} {} ({} cases so far)\n", s, p.families_done, p.families_total, p.family,
               p.cases_done);
  };
  const verify::CheckResult res = verify::check(*kernel, opt);
  std::optional<verify::BuildComparison> builds;
  if (!o.compare_plugin.empty() && !o.user.opencl.empty()) {  // the --glsl comparison follows
    builds = compare_with_plugin(o, *kernel, res);
    if (!builds) return 2;
  }

  // The cases of the families run, as the report and the build comparison see them.
  auto family_cases = [&] {
    std::vector<io::Case> cases;
    for (const auto& fc : res.families)
      for (auto p : {gen::Precision::float32, gen::Precision::float64}) {
        const std::size_t n = p == gen::Precision::float32 ? o.count / 2 : o.count - o.count / 2;
        auto part = gen::generate(*gen::find_family(fc.family), n, o.seed, p);
        for (auto& c : part)
          if (kernel->supports(c.kind)) cases.push_back(std::move(c));
      }
    return cases;
  };
  if (!o.compare_plugin.empty() && !o.user.glsl.empty()) {
    auto loaded = load_plugin_method(o.compare_plugin);
    if (auto* why = std::get_if<std::string>(&loaded)) {
      fmt::print(stderr, "rayproof check: --compare-plugin: {}\n", *why);
      return 2;
    }
    const Method& c = std::get<Method>(loaded);
    if (c.precision != kernel->precision) {
      fmt::print(stderr, "rayproof check: --compare-plugin {}: a {} plugin, the kernel is {}: compare builds of one "
                         "precision\n", o.compare_plugin, c.precision == Precision::float32 ? "float" : "double",
                 kernel->precision == Precision::float32 ? "float" : "double");
      return 2;
    }
    UserKernelOptions precise_opt = o.user;
    precise_opt.glsl_precise = true;
    auto precise = make_user_kernels("check", precise_opt);
    if (!precise) return 2;
    auto cases = family_cases();
    if (kernel->precision == Precision::float32)
      for (auto& x : cases) x = io::round_to_float(x);
    builds = verify::compare_builds(verify::DeviceLanguage::glsl, *kernel, c, precise->front().get(), cases,
                                    o.reproducers * 4);
    if (const auto at = kernel->summary.find("; subnormal "); at != std::string::npos)
      builds->device_note = kernel->summary.substr(at + 2);
  }

  if (!o.out.empty()) {
    std::vector<const Method*> methods{kernel};
    auto compare = registry::select_methods("check", o.compare, true);
    if (!compare) return 2;
    for (const Method* m : *compare)
      if (m->name != kernel->name) methods.push_back(m);
    std::vector<io::Case> cases = family_cases();
    auto rep = report::build_report(cases, methods, [](const std::string& msg) { fmt::print(stderr, "[report] {}\n", msg); });
    rep.title = fmt::format("rayproof check: {} among the built-in methods", kernel->name);
    rep.highlight = kernel->name;
    rep.notes.push_back(fmt::format("kernel under test: {} ({} precision): {}", kernel->name,
                                    kernel->precision == Precision::float32 ? "float" : "double", kernel->summary));
    rep.notes.push_back(fmt::format("cases: {} families x {} (half built in float precision, half in double), seed {}",
                                    res.families.size(), o.count, o.seed));
    for (const auto& line : verify::check_sentences(res)) rep.notes.push_back(line);
    if (builds)
      for (const auto& line : verify::comparison_lines(*builds)) {
        if (line.rfind("# the first", 0) == 0) break;  // the examples: the report's reproducers are the check's own
        rep.notes.push_back(line);
      }
    // The reproducers are the check's own (its worst cases, minimized), not the comparison's first ones.
    rep.reproducers = verify::reproducer_lines(res);
    rep.reproducers_intro = fmt::format("The worst cases of {} per family, minimized where marked, and its failures: "
                                        "one case-file line each, the input as the kernel saw it.",
                                        kernel->name);
    if (auto err = report::write_report(rep, o.out); !err.empty()) {
      fmt::print(stderr, "rayproof check: {}\n", err);
      return 2;
    }
    if (auto err = report::write_html(o.out); !err.empty()) {
      fmt::print(stderr, "rayproof check: {}\n", err);
      return 2;
    }
    fmt::print(stderr, "wrote {0}/report.md, {0}/report.html, {0}/report.csv, {0}/error_vs_time.svg\n", o.out);
  }

  if (o.json) {
    auto j = result_json(res);
    j["summary"] = kernel->summary;
    if (is_glsl_kernel(*kernel)) j["kernel"] = kernel->summary;
    if (builds) {
      nlohmann::json ex = nlohmann::json::array();
      for (const auto& d : builds->examples)
        ex.push_back({{"case", io::format_case(d.input)}, {"device", io::format_answer(d.device)}, {"c", io::format_answer(d.c)},
                      {"uncontracted", d.uncontracted ? nlohmann::json(io::format_answer(*d.uncontracted)) : nlohmann::json()},
                      {"why", d.why}});
      j["compare_plugin"] = {{"plugin", o.compare_plugin}, {"c", builds->c}, {"cases", builds->cases},
                             {"failed", builds->failed}, {"differ", builds->differ}, {"differ_hit_miss", builds->differ_hit},
                             {"contraction", builds->contraction}, {"subnormal", builds->subnormal},
                             {"unexplained", builds->unexplained}, {"uncontracted_differ", builds->uncontracted_differ},
                             {"device_note", builds->device_note}, {"examples", ex},
                             {"sentences", verify::comparison_lines(*builds)}};
    }
    fmt::print("{}\n", j.dump(1));
  } else {
    fmt::print("rayproof check: kernel '{}' ({} precision); {} cases generated per family (half built in float "
               "precision, half in double), seed {}; the table counts those of the kinds the kernel answers\n\n",
               res.method, res.precision == Precision::float32 ? "float" : "double", o.count, o.seed);
    fmt::print("kernel '{}': {}\n\n", kernel->name, kernel->summary);
    fmt::print("{}", verify::check_table(res));
    const auto lines = verify::reproducer_lines(res);
    if (!lines.empty()) {
      fmt::print("\n# worst reproducers (up to {} per family): case-file lines, the input as the kernel saw it\n",
                 o.reproducers);
      for (const auto& l : lines) fmt::print("{}\n", l);
    }
    fmt::print("\n");
    for (const auto& s : verify::check_sentences(res)) fmt::print("{}\n", s);
    if (builds) {
      fmt::print("\n");
      for (const auto& l : verify::comparison_lines(*builds)) fmt::print("{}\n", l);
    }
  }
  return res.promises_kept() ? 0 : 1;
}
}  // namespace

Run add_check(CLI::App& app) {
  auto o = std::make_shared<CheckCliOptions>();
  auto* sub = app.add_subcommand("check", "Check one kernel (yours, or a built-in one) against exact on every family");
  add_user_kernel_options(*sub, o->user);
  sub->add_flag("--plugin-in-process", o->plugin_in_process,
                "Load --plugin into rayproof itself instead of a forked child (faster; a crash ends the check)");
  sub->add_option("--method", o->method, "Check this built-in method instead of a kernel of yours");
  sub->add_option("--count", o->count, "Cases per family (half built in float precision, half in double)")
      ->check(CLI::Range(std::size_t{2}, std::size_t{10000000}))
      ->capture_default_str();
  sub->add_option("--seed", o->seed, "Seed of the case families")->capture_default_str();
  sub->add_option("--families", o->families, "Families (default: every family of the kinds the kernel answers)")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_option("--expect", o->expect, "Promises that set the exit status: watertight, exact-class, no-false-negative")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_option("--max-ulps", o->max_ulps, "Promise: every class-correct t within N ulps (also the tolerance shown)")
      ->check(CLI::Range(std::uint64_t{0}, std::numeric_limits<std::uint64_t>::max() - 1));
  sub->add_option("--reproducers", o->reproducers, "Worst cases shown per family")
      ->check(CLI::Range(std::size_t{0}, std::size_t{1000}))
      ->capture_default_str();
  sub->add_option("--out", o->out,
                  "Write report.md, report.html, report.csv and error_vs_time.svg here (--caster, --contains, "
                  "--distance, --crossings: report.md and report.html)");
  sub->add_option("--compare", o->compare, "Built-in methods placed beside the kernel in the report (default: all)")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_option("--compare-plugin", o->compare_plugin,
                  "With --glsl or --opencl: the C build of the same formula (PATH.so, rayproof/plugin.h); says where "
                  "the device build answers differently and why where it can tell (FMA contraction, subnormals)");
  sub->add_flag("--json", o->json, "Print the result as JSON instead of the table");
  sub->add_option("--mesh", o->mesh,
                  "Leak check on closed meshes instead of the families: mesh files (.off .obj .ply .stl .gltf .glb), or "
                  "`generated` for the generated meshes of fuzz --mesh; leaks break the promise watertight")
      ->expected(1, -1);
  sub->add_option("--meshes", o->meshes, "How many generated meshes `--mesh generated` checks")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000}))
      ->capture_default_str();
  sub->add_option("--mesh-targets", o->mesh_targets, "Vertices and edge midpoints aimed at per mesh, evenly strided (0: all)")
      ->capture_default_str();
  sub->add_option("--interior", o->interior, "Interior points per mesh (rays start there)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  sub->add_option("--caster", o->caster,
                  "NAME=COMMAND: a whole caster (BVH and all) judged on --mesh: it reads the mesh, then batches of rays, "
                  "and answers `t triangle` per ray (docs/check.md); repeatable. With --out: report.md and report.html, "
                  "rayproof's own casters beside");
  sub->add_option("--caster-precision", o->caster_precision, "The caster's precision: float (float rays, t in float ulps) or double")
      ->capture_default_str();
  sub->add_option("--caster-timeout", o->caster_timeout, "Seconds the caster may take per answer line")->capture_default_str();
  sub->add_option("--caster-batch", o->caster_batch, "Rays per batch sent to the caster")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}))
      ->capture_default_str();
  sub->add_option("--caster-rays", o->caster_rays, "Random rays per mesh (the other sets follow the mesh)")->capture_default_str();
  sub->add_option("--caster-max-per-set", o->caster_max_per_set, "Rays per set at most (evenly subsampled)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000000}))
      ->capture_default_str();
  sub->add_option("--caster-sets", o->caster_sets, "Ray sets: leak, graze, face, surface, random, extreme, invalid (default: all)")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_option("--contains", o->contains,
                  "NAME=COMMAND: a containment function judged on --mesh: it reads the mesh, then batches of points, "
                  "and answers 0 (outside), 1 (inside) or 2 (surface) per point (docs/check.md); repeatable. With --out: "
                  "report.md and report.html, rayproof's own contains beside");
  sub->add_option("--contains-rule", o->contains_rule, "The rule the answers are judged by: automatic, nonzero, parity, winding")
      ->capture_default_str();
  sub->add_option("--contains-precision", o->contains_precision,
                  "The function's precision: float (points rounded to float, nudged by float ulps) or double")
      ->capture_default_str();
  sub->add_option("--contains-timeout", o->contains_timeout, "Seconds the function may take per answer line")
      ->capture_default_str();
  sub->add_option("--contains-batch", o->contains_batch, "Points per batch sent to the function")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}))
      ->capture_default_str();
  sub->add_option("--contains-points", o->contains_points, "Random points per mesh (the other sets follow the mesh)")
      ->capture_default_str();
  sub->add_option("--contains-max-per-set", o->contains_max_per_set, "Points per set at most (evenly subsampled)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000000}))
      ->capture_default_str();
  sub->add_option("--contains-sets", o->contains_sets,
                  "Point sets: vertex, edge, face, nudged, medial, thin, far, random, invalid (default: all)")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_option("--contains-scale", o->contains_scale,
                  "Judge on the mesh times this power of two, exactly (2^K, e.g. 2^600 or 2^-600, or a number such as "
                  "0.25); refused when a coordinate would overflow or become subnormal")
      ->capture_default_str();
  sub->add_option("--distance", o->distance,
                  "NAME=COMMAND: a distance function judged on --mesh: it reads the mesh, then batches of points, and "
                  "answers per point a distance, optionally its closest point and triangle (docs/check.md); "
                  "repeatable. With --out: report.md and report.html, rayproof's own distance beside");
  sub->add_flag("--distance-signed", o->distance_signed,
                "The function answers signed distances (negative inside, 0 on the surface)");
  sub->add_option("--distance-precision", o->distance_precision,
                  "The function's precision: float (the mesh and points rounded to float, float ulps) or double")
      ->capture_default_str();
  sub->add_option("--distance-rel-tol", o->distance_rel_tol,
                  "Relative error forgiven beyond 1 ulp (0: every answer more than 1 ulp off is a finding)")
      ->capture_default_str();
  sub->add_option("--distance-timeout", o->distance_timeout, "Seconds the function may take per answer line")
      ->capture_default_str();
  sub->add_option("--distance-batch", o->distance_batch, "Points per batch sent to the function")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1000000}))
      ->capture_default_str();
  sub->add_option("--distance-points", o->distance_points, "Random points per mesh (the other sets follow the mesh)")
      ->capture_default_str();
  sub->add_option("--distance-max-per-set", o->distance_max_per_set, "Points per set at most (evenly subsampled)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{100000000}))
      ->capture_default_str();
  sub->add_option("--distance-sets", o->distance_sets,
                  "Point sets: vertex, edge, face, nudged, medial, thin, far, random, invalid (default: all)")
      ->delimiter(',')->allow_extra_args(false);
  sub->add_option("--distance-scale", o->distance_scale,
                  "Judge on the mesh times this power of two, exactly (2^K, e.g. 2^600 or 2^-600, or a number such as "
                  "0.25); refused when a coordinate would overflow or become subnormal")
      ->capture_default_str();
  add_crossings_check_options(*sub, *o);
  return [o] { return run_check(*o); };
}

}  // namespace rayproof::cli
