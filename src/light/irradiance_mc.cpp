#include "light/irradiance_mc.h"

#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "gen/rng.h"

namespace rayproof::light {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr std::size_t kBatch = 4096;

/// Running mean and variance (Welford).
struct Welford {
  std::uint64_t n = 0;
  double mean = 0, m2 = 0;
  void add(double x) {
    ++n;
    const double d = x - mean;
    mean += d / static_cast<double>(n);
    m2 += d * (x - mean);
  }
  [[nodiscard]] double std_error() const {
    return n > 1 ? std::sqrt(m2 / static_cast<double>(n - 1) / static_cast<double>(n)) : 0.0;
  }
};

/// Orthonormal basis around a unit vector (T. Duff et al., "Building an orthonormal basis,
/// revisited", JCGT 6(1), 2017).
struct Frame {
  Vec3<double> s, t, n;
  explicit Frame(Vec3<double> w) : n(w) {
    const double sign = std::copysign(1.0, w.z);
    const double a = -1.0 / (sign + w.z);
    const double b = w.x * w.y * a;
    s = {1.0 + sign * w.x * w.x * a, sign * b, -sign * w.x};
    t = {b, sign + w.y * w.y * a, -w.y};
  }
  [[nodiscard]] Vec3<double> to_world(double x, double y, double z) const { return x * s + y * t + z * n; }
};

bool is_hit(const io::CaseResult& res) {
  if (res.contact != Contact::hit && res.contact != Contact::rim) return false;
  return !res.t || *res.t > 0;
}

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

}  // namespace

std::string check_setup(const DiskLightSetup& s) {
  if (!(std::isfinite(s.r) && s.r > 0)) return "the disk radius r must be finite and > 0";
  if (!(std::isfinite(s.h) && s.h > 0)) return "the height h must be finite and > 0 (the receiver is below the light)";
  if (!std::isfinite(s.offset)) return "the lateral offset must be finite";
  if (!(std::isfinite(s.tilt) && std::fabs(s.tilt) <= kPi * (1 + 1e-12))) return "the tilt must be within [-180, 180] degrees";
  if (!(std::isfinite(s.L) && s.L >= 0)) return "the radiance L must be finite and >= 0";
  if (!all_finite(s.at)) return "the receiver position must be finite";
  // Squares and products of the sizes must stay normal doubles.
  constexpr double kMax = 1e100, kMin = 1e-100;
  if (s.r > kMax || s.r < kMin || s.h > kMax || s.h < kMin) return "r and h must be within [1e-100, 1e100]";
  if (std::fabs(s.offset) > kMax || std::fabs(s.at.x) > kMax || std::fabs(s.at.y) > kMax || std::fabs(s.at.z) > kMax ||
      s.L > kMax)
    return "the offset, the receiver position and L must be at most 1e100 in magnitude";
  return {};
}

std::string_view to_string(Estimator e) {
  switch (e) {
    case Estimator::hemisphere: return "hemisphere";
    case Estimator::cosine: return "cosine";
    case Estimator::area: return "area";
    case Estimator::solid_angle: return "solid-angle";
  }
  return "?";
}

std::optional<Estimator> estimator_from_string(std::string_view s) {
  for (Estimator e : kAllEstimators)
    if (to_string(e) == s) return e;
  return std::nullopt;
}

EstimateRun estimate_irradiance(const DiskLightSetup& setup, Estimator est, std::span<const Method* const> methods,
                                std::uint64_t samples, std::uint64_t seed) {
  if (const std::string bad = check_setup(setup); !bad.empty()) throw std::invalid_argument(bad);
  if (methods.empty()) throw std::invalid_argument("no method to cast the rays with");
  for (const Method* m : methods)
    if (!m || !m->supports(io::Kind::disk)) throw std::invalid_argument("method '" + (m ? m->name : std::string("?")) + "' does not answer disk cases");

  const Vec3<double> n{std::sin(setup.tilt), 0, std::cos(setup.tilt)};
  const Vec3<double> rel{setup.offset, 0, setup.h};  // disk centre - receiver
  const Vec3<double> centre = setup.at + rel;
  const Frame around_n(n);
  // Solid-angle sampling: the cone around the disk's bounding sphere (centre, r).
  const double dist = length(rel);
  // Inside the bounding sphere, the hemisphere above the receiver's height (toward the disk's
  // plane, which lies wholly at z > 0 relative to it) contains the disk instead.
  double k = 1;  // 1 - cos theta_max
  Vec3<double> axis{0, 0, 1};
  if (dist > setup.r) {
    const double s2 = (setup.r / dist) * (setup.r / dist);
    k = s2 / (1 + std::sqrt(1 - s2));
    axis = rel / dist;
  }
  const Frame around_axis(axis);
  const double disk_area = kPi * setup.r * setup.r;

  EstimateRun run;
  run.estimator = est;
  run.samples = samples;
  run.sampled_solid_angle = est == Estimator::solid_angle ? 2 * kPi * k : 2 * kPi;
  std::vector<Welford> acc(methods.size()), diff(methods.size());
  run.per_method.resize(methods.size());
  for (std::size_t i = 0; i < methods.size(); ++i) run.per_method[i].method = methods[i];

  gen::Rng rng(seed);
  std::vector<io::Case> cases, rounded;
  std::vector<double> weight;  // contribution of each sample on a hit
  std::vector<std::size_t> case_of;  // sample -> case index, or npos when no ray is cast
  std::vector<std::vector<io::CaseResult>> results(methods.size());
  std::vector<double> f(methods.size());
  double sampling_seconds = 0;
  constexpr std::size_t npos = ~std::size_t{0};

  for (std::uint64_t done = 0; done < samples;) {
    const std::size_t count = static_cast<std::size_t>(std::min<std::uint64_t>(kBatch, samples - done));
    const auto t0 = Clock::now();
    cases.clear();
    weight.assign(count, 0.0);
    case_of.assign(count, npos);
    for (std::size_t i = 0; i < count; ++i) {
      const double u1 = rng.unit();
      const double u2 = rng.unit();
      Vec3<double> dir{};
      double w = 0;
      switch (est) {
        case Estimator::hemisphere: {
          const double z = 1 - u1;  // in (0, 1]
          const double sr = std::sqrt(std::max(0.0, 1 - z * z));
          dir = around_n.to_world(sr * std::cos(2 * kPi * u2), sr * std::sin(2 * kPi * u2), z);
          w = 2 * kPi * setup.L * z;
          break;
        }
        case Estimator::cosine: {
          const double sr = std::sqrt(u1);
          dir = around_n.to_world(sr * std::cos(2 * kPi * u2), sr * std::sin(2 * kPi * u2), std::sqrt(1 - u1));
          w = kPi * setup.L;
          break;
        }
        case Estimator::area: {
          const double rho = setup.r * std::sqrt(u1);
          const Vec3<double> y = centre + Vec3<double>{rho * std::cos(2 * kPi * u2), rho * std::sin(2 * kPi * u2), 0};
          // The direction and cosines from the sample's geometry relative to the receiver.
          const Vec3<double> d = rel + Vec3<double>{rho * std::cos(2 * kPi * u2), rho * std::sin(2 * kPi * u2), 0};
          const double d2 = length_squared(d);
          const double cos_r = dot(n, d) / std::sqrt(d2);
          if (!(cos_r > 0)) continue;  // below the receiver's horizon: contributes 0, no ray
          const double cos_l = setup.h / std::sqrt(d2);
          dir = y - setup.at;
          w = disk_area * setup.L * cos_r * cos_l / d2;
          break;
        }
        case Estimator::solid_angle: {
          const double one_minus_cos = u1 * k;
          const double cos_t = 1 - one_minus_cos;
          const double sin_t = std::sqrt(std::max(0.0, one_minus_cos * (2 - one_minus_cos)));
          dir = around_axis.to_world(sin_t * std::cos(2 * kPi * u2), sin_t * std::sin(2 * kPi * u2), cos_t);
          const double cos_r = dot(n, dir);
          if (!(cos_r > 0)) continue;  // below the horizon: contributes 0, no ray
          w = setup.L * cos_r * 2 * kPi * k;
          break;
        }
      }
      io::Case c;
      c.kind = io::Kind::disk;
      c.v = {setup.at.x, setup.at.y, setup.at.z, dir.x, dir.y, dir.z, centre.x, centre.y, centre.z, 0, 0, -1, setup.r};
      case_of[i] = cases.size();
      weight[i] = w;
      cases.push_back(c);
    }
    sampling_seconds += seconds_since(t0);

    for (std::size_t m = 0; m < methods.size(); ++m) {
      const auto t1 = Clock::now();
      std::span<const io::Case> in(cases);
      if (methods[m]->precision == Precision::float32) {
        rounded.resize(cases.size());
        for (std::size_t i = 0; i < cases.size(); ++i) rounded[i] = io::round_to_float(cases[i]);
        in = rounded;
      }
      results[m].resize(cases.size());
      methods[m]->classify_many(in, results[m]);
      run.per_method[m].seconds += seconds_since(t1);
    }
    for (std::size_t i = 0; i < count; ++i) {
      for (std::size_t m = 0; m < methods.size(); ++m) {
        const bool hit = case_of[i] != npos && is_hit(results[m][case_of[i]]);
        f[m] = hit ? weight[i] : 0.0;
        if (hit) ++run.per_method[m].hits;
        acc[m].add(f[m]);
        diff[m].add(f[m] - f[0]);
        if (case_of[i] != npos && hit != is_hit(results[0][case_of[i]])) ++run.per_method[m].disagreements;
      }
    }
    run.rays += cases.size();
    done += count;
  }
  for (std::size_t m = 0; m < methods.size(); ++m) {
    auto& pm = run.per_method[m];
    pm.mean = acc[m].mean;
    pm.std_error = acc[m].std_error();
    pm.diff_mean = diff[m].mean;
    pm.diff_std_error = diff[m].std_error();
    pm.seconds += sampling_seconds;
  }
  return run;
}

}  // namespace rayproof::light
