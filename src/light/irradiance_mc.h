#pragma once
/// Monte Carlo estimators of the irradiance from a uniform disk light, casting real rays through a
/// registered method's ray/disk kernel (Method::classify_many on `disk` cases), so that what the
/// kernel gets wrong shows in the estimate.
///
/// Geometry (the same as verify/radiometry.h, translated by `at`): the receiver point is `at` with
/// unit normal n = (sin tilt, 0, cos tilt); the disk light has centre at + (offset, 0, h), h > 0,
/// normal (0, 0, -1), radius r, and emits radiance L from its lower face.
///
/// Estimators (each sample's contribution f, E = mean of f):
/// - hemisphere: directions uniform on n's hemisphere (pdf 1 / 2pi): f = 2 pi L cos theta on a hit;
/// - cosine: directions with pdf cos theta / pi (Malley's method): f = pi L on a hit;
/// - area: points y uniform on the disk (pdf 1 / (pi r^2)), the ray aimed at y (direction y - at):
///   f = pi r^2 L cos theta cos theta' / |y - at|^2 on a hit (change of variables dw = cos theta' dA / d^2);
/// - solid-angle: directions uniform in the cone around the disk's bounding sphere (pdf
///   1 / (2 pi (1 - cos theta_max)); when `at` is inside that sphere, the hemisphere toward the
///   disk's plane): f = L cos theta / pdf on
///   a hit, 0 on a miss. This is the cone sampling of sphere lights (P. Shirley, C. Wang,
///   K. Zimmerman, "Monte Carlo techniques for direct lighting calculations", ACM TOG 15(1), 1996),
///   used as a solid-angle sampler for the disk; not the exact spherical-ellipse sampling of
///   Guillen et al. 2017 (its variance is higher by about the ratio of the cone's solid angle,
///   `sampled_solid_angle`, to the disk's).
/// Every estimator is unbiased when the kernel answers exactly. Deterministic by seed.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "methods/method.h"
#include "rayproof/vec3.h"

namespace rayproof::light {

struct DiskLightSetup {
  double r = 1, h = 1, offset = 0;
  double tilt = 0;  ///< radians, about the y axis
  double L = 1;
  Vec3<double> at{};
};

/// An empty string when the setup is usable, else what is wrong with it.
[[nodiscard]] std::string check_setup(const DiskLightSetup& s);

enum class Estimator : unsigned char { hemisphere, cosine, area, solid_angle };
inline constexpr std::array<Estimator, 4> kAllEstimators = {Estimator::hemisphere, Estimator::cosine, Estimator::area,
                                                            Estimator::solid_angle};
[[nodiscard]] std::string_view to_string(Estimator e);
[[nodiscard]] std::optional<Estimator> estimator_from_string(std::string_view s);

/// One method's estimate over the run's samples.
struct MethodEstimate {
  const Method* method = nullptr;
  double mean = 0, std_error = 0;
  std::uint64_t hits = 0;
  double seconds = 0;  ///< sampling plus this method's kernel time
  /// Against the run's first method on the same rays: the mean of the per-sample differences
  /// f_this - f_first and its standard error (a paired estimate of the bias between the two), and
  /// the number of rays whose hit or miss differs.
  double diff_mean = 0, diff_std_error = 0;
  std::uint64_t disagreements = 0;
};

struct EstimateRun {
  Estimator estimator = Estimator::cosine;
  std::uint64_t samples = 0;
  std::uint64_t rays = 0;  ///< rays cast per method (area sampling skips points below the horizon)
  double sampled_solid_angle = 0;  ///< solid angle the directions are drawn from (2 pi for the hemispheres)
  std::vector<MethodEstimate> per_method;
};

/// Runs `samples` samples of `est` and answers every ray with each of `methods` (all of them on the
/// same rays). Throws std::invalid_argument on a bad setup, no method or a method without disks.
[[nodiscard]] EstimateRun estimate_irradiance(const DiskLightSetup& setup, Estimator est,
                                              std::span<const Method* const> methods, std::uint64_t samples,
                                              std::uint64_t seed);

}  // namespace rayproof::light
