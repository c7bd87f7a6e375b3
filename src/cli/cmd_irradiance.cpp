/// rayproof irradiance: Monte Carlo irradiance from a uniform disk light, rays cast through a
/// registered method's disk kernel, against a reference of stated accuracy (verify/radiometry.h).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <numbers>

#include "cli/commands.h"
#include "registry/registry.h"
#include "cli/user_kernels.h"
#include "light/irradiance_mc.h"
#include "report/irradiance_sweep.h"
#include "verify/radiometry.h"

namespace rayproof::cli {

namespace {

struct IrradianceOptions {
  double r = 1, h = 1, offset = 0, tilt_deg = 0, L = 1;
  std::vector<double> at{0, 0, 0};
  std::uint64_t samples = 100000;
  std::uint64_t seed = 1;
  std::vector<std::string> estimators;  ///< empty: cosine, or all for a sweep
  std::vector<std::string> methods;
  std::string bias_against = "certified";
  bool sweep = false;
  std::string out = "irradiance_sweep";
  int sweep_seeds = 4;
  std::uint64_t sweep_min = 256;
  UserKernelOptions user;
};

constexpr const char* kCmd = "rayproof irradiance";

std::string describe_reference(const verify::Reference& ref) {
  const double rel = ref.value != 0 ? ref.error_bound() / std::fabs(ref.value) : ref.error_bound();
  return fmt::format("{:.17g}, {} within [{:.17g}, {:.17g}] (width {:.2g}, {:.2g} relative): {}", ref.value,
                     ref.proven ? "proven" : "estimated", ref.lo, ref.hi, ref.error_bound(), rel, ref.method);
}

/// Methods by name (comma lists allowed), from the registry or the user's kernels.
std::optional<std::vector<const Method*>> resolve(const std::vector<std::string>& names,
                                                  const std::vector<std::unique_ptr<Method>>& user) {
  std::vector<const Method*> out;
  for (const auto& name : names) {
    const Method* m = nullptr;
    for (const auto& u : user)
      if (u->name == name) m = u.get();
    if (!m) m = registry::all_methods().find(name);
    if (!m) {
      fmt::print(stderr, "{}: unknown method '{}' (known: {})\n", kCmd, name, registry::all_methods().names());
      return std::nullopt;
    }
    if (!m->supports(io::Kind::disk)) {
      fmt::print(stderr, "{}: method '{}' does not answer disk cases\n", kCmd, name);
      return std::nullopt;
    }
    out.push_back(m);
  }
  return out;
}

/// What the paired difference against the reference method says, in words true for its numbers.
std::string bias_verdict(const light::MethodEstimate& pm, const light::MethodEstimate& ref) {
  if (pm.disagreements == 0) return "the same answer on every ray: no kernel bias in this run";
  if (pm.diff_std_error == 0 && pm.diff_mean != 0)
    return "BIASED: the difference has no spread (every sample differs by the same amount)";
  const double z = pm.diff_std_error > 0 ? pm.diff_mean / pm.diff_std_error : 0;
  const std::string size =
      ref.std_error > 0 ? fmt::format("{:.3g} times the standard error of {}'s estimate", std::fabs(pm.diff_mean) / ref.std_error,
                                      ref.method->name)
                        : std::string("the reference method's estimate has no spread");
  if (std::fabs(z) > 4) return fmt::format("BIASED beyond 4 standard errors of the difference ({:+.1f}); the bias is {}", z, size);
  return fmt::format("not significant at 4 standard errors of the difference ({:+.1f}); its size is {}", z, size);
}

int run_single(const IrradianceOptions& opt, const light::DiskLightSetup& setup, const verify::Reference& ref,
               const std::vector<light::Estimator>& estimators, const std::vector<const Method*>& methods,
               const Method* bias_ref) {
  for (light::Estimator est : estimators) {
    std::vector<const Method*> run_methods;
    if (bias_ref) run_methods.push_back(bias_ref);
    for (const Method* m : methods)
      if (m != bias_ref) run_methods.push_back(m);
    const light::EstimateRun run = light::estimate_irradiance(setup, est, run_methods, opt.samples, opt.seed);
    fmt::print("\nestimator {}: {} samples, seed {}, {} rays per method", light::to_string(est), run.samples, opt.seed,
               run.rays);
    if (est == light::Estimator::solid_angle) fmt::print(", cone of {:.6g} sr", run.sampled_solid_angle);
    fmt::print("\n{:<16} {:>20} {:>11} {:>12} {:>9} {:>10} {:>9}\n", "method", "estimate", "std.error", "error",
               "error/SE", "hits", "Mrays/s*");
    for (const auto& pm : run.per_method) {
      const bool shown = std::find(methods.begin(), methods.end(), pm.method) != methods.end();
      if (!shown) continue;
      const double err = pm.mean - ref.value;
      // With no spread (no hits, or a constant contribution) error/SE is undefined unless the error is 0.
      const std::string z = pm.std_error > 0 ? fmt::format("{:.2f}", err / pm.std_error) : err == 0 ? "0" : "no SE";
      fmt::print("{:<16} {:>20.15g} {:>11.3g} {:>12.3g} {:>9} {:>10} {:>9.2f}\n", pm.method->name, pm.mean,
                 pm.std_error, err, z, pm.hits,
                 pm.seconds > 0 ? static_cast<double>(run.rays) / pm.seconds * 1e-6 : 0.0);
    }
    fmt::print("(* rays per second of wall time, sampling included)\n");
    if (bias_ref && run.per_method.size() > 1) {
      fmt::print("kernel bias, paired against {} on the same rays (mean of f_method - f_{}):\n", bias_ref->name,
                 bias_ref->name);
      for (const auto& pm : run.per_method) {
        if (pm.method == bias_ref) continue;
        fmt::print("  {:<16} {} rays differ; difference {:.3g} +- {:.3g}: {}\n", pm.method->name, pm.disagreements,
                   pm.diff_mean, pm.diff_std_error, bias_verdict(pm, run.per_method.front()));
      }
    }
  }
  return 0;
}

int run_sweep(const IrradianceOptions& opt, const light::DiskLightSetup& setup,
              const std::vector<light::Estimator>& estimators, const std::vector<const Method*>& methods) {
  std::vector<std::uint64_t> counts;
  for (std::uint64_t n = opt.sweep_min; n <= opt.samples; n *= 4) counts.push_back(n);
  if (counts.empty()) counts.push_back(opt.samples);
  const auto sw = report::run_irradiance_sweep(setup, estimators, methods, counts, opt.sweep_seeds, opt.seed,
                                               [](const std::string& msg) { fmt::print(stderr, "{}: {}\n", kCmd, msg); });
  std::error_code ec;
  std::filesystem::create_directories(opt.out, ec);
  const auto svg_path = std::filesystem::path(opt.out) / "irradiance_sweep.svg";
  const auto csv_path = std::filesystem::path(opt.out) / "irradiance_sweep.csv";
  const std::string title = fmt::format("Irradiance: {}; RMS over {} seeds", report::describe_setup(setup), opt.sweep_seeds);
  for (const auto& [path, text] : {std::pair{svg_path, report::sweep_svg(sw.series, title)}, std::pair{csv_path, sw.csv}}) {
    std::ofstream f(path, std::ios::binary);
    f << text;
    if (!f) {
      fmt::print(stderr, "{}: cannot write {}\n", kCmd, path.string());
      return 2;
    }
  }
  fmt::print("wrote {} and {}\n", svg_path.string(), csv_path.string());
  fmt::print("{:<12} {:<16} {:>8} {:>12} {:>12} {:>11} {:>14}\n", "estimator", "method", "N", "RMS error", "mean SE",
             "slope vs N", "us/estimate");
  for (const auto& s : sw.series) {
    const auto& p = s.points.back();
    fmt::print("{:<12} {:<16} {:>8} {:>12.3g} {:>12.3g} {:>11.2f} {:>14.0f}\n", s.estimator, s.method, p.samples,
               p.rms_error, p.mean_std_error, report::fitted_slope(s), p.seconds * 1e6);
  }
  return 0;
}

int run_irradiance(const IrradianceOptions& opt) {
  light::DiskLightSetup setup;
  setup.r = opt.r, setup.h = opt.h, setup.offset = opt.offset, setup.L = opt.L;
  setup.tilt = opt.tilt_deg * std::numbers::pi / 180;
  if (opt.at.size() != 3) {
    fmt::print(stderr, "{}: --at needs three numbers X,Y,Z\n", kCmd);
    return 2;
  }
  setup.at = {opt.at[0], opt.at[1], opt.at[2]};
  if (const std::string bad = light::check_setup(setup); !bad.empty()) {
    fmt::print(stderr, "{}: {}\n", kCmd, bad);
    return 2;
  }
  if (opt.samples == 0 || opt.samples > (std::uint64_t{1} << 36)) {
    fmt::print(stderr, "{}: --samples must be in 1..2^36\n", kCmd);
    return 2;
  }
  if (opt.sweep_min < 1 || opt.sweep_min > (std::uint64_t{1} << 36)) {
    fmt::print(stderr, "{}: --sweep-min must be in 1..2^36\n", kCmd);
    return 2;
  }
  if (opt.sweep_seeds < 1 || opt.sweep_seeds > 1000) {
    fmt::print(stderr, "{}: --sweep-seeds must be in 1..1000\n", kCmd);
    return 2;
  }
  std::vector<light::Estimator> estimators;
  std::vector<std::string> estimator_names = opt.estimators;
  if (estimator_names.empty()) estimator_names.push_back(opt.sweep ? "all" : "cosine");
  for (const auto& name : estimator_names) {
    if (name == "all") {
      estimators.assign(light::kAllEstimators.begin(), light::kAllEstimators.end());
      continue;
    }
    const auto e = light::estimator_from_string(name);
    if (!e) {
      fmt::print(stderr, "{}: unknown estimator '{}' (known: hemisphere, cosine, area, solid-angle, all)\n", kCmd, name);
      return 2;
    }
    estimators.push_back(*e);
  }
  auto user = make_user_kernels("irradiance", opt.user);
  if (!user) return 2;
  std::vector<std::string> names = opt.methods;
  if (names.empty()) {
    if (opt.sweep) {
      for (const auto& m : registry::all_methods().all())
        if (m.name != "exact" && m.supports(io::Kind::disk)) names.push_back(m.name);
    } else {
      names.push_back("double");
    }
    for (const auto& u : *user) names.push_back(u->name);
  }
  const auto methods = resolve(names, *user);
  if (!methods) return 2;
  const Method* bias_ref = nullptr;
  if (!opt.bias_against.empty() && opt.bias_against != "none") {
    const auto b = resolve({opt.bias_against}, *user);
    if (!b) return 2;
    bias_ref = b->front();
  }

  const verify::Reference ref = verify::irradiance_reference(setup.r, setup.h, setup.offset, setup.tilt, setup.L);
  fmt::print("disk light: r = {:g}, h = {:g}, lateral offset = {:g}, L = {:g}; receiver at ({:g}, {:g}, {:g}) tilted {:g} deg\n",
             setup.r, setup.h, setup.offset, setup.L, setup.at.x, setup.at.y, setup.at.z, opt.tilt_deg);
  fmt::print("reference E = {}\n", describe_reference(ref));
  const verify::Reference omega = verify::disk_solid_angle(setup.r, setup.h, setup.offset);
  fmt::print("disk solid angle = {}\n", describe_reference(omega));
  if (opt.sweep) return run_sweep(opt, setup, estimators, *methods);
  return run_single(opt, setup, ref, estimators, *methods, bias_ref);
}

}  // namespace

Run add_irradiance(CLI::App& app) {
  auto opt = std::make_shared<IrradianceOptions>();
  auto* sub = app.add_subcommand(
      "irradiance", "Monte Carlo irradiance from a uniform disk light through a method's disk kernel, against its reference");
  sub->add_option("--r", opt->r, "Disk radius")->capture_default_str();
  sub->add_option("--h", opt->h, "Height of the disk's plane above the receiver (> 0)")->capture_default_str();
  sub->add_option("--offset", opt->offset, "Lateral offset of the disk's centre from the receiver's vertical (along x)")
      ->capture_default_str();
  sub->add_option("--tilt", opt->tilt_deg, "Tilt of the receiver's normal toward +x, degrees")->capture_default_str();
  sub->add_option("--L", opt->L, "Radiance of the disk")->capture_default_str();
  sub->add_option("--at", opt->at, "Receiver position X,Y,Z (the whole setup is translated)")->delimiter(',')
      ->expected(3);
  sub->add_option("--samples,-n", opt->samples, "Samples per estimate (the largest count of a sweep)")->capture_default_str();
  sub->add_option("--seed", opt->seed, "Seed (a sweep uses SEED..SEED+K-1)")->capture_default_str();
  sub->add_option("--estimator,-e", opt->estimators, "hemisphere, cosine, area, solid-angle or all; comma list (default: cosine; a sweep: all)")
      ->delimiter(',');
  sub->add_option("--method,-m", opt->methods,
                  "Methods casting the rays, comma list (default: double; a sweep: every method answering disks but exact)")
      ->delimiter(',');
  sub->add_option("--bias-against", opt->bias_against,
                  "Method answering the same rays for the paired bias estimate (none to skip)")->capture_default_str();
  sub->add_flag("--sweep", opt->sweep, "Error against sample count and time for every estimator x method: SVG and CSV");
  sub->add_option("--out", opt->out, "Directory for the sweep's files")->capture_default_str();
  sub->add_option("--sweep-seeds", opt->sweep_seeds, "Seeds per point of the sweep (RMS error over them)")->capture_default_str();
  sub->add_option("--sweep-min", opt->sweep_min, "Smallest sample count of the sweep (counts grow by 4)")->capture_default_str();
  add_user_kernel_options(*sub, opt->user);
  return [opt] { return run_irradiance(*opt); };
}

}  // namespace rayproof::cli
