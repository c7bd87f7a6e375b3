// Radiometry references (verify/radiometry.h) against each other and the worked problems, the Monte
// Carlo estimators (light/irradiance_mc.h) against the references, and `rayproof irradiance`'s
// handling of bad flags.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>

#include "registry/registry.h"
#include "light/irradiance_mc.h"
#include "tests/cli_support.h"
#include "verify/radiometry.h"

namespace rayproof {
namespace {

constexpr double kPi = std::numbers::pi;
double deg(double d) { return d * kPi / 180; }

/// The reference's interval holds `x` to within `slack` (absolute).
void expect_holds(const verify::Reference& ref, double x, double slack = 0) {
  EXPECT_LE(ref.lo - slack, x) << ref.method;
  EXPECT_GE(ref.hi + slack, x) << ref.method;
}

/// Midpoint rule over the disk in polar coordinates about its centre, n_rho x n_psi cells:
/// integral of g(p) dA with p the point relative to the receiver at the origin.
double disk_integral(double r, double h, double a, int n_rho, int n_psi, const std::function<double(double, double, double)>& g) {
  double sum = 0;
  for (int i = 0; i < n_rho; ++i) {
    const double rho = r * (i + 0.5) / n_rho;
    double ring = 0;
    for (int j = 0; j < n_psi; ++j) {
      const double psi = 2 * kPi * (j + 0.5) / n_psi;
      ring += g(a + rho * std::cos(psi), rho * std::sin(psi), h);
    }
    sum += ring * rho;
  }
  return sum * (r / n_rho) * (2 * kPi / n_psi);
}

TEST(Radiometry, PatchEstimateIsTheWorkedProblemsPiSquaredOver144) {
  // The patch theta in [30, 45] degrees, 30 degrees of phi; the estimate takes sin at theta = 30.
  const auto est = verify::patch_solid_angle_estimate(30, 45, 30, 30);
  EXPECT_TRUE(est.proven);
  expect_holds(est, kPi * kPi / 144, 2e-17);
  EXPECT_NEAR(est.value, kPi * kPi / 144, 1e-17);
  const auto exact = verify::patch_solid_angle(30, 45, 30);
  EXPECT_TRUE(exact.proven);
  EXPECT_LE(exact.error_bound(), 2e-17);
  EXPECT_NEAR(exact.value, (std::sqrt(3.0) / 2 - std::sqrt(2.0) / 2) * kPi / 6, 1e-16);
  // The small-patch estimate is about 18% low for this patch: the two are different numbers.
  EXPECT_NEAR(est.value / exact.value, 0.8236, 1e-3);
  // Shrinking the patch makes the estimate converge to the exact value (error ~ dtheta).
  const double e1 = std::fabs(verify::patch_solid_angle_estimate(30, 31, 1, 30.5).value / verify::patch_solid_angle(30, 31, 1).value - 1);
  EXPECT_LT(e1, 1e-4);
  EXPECT_THROW((void)verify::patch_solid_angle(50, 40, 10), std::invalid_argument);
}

TEST(Radiometry, DiskSolidAngleOnAndOffAxis) {
  const auto on = verify::disk_solid_angle_on_axis(1, 2);
  EXPECT_TRUE(on.proven);
  EXPECT_NEAR(on.value, 2 * kPi * (1 - 2 / std::sqrt(5.0)), 1e-15);
  // The rim quadrature at a negligible offset agrees with the closed form.
  const auto quad = verify::disk_solid_angle(1, 2, 1e-200);
  EXPECT_FALSE(quad.proven);
  EXPECT_NEAR(quad.value, on.value, 1e-14);
  // Off axis: against the area integral of h / d^3 (midpoint rule, ~1e-7 relative).
  for (const auto& [r, h, a] : {std::array{1.0, 1.0, 0.5}, std::array{1.0, 0.5, 2.0}, std::array{0.3, 2.0, 5.0}}) {
    const auto ref = verify::disk_solid_angle(r, h, a);
    const double brute = disk_integral(r, h, a, 1000, 256, [](double x, double y, double z) {
      const double d2 = x * x + y * y + z * z;
      return z / (d2 * std::sqrt(d2));
    });
    EXPECT_NEAR(ref.value / brute, 1, 1e-5) << r << " " << h << " " << a;
    EXPECT_LT(ref.error_bound(), 1e-11 * ref.value);
  }
  // A far, small disk: pi r^2 h / d^3 to first order.
  const auto far = verify::disk_solid_angle(1e-3, 100, 30);
  const double d = std::hypot(100.0, 30.0);
  EXPECT_NEAR(far.value / (kPi * 1e-6 * 100 / (d * d * d)), 1, 1e-6);
}

TEST(Radiometry, OnAxisIrradianceIsTheWorkedProblemsClosedForm) {
  // E = pi L sin^2 alpha: r = h gives alpha = 45 degrees, E = pi L / 2.
  const auto e = verify::irradiance_on_axis(1, 1, 3);
  EXPECT_TRUE(e.proven);
  expect_holds(e, 3 * kPi / 2, 1e-15);
  EXPECT_LE(e.error_bound(), 1e-15);
  EXPECT_NEAR(verify::irradiance_on_axis(3, 4, 1).value, kPi * 9 / 25, 1e-15);
}

TEST(Radiometry, ParallelOffAxisClosedFormAgreesWithOnAxisAndQuadrature) {
  // At offset 0 the off-axis closed form is the on-axis one.
  for (const auto& [r, h] : {std::pair{1.0, 2.0}, std::pair{2.0, 0.5}, std::pair{1e-3, 1e3}}) {
    const auto on = verify::irradiance_on_axis(r, h, 1);
    const auto off = verify::irradiance_parallel(r, h, 0, 1);
    EXPECT_NEAR(off.value / on.value, 1, 1e-15);
  }
  // Off axis: the closed form, its double version and Lambert's rim quadrature agree.
  for (const auto& [r, h, a] : {std::array{1.0, 1.0, 0.5}, std::array{1.0, 0.5, 2.0}, std::array{0.3, 2.0, 5.0},
                                std::array{2.0, 0.1, 1.9}, std::array{1e-3, 100.0, 30.0}}) {
    const auto closed = verify::irradiance_parallel(r, h, a, 1);
    EXPECT_TRUE(closed.proven);
    EXPECT_LE(closed.error_bound(), 4e-16 * closed.value);
    EXPECT_NEAR(verify::irradiance_parallel_double(r, h, a, 1) / closed.value, 1, 1e-14);
    const auto quad = verify::irradiance_tilted(r, h, a, 0, 1);
    EXPECT_FALSE(quad.proven);
    EXPECT_NEAR(quad.value, closed.value, quad.error_bound() + 1e-14 * closed.value) << r << " " << h << " " << a;
    // And the area integral of cos theta cos theta' / d^2 = h^2 / d^4 (midpoint rule; slowest, ~1e-5, for
    // the receiver close to the plane near the rim).
    const double brute = disk_integral(r, h, a, 1000, 256, [](double x, double y, double z) {
      const double d2 = x * x + y * y + z * z;
      return z * z / (d2 * d2);
    });
    EXPECT_NEAR(brute / closed.value, 1, 5e-5) << r << " " << h << " " << a;
  }
}

TEST(Radiometry, QuadratureErrorEstimatesHoldTheClosedFormInHardParallelCases) {
  // Receivers close to the disk's plane, under the rim, far away: the rim quadrature's stated
  // interval must hold the proven closed form (or say that it did not converge).
  int converged = 0;
  for (const auto& [r, h, a] : {std::array{1.0, 1e-6, 1.0}, std::array{1.0, 1e-3, 0.999}, std::array{1.0, 1e-6, 1.5},
                                std::array{1.0, 1e-2, 2.001}, std::array{1e-3, 1e3, 50.0}, std::array{1.0, 1e-8, 3.0},
                                std::array{1.0, 1e-4, 0.5}, std::array{5.0, 0.3, 4.0}}) {
    const auto closed = verify::irradiance_parallel(r, h, a, 1);
    const auto quad = verify::irradiance_tilted(r, h, a, 0, 1);
    if (quad.method.find("NOT CONVERGED") != std::string::npos) continue;
    ++converged;
    EXPECT_LE(quad.lo, closed.hi) << r << " " << h << " " << a << ": " << quad.method;
    EXPECT_GE(quad.hi, closed.lo) << r << " " << h << " " << a << ": " << quad.method;
  }
  EXPECT_GE(converged, 7);
}

TEST(Radiometry, TiltedReceiverReferences) {
  // Wholly above the horizon, E is linear in n: E(t) = cos t E(0) + sin t E(90 deg).
  const double r = 1, h = 1.5, a = 2.5;
  const double e0 = verify::irradiance_parallel(r, h, a, 1).value;
  const double e90 = verify::irradiance_tilted(r, h, a, deg(90), 1).value;
  for (double t : {10.0, 35.0, 60.0, 85.0}) {
    const auto et = verify::irradiance_tilted(r, h, a, deg(t), 1);
    EXPECT_NEAR(et.value, std::cos(deg(t)) * e0 + std::sin(deg(t)) * e90, 1e-13) << t;
    EXPECT_LT(et.error_bound(), 1e-13);
  }
  // On the axis, tilted but wholly visible: cos t times the on-axis value.
  EXPECT_NEAR(verify::irradiance_tilted(1, 2, 0, deg(30), 1).value, std::cos(deg(30)) * kPi / 5, 1e-14);
  // Clipped by the horizon: the arc plus chord against the clamped area integral (kinked, so the
  // midpoint rule only reaches ~1e-4).
  for (const auto& [rr, hh, aa, t] : {std::array{1.0, 1.0, 0.0, 60.0}, std::array{1.0, 1.0, 1.5, -60.0},
                                      std::array{2.0, 0.5, 1.0, 80.0}, std::array{1.0, 1.0, 0.5, 120.0}}) {
    const auto ref = verify::irradiance_tilted(rr, hh, aa, deg(t), 1);
    const double nx = std::sin(deg(t)), nz = std::cos(deg(t));
    const double brute = disk_integral(rr, hh, aa, 1200, 1200, [&](double x, double y, double z) {
      const double d2 = x * x + y * y + z * z;
      const double cr = (nx * x + nz * z);
      return cr > 0 ? cr * z / (d2 * d2) : 0.0;
    });
    EXPECT_NEAR(ref.value / brute, 1, 2e-4) << rr << " " << hh << " " << aa << " " << t;
  }
  // Wholly below the horizon: nothing arrives.
  EXPECT_EQ(verify::irradiance_tilted(1, 1, -5, deg(100), 1).value, 0);
  // The dispatcher: closed forms for parallel receivers.
  EXPECT_TRUE(verify::irradiance_reference(1, 1, 0, 0, 1).proven);
  EXPECT_TRUE(verify::irradiance_reference(1, 1, 2, 0, 1).proven);
  EXPECT_FALSE(verify::irradiance_reference(1, 1, 2, 0.1, 1).proven);
  EXPECT_THROW((void)verify::irradiance_tilted(1, -1, 0, 0, 1), std::invalid_argument);
  EXPECT_THROW((void)verify::irradiance_on_axis(std::nan(""), 1, 1), std::invalid_argument);
}

struct McCase {
  light::DiskLightSetup setup;
  const char* what;
};

// Every estimator through several methods, three seeds, a fixed count: within 4 standard errors of
// the reference (and the reference's own stated error).
TEST(IrradianceMc, EveryEstimatorConvergesToTheReference) {
  light::DiskLightSetup on_axis;
  on_axis.r = 1, on_axis.h = 2, on_axis.L = 1.5;
  light::DiskLightSetup clipped;
  clipped.r = 1, clipped.h = 1, clipped.offset = 1.5, clipped.tilt = deg(-50), clipped.at = {3, -2, 1};
  light::DiskLightSetup near;  // receiver inside the disk's bounding sphere: the hemisphere toward the disk
  near.r = 2, near.h = 0.5, near.offset = 0.3, near.tilt = deg(20);
  std::vector<const Method*> methods;
  for (const char* name : {"certified", "double", "float", "robust"}) {
    const Method* m = registry::all_methods().find(name);
    ASSERT_NE(m, nullptr) << name;
    methods.push_back(m);
  }
  for (const McCase& c : {McCase{on_axis, "on axis"}, McCase{clipped, "tilted, clipped, off origin"},
                          McCase{near, "inside the bounding sphere"}}) {
    const auto& s = c.setup;
    const auto ref = verify::irradiance_reference(s.r, s.h, s.offset, s.tilt, s.L);
    for (light::Estimator est : light::kAllEstimators) {
      for (std::uint64_t seed : {1, 2, 3}) {
        const auto run = light::estimate_irradiance(s, est, methods, 20000, seed);
        ASSERT_EQ(run.per_method.size(), methods.size());
        for (const auto& pm : run.per_method) {
          EXPECT_GT(pm.std_error, 0);
          EXPECT_NEAR(pm.mean, ref.value, 4 * pm.std_error + ref.error_bound())
              << c.what << ", " << light::to_string(est) << ", " << pm.method->name << ", seed " << seed;
        }
      }
    }
  }
}

TEST(IrradianceMc, DeterministicBySeedAndPairedOnTheSameRays) {
  light::DiskLightSetup s;
  s.r = 0.5, s.h = 1, s.offset = 0.7;
  const Method* dbl = registry::all_methods().find("double");
  const Method* cert = registry::all_methods().find("certified");
  const std::vector<const Method*> two{cert, dbl};
  for (light::Estimator est : light::kAllEstimators) {
    const auto a = light::estimate_irradiance(s, est, two, 5000, 9);
    const auto b = light::estimate_irradiance(s, est, two, 5000, 9);
    const auto c = light::estimate_irradiance(s, est, two, 5000, 10);
    EXPECT_EQ(a.per_method[1].mean, b.per_method[1].mean);
    EXPECT_NE(a.per_method[1].mean, c.per_method[1].mean);
    // On these benign rays double answers as certified does: no disagreement, zero difference.
    EXPECT_EQ(a.per_method[1].disagreements, 0u);
    EXPECT_EQ(a.per_method[1].diff_mean, 0);
    EXPECT_EQ(a.per_method[1].mean, a.per_method[0].mean);
  }
}

TEST(IrradianceMc, FloatKernelsFarFromTheOriginLoseRimHitsMeasurably) {
  // A small, far disk seen from a receiver far from the origin: float rounding of the inputs moves
  // rays across the rim. The paired difference against certified shows a bias far beyond its
  // standard error for `float`; `robust` (FMA disk, the same float inputs) stays within it here.
  light::DiskLightSetup s;
  s.r = 0.01, s.h = 100, s.offset = 3, s.at = {1000, -700, 300};
  const std::vector<const Method*> ms{registry::all_methods().find("certified"), registry::all_methods().find("float")};
  const auto run = light::estimate_irradiance(s, light::Estimator::solid_angle, ms, 100000, 1);
  const auto& f = run.per_method[1];
  EXPECT_GT(f.disagreements, 0u);
  EXPECT_GT(std::fabs(f.diff_mean), 4 * f.diff_std_error);
}

TEST(IrradianceMc, BadInputIsRejected) {
  light::DiskLightSetup s;
  const std::vector<const Method*> ms{registry::all_methods().find("double")};
  s.r = -1;
  EXPECT_NE(light::check_setup(s), "");
  EXPECT_THROW((void)light::estimate_irradiance(s, light::Estimator::cosine, ms, 10, 1), std::invalid_argument);
  s = {};
  s.h = std::nan("");
  EXPECT_NE(light::check_setup(s), "");
  s = {};
  EXPECT_EQ(light::check_setup(s), "");
  EXPECT_THROW((void)light::estimate_irradiance(s, light::Estimator::cosine, {}, 10, 1), std::invalid_argument);
  EXPECT_EQ(light::estimator_from_string("solid-angle"), light::Estimator::solid_angle);
  EXPECT_FALSE(light::estimator_from_string("nope"));
}

TEST(IrradianceCli, PrintsEstimateReferenceAndError) {
  const auto res = testing::run_rayproof("irradiance --r 1 --h 1 -n 2000 --seed 3 -e cosine -m double");
  ASSERT_EQ(res.status, 0) << res.err;
  EXPECT_NE(res.out.find("reference E = 1.5707963267948966"), std::string::npos) << res.out;
  EXPECT_NE(res.out.find("proven"), std::string::npos);
  EXPECT_NE(res.out.find("error/SE"), std::string::npos);
  EXPECT_NE(res.out.find("double"), std::string::npos);
}

TEST(IrradianceCli, BadFlagsGetClearErrors) {
  const std::pair<const char*, const char*> bad[] = {
      {"--r -1", "radius"},
      {"--h 0", "height"},
      {"--h nan", "height"},
      {"--tilt 200", "tilt"},
      {"--L -2", "radiance"},
      {"--samples 0", "--samples"},
      {"--estimator bogus", "unknown estimator 'bogus'"},
      {"--method nosuch", "unknown method 'nosuch'"},
      {"--method cramer-double", "does not answer disk"},
      {"--sweep-seeds 0", "--sweep-seeds"},
      {"--r 1e300", "within [1e-100, 1e100]"},
      {"--at 1e200,0,0", "at most 1e100"},
      {"--sweep --sweep-min 0", "--sweep-min"},
  };
  for (const auto& [flags, message] : bad) {
    const auto res = testing::run_rayproof(std::string("irradiance ") + flags);
    EXPECT_EQ(res.status, 2) << flags;
    EXPECT_NE(res.err.find(message), std::string::npos) << flags << ": " << res.err;
    EXPECT_EQ(res.out, "") << flags;
  }
  const auto res = testing::run_rayproof("irradiance --r abc");
  EXPECT_NE(res.status, 0);
  EXPECT_NE(res.err, "");
}

TEST(IrradianceCli, SweepWritesSvgAndCsv) {
  const auto dir = testing::scratch_dir() / "sweep";
  const auto res = testing::run_rayproof("irradiance --sweep -n 1024 --sweep-min 256 --sweep-seeds 2 -m double,float --out " +
                                         dir.string());
  ASSERT_EQ(res.status, 0) << res.err;
  const std::string svg = testing::slurp(dir / "irradiance_sweep.svg");
  const std::string csv = testing::slurp(dir / "irradiance_sweep.csv");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("slope -1/2"), std::string::npos);
  // 4 estimators x 2 methods x 2 counts, one header line.
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 4 * 2 * 2);
  EXPECT_NE(csv.find("solid-angle,float,1024,2,"), std::string::npos);
}

TEST(IrradianceCli, ReportGainsAnIrradianceSection) {
  const auto dir = testing::scratch_dir() / "report_light";
  const auto res = testing::run_rayproof("report --count 20 --families disk_rim --methods double,float --irradiance-samples 1024 --out " +
                                         dir.string());
  ASSERT_EQ(res.status, 0) << res.err;
  const std::string md = testing::slurp(dir / "report.md");
  EXPECT_NE(md.find("## Irradiance from a disk light"), std::string::npos);
  EXPECT_NE(md.find("| solid-angle | float | 1024 |"), std::string::npos) << md;
  EXPECT_NE(md.find("rays answered unlike certified"), std::string::npos);
  EXPECT_NE(md.find("| sphere | 20 | float | 2000 |"), std::string::npos) << md;
  EXPECT_NE(testing::slurp(dir / "irradiance_sweep.svg").find("</svg>"), std::string::npos);
  // --irradiance-samples 0: no section.
  const auto dir0 = testing::scratch_dir() / "report_dark";
  ASSERT_EQ(testing::run_rayproof("report --count 20 --families disk_rim --methods double --irradiance-samples 0 --out " +
                                  dir0.string()).status, 0);
  EXPECT_EQ(testing::slurp(dir0 / "report.md").find("## Irradiance"), std::string::npos);
}

}  // namespace
}  // namespace rayproof
