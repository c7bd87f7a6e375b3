#include "report/irradiance_sweep.h"

#include "light/spawn_count.h"

#include <fmt/core.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <array>

namespace rayproof::report {

IrradianceSweep run_irradiance_sweep(const light::DiskLightSetup& setup, std::span<const light::Estimator> estimators,
                                     std::span<const Method* const> methods, std::span<const std::uint64_t> counts,
                                     int seeds, std::uint64_t seed,
                                     const std::function<void(const std::string&)>& progress) {
  IrradianceSweep sw;
  sw.setup = setup;
  sw.seeds = seeds;
  sw.reference = verify::irradiance_reference(setup.r, setup.h, setup.offset, setup.tilt, setup.L);
  const double ref = sw.reference.value;
  sw.csv = "estimator,method,samples,seeds,rms_error,mean_std_error,seconds_per_estimate,mean_estimate,reference\n";
  for (light::Estimator est : estimators) {
    const std::size_t first = sw.series.size();
    for (const Method* m : methods) sw.series.push_back({std::string(light::to_string(est)), m->name, {}});
    for (std::uint64_t n : counts) {
      std::vector<double> sq(methods.size()), se(methods.size()), sec(methods.size()), mean(methods.size());
      for (int k = 0; k < seeds; ++k) {
        const auto run = light::estimate_irradiance(setup, est, methods, n, seed + static_cast<std::uint64_t>(k));
        for (std::size_t i = 0; i < methods.size(); ++i) {
          const auto& pm = run.per_method[i];
          sq[i] += (pm.mean - ref) * (pm.mean - ref);
          se[i] += pm.std_error;
          sec[i] += pm.seconds;
          mean[i] += pm.mean;
        }
      }
      const double K = seeds;
      for (std::size_t i = 0; i < methods.size(); ++i) {
        const SweepPoint p{n, sec[i] / K, std::sqrt(sq[i] / K), se[i] / K};
        sw.series[first + i].points.push_back(p);
        sw.csv += fmt::format("{},{},{},{},{:.17g},{:.17g},{:.6g},{:.17g},{:.17g}\n", light::to_string(est),
                              methods[i]->name, n, seeds, p.rms_error, p.mean_std_error, p.seconds, mean[i] / K, ref);
      }
      if (progress) progress(fmt::format("irradiance sweep: {} N = {} done", light::to_string(est), n));
    }
  }
  return sw;
}

double fitted_slope(const SweepSeries& s) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (const auto& p : s.points)
    if (p.rms_error > 0) {
      const double x = std::log10(static_cast<double>(p.samples)), y = std::log10(p.rms_error);
      sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
    }
  return n > 1 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : 0;
}

std::string describe_setup(const light::DiskLightSetup& s) {
  return fmt::format("disk r = {:g} at height h = {:g}, lateral offset {:g}, L = {:g}; receiver at ({:g}, {:g}, {:g}) tilted {:g} deg",
                     s.r, s.h, s.offset, s.L, s.at.x, s.at.y, s.at.z, s.tilt * 180 / std::numbers::pi);
}

std::string sweep_table_markdown(const IrradianceSweep& sw) {
  std::string s = "| estimator | method | N | RMS error | mean std. error | slope of log error vs log N | us per estimate |\n"
                  "|---|---|---:|---:|---:|---:|---:|\n";
  for (const auto& se : sw.series) {
    if (se.points.empty()) continue;
    const auto& p = se.points.back();
    s += fmt::format("| {} | {} | {} | {:.3g} | {:.3g} | {:.2f} | {:.0f} |\n", se.estimator, se.method, p.samples,
                     p.rms_error, p.mean_std_error, fitted_slope(se), p.seconds * 1e6);
  }
  return s;
}

std::string bias_table_markdown(const light::DiskLightSetup& setup, std::span<const light::Estimator> estimators,
                                const Method* reference_method, std::span<const Method* const> methods,
                                std::uint64_t samples, std::uint64_t seed) {
  std::vector<const Method*> all{reference_method};
  for (const Method* m : methods)
    if (m != reference_method) all.push_back(m);
  std::string s = fmt::format("| estimator | method | rays | rays answered unlike {0} | mean of f - f_{0} | its std. error | "
                              "in its std. errors | in std. errors of {0}'s estimate |\n|---|---|---:|---:|---:|---:|---:|---:|\n",
                              reference_method->name);
  for (light::Estimator est : estimators) {
    const auto run = light::estimate_irradiance(setup, est, all, samples, seed);
    const auto& ref = run.per_method.front();
    for (std::size_t i = 1; i < run.per_method.size(); ++i) {
      const auto& pm = run.per_method[i];
      const double z = pm.diff_std_error > 0 ? pm.diff_mean / pm.diff_std_error : 0;
      const std::string of_ref = ref.std_error > 0 ? fmt::format("{:+.3g}", pm.diff_mean / ref.std_error)
                                 : pm.diff_mean == 0 ? std::string("0") : std::string("n/a (no spread)");
      const std::string zs = pm.diff_std_error == 0 && pm.diff_mean != 0 ? std::string("**biased** (no spread)")
                             : fmt::format("{}{:+.1f}", std::fabs(z) > 4 ? "**biased** " : "", z);
      s += fmt::format("| {} | {} | {} | {} | {:.3g} | {:.3g} | {} | {} |\n", light::to_string(est), pm.method->name,
                       run.rays, pm.disagreements, pm.diff_mean, pm.diff_std_error, zs, of_ref);
    }
  }
  return s;
}

std::string write_irradiance_section(const std::string& dir, std::span<const Method* const> methods,
                                     const Method* bias_reference, std::uint64_t max_samples, std::uint64_t seed,
                                     const std::function<void(const std::string&)>& progress) {
  std::vector<const Method*> disk_methods;
  for (const Method* m : methods)
    if (m->supports(io::Kind::disk)) disk_methods.push_back(m);
  if (disk_methods.empty() || max_samples == 0) return "";
  light::DiskLightSetup moderate;
  moderate.r = 1, moderate.h = 1, moderate.offset = 1.5, moderate.tilt = 30 * std::numbers::pi / 180;
  std::vector<std::uint64_t> counts;
  for (std::uint64_t n = 256; n <= max_samples; n *= 4) counts.push_back(n);
  if (counts.empty()) counts.push_back(max_samples);
  constexpr int kSeeds = 4;
  const auto sw = run_irradiance_sweep(moderate, light::kAllEstimators, disk_methods, counts, kSeeds, seed, progress);
  const std::string title = fmt::format("Irradiance: {}; RMS over {} seeds", describe_setup(moderate), kSeeds);

  std::string md = "\n## Irradiance from a disk light: Monte Carlo error against samples and time\n\n";
  md += fmt::format("Setup: {}. Reference E = {:.17g} ({}, {} to {:.2g}). Every estimator casts its rays through each "
                    "method's ray/disk kernel; RMS error over {} seeds (seeds {}..{}); an unbiased estimator's error "
                    "falls as N^-1/2 (slope -0.5). `rayproof irradiance --help` for one configuration.\n\n",
                    describe_setup(moderate), sw.reference.value, sw.reference.method,
                    sw.reference.proven ? "proven" : "estimated", sw.reference.error_bound(), kSeeds, seed,
                    seed + kSeeds - 1);
  md += "![irradiance error against samples and time](irradiance_sweep.svg)\n\n";
  md += sweep_table_markdown(sw);
  if (bias_reference) {
    light::DiskLightSetup far;
    far.r = 0.01, far.h = 100, far.offset = 3, far.at = {1000, -700, 300};
    const std::uint64_t n = 4 * max_samples;
    const std::array<light::Estimator, 2> aimed{light::Estimator::area, light::Estimator::solid_angle};
    md += fmt::format("\nKernel bias where the disk is small and far ({}): each method against {} on the same {} "
                      "samples (seed {}); the mean per-sample difference of contributions is a paired estimate of the "
                      "bias the kernel adds. The hemisphere estimators are left out: they almost never hit a disk of "
                      "{:.3g} sr.\n\n",
                      describe_setup(far), bias_reference->name, n, seed,
                      verify::disk_solid_angle(far.r, far.h, far.offset).value);
    if (progress) progress("irradiance: kernel bias on a far, small disk");
    md += bias_table_markdown(far, aimed, bias_reference, disk_methods, n, seed);
  }
  if (bias_reference) {
    // Secondary rays: self-intersections per spawn strategy (rayproof spawn for more).
    constexpr std::uint64_t kTrials = 1000;
    constexpr double kEpsilon = 1e-4;
    md += fmt::format("\n## Secondary rays: self-intersections per spawn strategy\n\n"
                      "{} primary rays per kind, magnitude and method hit a plane, sphere or disk placed at coordinates "
                      "up to 2^k; from each computed hit point a reflection ray and a shadow ray leave to the side the "
                      "primary ray came from, so any contact with the same primitive at t > 0 is a self-intersection. "
                      "Counted by the method's own kernel and by {} on the same spawned rays; fixed epsilon = {:g}; "
                      "`misses`: primary rays the method's kernel did not see hit (float inputs at large magnitudes). "
                      "The certified strategy's origins sit within ulps of the surface and a renderer using it tests the "
                      "primitive it leaves with the exact classifier, so its exact count is the one that applies; its own-kernel "
                      "count shows what a fast kernel would see there instead. `rayproof spawn` reproduces these (seed {}).\n\n"
                      "| kind | 2^k | method | spawned | misses | none: own / exact | fixed epsilon: own / exact | "
                      "error-bounded: own / exact | certified: own / exact |\n|---|---:|---|---:|---:|---:|---:|---:|---:|\n",
                      kTrials, bias_reference->name, kEpsilon, seed);
    for (io::Kind kind : {io::Kind::plane, io::Kind::sphere, io::Kind::disk}) {
      std::vector<const Method*> ms;
      for (const Method* m : methods)
        if (m->supports(kind) && m->name != "exact") ms.push_back(m);
      if (ms.empty()) continue;
      for (int mag : {0, 20, 40}) {
        if (progress) progress(fmt::format("spawn counts: {} at 2^{}", io::to_string(kind), mag));
        const auto rows = light::count_self_intersections(kind, ms, *bias_reference, kTrials, seed, mag, kEpsilon);
        for (std::size_t i = 0; i + 3 < rows.size(); i += 4)
          md += fmt::format("| {} | {} | {} | {} | {} | {} / {} | {} / {} | {} / {} | {} / {} |\n", io::to_string(kind), mag,
                            rows[i].method->name, rows[i].spawned, rows[i].primary_misses, rows[i].self_hits,
                            rows[i].exact_self_hits, rows[i + 1].self_hits, rows[i + 1].exact_self_hits,
                            rows[i + 2].self_hits, rows[i + 2].exact_self_hits, rows[i + 3].self_hits,
                            rows[i + 3].exact_self_hits);
      }
    }
  }
  if (bias_reference) {
    constexpr std::uint64_t kTrials = 1000;
    std::vector<const Method*> ms;
    for (const Method* m : disk_methods)
      if (m->name != "exact") ms.push_back(m);
    md += fmt::format("\nLeaks through a thin slab: two parallel disks 1e-6 x 2^k apart; a shadow ray leaves the top "
                      "disk's hit point toward a light below the bottom disk, which must block it. Leaks counted by the "
                      "method's kernel / by {} ({} rays each, seed {}; `rayproof spawn --slab-gap 1e-6`).\n\n"
                      "| 2^k | method | shadow rays | misses | none | fixed epsilon | error-bounded | certified |\n"
                      "|---:|---|---:|---:|---:|---:|---:|---:|\n",
                      bias_reference->name, kTrials, seed);
    for (int mag : {0, 20}) {
      if (progress) progress(fmt::format("slab leaks at 2^{}", mag));
      const auto rows = light::count_slab_leaks(ms, *bias_reference, kTrials, seed, mag, 1e-6 * std::ldexp(1.0, mag), 1e-4);
      for (std::size_t i = 0; i + 3 < rows.size(); i += 4)
        md += fmt::format("| {} | {} | {} | {} | {} / {} | {} / {} | {} / {} | {} / {} |\n", mag, rows[i].method->name,
                          rows[i].spawned, rows[i].primary_misses, rows[i].self_hits, rows[i].exact_self_hits,
                          rows[i + 1].self_hits, rows[i + 1].exact_self_hits, rows[i + 2].self_hits,
                          rows[i + 2].exact_self_hits, rows[i + 3].self_hits, rows[i + 3].exact_self_hits);
    }
  }
  const std::pair<const char*, std::string> files[] = {{"irradiance_sweep.svg", sweep_svg(sw.series, title)},
                                                       {"irradiance_sweep.csv", sw.csv}};
  for (const auto& [name, text] : files) {
    const auto path = std::filesystem::path(dir) / name;
    std::ofstream out(path, std::ios::binary);
    out << text;
    if (!out) return path.string() + ": cannot write";
  }
  const auto md_path = std::filesystem::path(dir) / "report.md";
  std::ofstream out(md_path, std::ios::binary | std::ios::app);
  out << md;
  if (!out) return md_path.string() + ": cannot append";
  return "";
}

}  // namespace rayproof::report
