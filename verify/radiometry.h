#pragma once
/// Radiometry references for a uniform (Lambertian) disk light: solid angles and irradiance,
/// each with its accuracy.
///
/// Closed forms are evaluated in MPFR interval arithmetic (every operation rounded outward), so the
/// returned interval [lo, hi] provably contains the exact value of the formula at the given double
/// inputs. Configurations without a closed form (a disk seen off its axis, a tilted receiver) are
/// integrated along the disk's rim (a smooth, usually periodic integrand) by composite
/// Gauss-Legendre quadrature, doubling the panels until two rules agree; the accuracy given there is
/// that difference, an estimate, not a proof (`proven` is false).
///
/// Geometry (light/disk_light.h): the receiver point is the origin with unit normal
/// n = (sin tilt, 0, cos tilt); the disk light has centre (offset, 0, h), h > 0, radius r, and
/// emits radiance L downward (normal (0, 0, -1)).
#include <cstdint>
#include <string>

namespace rayproof::verify {

/// A reference value and how accurate it is.
struct Reference {
  double value = 0;        ///< nearest double to the midpoint of [lo, hi]
  double lo = 0, hi = 0;   ///< the exact value lies in [lo, hi] (proven) or is estimated to
  bool proven = false;     ///< true: interval arithmetic; false: quadrature error estimate
  std::string method;      ///< how it was computed, one line
  [[nodiscard]] double error_bound() const { return hi - lo; }
};

/// Solid angle of the patch theta in [theta1, theta2], phi in [0, dphi] (degrees): exactly
/// (cos theta1 - cos theta2) dphi.
[[nodiscard]] Reference patch_solid_angle(double theta1_deg, double theta2_deg, double dphi_deg);
/// The small-patch estimate sin(theta) dtheta dphi with sin taken at theta_at (degrees). The worked
/// problems' patch (theta from 30 to 45 degrees, 30 degrees of phi, sin at 30) gives pi^2/144.
[[nodiscard]] Reference patch_solid_angle_estimate(double theta1_deg, double theta2_deg, double dphi_deg,
                                                   double theta_at_deg);

/// Solid angle of a disk of radius r seen from a point on its axis at distance h > 0:
/// 2 pi (1 - h / sqrt(h^2 + r^2)), evaluated as 2 pi r^2 / (R (R + h)), R = sqrt(h^2 + r^2).
[[nodiscard]] Reference disk_solid_angle_on_axis(double r, double h);
/// Solid angle of the disk from a point at height h below the disk's plane and `offset` from its
/// axis: rim integral of the monopole vector potential (ez x p) / (|p| (|p| + p.ez)), quadrature.
[[nodiscard]] Reference disk_solid_angle(double r, double h, double offset);

/// Irradiance on the axis, receiver parallel to the disk: E = pi L r^2 / (r^2 + h^2).
[[nodiscard]] Reference irradiance_on_axis(double r, double h, double L);
/// Irradiance off the axis, receiver parallel to the disk (closed form, interval arithmetic).
[[nodiscard]] Reference irradiance_parallel(double r, double h, double offset, double L);
/// Irradiance on a receiver tilted by `tilt_rad` about the y axis (toward +x for tilt > 0):
/// Lambert's rim integral E = L n . (1/2) \oint p x dp / |p|^2 over the part of the disk above the
/// receiver's horizon (the chord closing a clipped disk contributes in closed form); quadrature.
[[nodiscard]] Reference irradiance_tilted(double r, double h, double offset, double tilt_rad, double L);

/// The best reference for the configuration: the closed forms when the receiver is parallel
/// (tilt == 0), else the rim quadrature.
[[nodiscard]] Reference irradiance_reference(double r, double h, double offset, double tilt_rad, double L);

/// Double-precision closed form of the parallel case without cancellation (for estimators' sanity
/// checks and tests): pi L (1 - B / S) / 2, B = h^2 + a^2 - r^2, S^2 = B^2 + 4 r^2 h^2.
[[nodiscard]] double irradiance_parallel_double(double r, double h, double offset, double L);

}  // namespace rayproof::verify
