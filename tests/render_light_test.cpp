// rayproof render --light: direct lighting with shadow rays; the error-bounded and
// certified spawn strategies leave no acne (no shadow ray meets the primitive it leaves) and agree
// with exact visibility, while no offset leaves acne (light/render_light.h).
#include <gtest/gtest.h>

#include <string>

#include "registry/registry.h"
#include "light/render_light.h"
#include "tests/cli_support.h"

namespace rayproof {
namespace {

struct Frame {
  scene::Scene s;
  std::vector<Ray<double>> rays;
  std::vector<scene::CastHit> hits;
  int w, h;
};

Frame primary(int w, int h, const scene::SceneCaster& caster, const scene::Scene& s) {
  Frame f{s, {}, {}, w, h};
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) f.rays.push_back(s.camera->generate(i, j));
  f.hits.resize(f.rays.size());
  caster.closest(f.rays, f.hits, 1);
  return f;
}

light::LightResult lit(const scene::Scene& s, const scene::SceneCaster& c, const Frame& f, SpawnStrategy sp, bool solid_angle,
                     const scene::SceneCaster* exact = nullptr, bool float_inputs = false) {
  light::LightOptions o;
  o.shadow_rays = 2;
  o.spawn = sp;
  o.solid_angle = solid_angle;
  o.threads = 1;
  o.exact = exact;
  o.float_inputs = float_inputs;
  return light::render_lit(s, c, f.w, f.h, f.rays, f.hits, o);
}

TEST(RenderLight, ErrorBoundedAndCertifiedHaveNoAcneNoneHas) {
  const scene::Scene s = scene::default_scene(2, 96, 72);
  for (const char* method : {"double", "float", "robust"}) {
    const scene::SceneCaster c(s, scene::find_scene_method(method, registry::all_methods()));
    const Frame f = primary(96, 72, c, s);
    for (bool sa : {false, true}) {
      const std::string what = std::string(method) + (sa ? " solid-angle" : " area");
      const bool fi = std::string(method) != "double";
      const auto none = lit(s, c, f, SpawnStrategy::none, sa, nullptr, fi);
      EXPECT_GT(none.hit_pixels, 96u * 72u / 3) << what;
      EXPECT_GT(none.shadow_rays, none.hit_pixels / 2) << what;
      EXPECT_GT(none.acne_pixels, none.hit_pixels / 50) << what;
      const auto eb = lit(s, c, f, SpawnStrategy::error_bounded, sa, nullptr, fi);
      EXPECT_EQ(eb.acne_rays, 0u) << what;
      EXPECT_EQ(eb.acne_pixels, 0u) << what;
      EXPECT_EQ(eb.shadow_rays, none.shadow_rays) << what;  // the same light samples
      const auto cert = lit(s, c, f, SpawnStrategy::certified, sa, nullptr, fi);
      EXPECT_EQ(cert.acne_pixels, 0u) << what;
      // Acne darkens: the naive image is darker in sum.
      std::uint64_t sum_none = 0, sum_eb = 0;
      for (auto v : none.rgb) sum_none += v;
      for (auto v : eb.rgb) sum_eb += v;
      EXPECT_LT(sum_none, sum_eb) << what;
    }
  }
}

TEST(RenderLight, VisibilityAgreesWithExactForErrorBounded) {
  const scene::Scene s = scene::default_scene(2, 40, 30);
  const scene::SceneCaster c(s, scene::find_scene_method("double", registry::all_methods()));
  const scene::SceneCaster exact(s, scene::find_scene_method("exact", registry::all_methods()));
  const Frame f = primary(40, 30, c, s);
  const auto eb = lit(s, c, f, SpawnStrategy::error_bounded, false, &exact);
  EXPECT_EQ(eb.false_occlusions, 0u);
  EXPECT_EQ(eb.leaks, 0u);
  EXPECT_EQ(eb.differing_pixels, 0u);
  EXPECT_EQ(eb.overlay.size(), eb.rgb.size());
  const auto none = lit(s, c, f, SpawnStrategy::none, false, &exact);
  EXPECT_GE(none.false_occlusions, 1u);
  EXPECT_GE(none.differing_pixels, none.acne_pixels / 2);
}

TEST(RenderLight, CommandLine) {
  const auto dir = testing::scratch_dir();
  const auto out = (dir / "lit.png").string();
  auto r = testing::run_rayproof("render default --light --width 48 --height 36 --shadow-rays 2 --spawn none --out " + out);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("acne:"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(out));
  r = testing::run_rayproof("render default --light --width 48 --height 36 --spawn sometimes --out " + out);
  EXPECT_NE(r.status, 0);
  const auto off = testing::write_file("tri.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  r = testing::run_rayproof("render " + off.string() + " --light --width 8 --height 8 --out " + out);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("no lights"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rayproof
