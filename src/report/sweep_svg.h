#pragma once
/// The irradiance sweep's chart: Monte Carlo error against sample count and against run time,
/// log-log, one line per estimator x method, with the N^-1/2 slope an unbiased estimator follows.
#include <cstdint>
#include <string>
#include <vector>

namespace rayproof::report {

struct SweepPoint {
  std::uint64_t samples = 0;
  double seconds = 0;    ///< mean run time of one estimate
  double rms_error = 0;  ///< root mean square of (estimate - reference) over the seeds
  double mean_std_error = 0;
};

struct SweepSeries {
  std::string estimator, method;
  std::vector<SweepPoint> points;  ///< by increasing samples
};

/// Two panels (error against samples, error against seconds); colour by estimator, dash by method.
[[nodiscard]] std::string sweep_svg(const std::vector<SweepSeries>& series, const std::string& title);

}  // namespace rayproof::report
