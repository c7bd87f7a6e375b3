#pragma once
/// Direct lighting for `rayproof render --light`: every pixel's first hit is lit
/// by the scene's disk lights with N shadow rays (a light chosen uniformly, then a point on it by
/// the area estimator, or a direction by the solid-angle estimator of light/irradiance_mc.h: the
/// cone around the disk's bounding sphere), leaving the surface by a spawn strategy of
/// rayproof/spawn.h. Lambertian surfaces (albedo 0.75) plus a small constant ambient term.
///
/// Acne: a shadow ray whose first crossing (t > 0, up to the light) is the primitive it leaves.
/// Shadow rays are spawned only where the light is above the surface (cos > 1e-6 against the
/// geometric normal facing the viewer), where no convex primitive or flat triangle can be met
/// again: every such crossing is a self-intersection.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "scene/scene_caster.h"
#include "rayproof/spawn.h"
#include "scene/scene.h"

namespace rayproof::light {

using scene::CastHit;
using scene::SceneCaster;

struct LightOptions {
  int shadow_rays = 4;
  bool solid_angle = false;  ///< estimator: false = area, true = solid angle
  SpawnStrategy spawn = SpawnStrategy::error_bounded;
  double epsilon = 1e-4;  ///< the fixed-epsilon strategy's offset
  std::uint64_t seed = 1;
  int threads = 0;
  /// The method casts float-rounded rays and primitives (float, robust, ...): origins are computed
  /// in float, with the rounding of the point and of the primitive added to the error bound.
  bool float_inputs = false;
  const SceneCaster* exact = nullptr;  ///< --verify: visibility against this caster (exact kernels)
};

struct LightResult {
  std::vector<std::uint8_t> rgb;      ///< the lit image
  std::vector<std::uint8_t> overlay;  ///< with `exact`: differing pixels marked, else empty
  std::uint64_t hit_pixels = 0, shadow_rays = 0, acne_rays = 0, acne_pixels = 0;
  std::uint64_t certified_fallbacks = 0;  ///< certified walks that gave up (error-bounded origin used)
  /// With `exact`: shadow rays blocked for the method but not for the exact reference (false
  /// occlusions), the other way (leaks), and pixels with either.
  std::uint64_t false_occlusions = 0, leaks = 0, differing_pixels = 0;
};

/// Lights the pixels of `rays` (width x height, row-major) whose first hits are `hits`, through
/// `caster`. The scene must have at least one light.
[[nodiscard]] LightResult render_lit(const scene::Scene& s, const SceneCaster& caster, int width, int height,
                                     std::span<const Ray<double>> rays, std::span<const CastHit> hits,
                                     const LightOptions& opt);

}  // namespace rayproof::light
