#pragma once
/// Monte Carlo irradiance error against sample count and time, every estimator x method, for
/// `rayproof irradiance --sweep` and the irradiance section of `rayproof report`.
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "light/irradiance_mc.h"
#include "report/sweep_svg.h"
#include "verify/radiometry.h"

namespace rayproof::report {

struct IrradianceSweep {
  light::DiskLightSetup setup;
  verify::Reference reference;
  int seeds = 0;
  std::vector<SweepSeries> series;  ///< estimator-major, methods in the order given
  std::string csv;
};

/// For each estimator and count, `seeds` estimates (seeds seed..seed+seeds-1), all methods on the
/// same rays; RMS error against the reference, mean standard error and mean run time per point.
[[nodiscard]] IrradianceSweep run_irradiance_sweep(const light::DiskLightSetup& setup,
                                                   std::span<const light::Estimator> estimators,
                                                   std::span<const Method* const> methods,
                                                   std::span<const std::uint64_t> counts, int seeds, std::uint64_t seed,
                                                   const std::function<void(const std::string&)>& progress);

/// Least-squares slope of log RMS error against log N (about -0.5 for an unbiased estimator).
[[nodiscard]] double fitted_slope(const SweepSeries& s);

/// One line describing the setup (for titles and notes).
[[nodiscard]] std::string describe_setup(const light::DiskLightSetup& s);

/// A markdown table: estimator, method, RMS error and standard error at the largest N, slope,
/// microseconds per estimate at the largest N.
[[nodiscard]] std::string sweep_table_markdown(const IrradianceSweep& sw);

/// The kernel bias of each method against `reference_method` on the same rays (paired difference),
/// one markdown table row per estimator x method.
[[nodiscard]] std::string bias_table_markdown(const light::DiskLightSetup& setup,
                                              std::span<const light::Estimator> estimators,
                                              const Method* reference_method, std::span<const Method* const> methods,
                                              std::uint64_t samples, std::uint64_t seed);

/// The irradiance section of `rayproof report`: a sweep (256 .. max_samples by 4, four seeds) of
/// every estimator x method (those answering disks) on a tilted, off-axis receiver, written as
/// DIR/irradiance_sweep.svg and .csv, and a kernel-bias table on a small, far disk seen from far
/// from the origin, against `bias_reference`; then self-intersection counts per spawn strategy
/// (light/spawn_count.h) with `bias_reference` as the exact judge; all appended to DIR/report.md.
/// Returns an error message or "".
[[nodiscard]] std::string write_irradiance_section(const std::string& dir, std::span<const Method* const> methods,
                                                   const Method* bias_reference, std::uint64_t max_samples,
                                                   std::uint64_t seed,
                                                   const std::function<void(const std::string&)>& progress);

}  // namespace rayproof::report
