/// rayproof render SCENE --out IMAGE.png [--method M] [--verify]: primary rays from the scene's
/// camera (or a default view framing the scene), shaded by normal and depth. With --verify, every
/// pixel's first hit is compared with the exact method's (conservative traversal, exact kernels);
/// a second image marks false misses (red), false hits (blue) and wrong primitive or class
/// (yellow), and the counts are printed.
/// With --light: direct lighting from the scene's disk lights (light/render_light.h),
/// --shadow-rays N per pixel, --estimator area|solid-angle, --spawn none|epsilon|error-bounded|
/// certified; the acne (shadow rays meeting the primitive they leave) is counted. --verify then
/// compares every shadow ray's visibility with the exact kernels' from the certified origin and
/// marks the pixels that differ: red a false occlusion, blue a leak, magenta both.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <png.h>

#include <cmath>
#include <cstdio>
#include <memory>

#include "cli/commands.h"
#include "light/render_light.h"
#include "cli/scene_input.h"

namespace rayproof::cli {

using light::LightOptions;
using light::LightResult;
using light::render_lit;

namespace {
struct RenderOptions {
  std::string scene, out, method = "double", builder = "sah", verify_out;
  int width = 0, height = 0, threads = 0;
  bool verify = false, verbose = false;
  bool light = false;
  int shadow_rays = 4;
  std::string estimator = "area", spawn = "error-bounded";
  double epsilon = 1e-4;
  std::uint64_t seed = 1;
};

bool write_png(const std::string& path, int w, int h, const std::vector<std::uint8_t>& rgb, std::string& err) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return err = path + ": cannot write", false;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    return err = path + ": libpng error", false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  for (int y = 0; y < h; ++y) png_write_row(png, const_cast<png_bytep>(rgb.data() + 3 * std::size_t(w) * y));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return std::fclose(f) == 0 || (err = path + ": write error", false);
}

/// Unit normal of a primitive at the hit point p (geometric; towards the ray's origin side).
Vec3<double> normal_at(const scene::Scene& s, std::uint32_t id, Vec3<double> p, Vec3<double> d) {
  std::uint32_t k;
  Vec3<double> n{0, 1, 0};
  switch (s.kind_of(id, k)) {
    case scene::PrimKind::triangle: {
      const auto t = s.triangle(k);
      n = cross(t.p1 - t.p0, t.p2 - t.p0);
      break;
    }
    case scene::PrimKind::sphere: n = p - s.spheres[k].center; break;
    case scene::PrimKind::ellipsoid: {
      const auto& e = s.ellipsoids[k];
      n = div(p - e.center, mul(e.semi_axes, e.semi_axes));
      break;
    }
    case scene::PrimKind::disk: n = s.disks[k].normal; break;
    case scene::PrimKind::box: {
      const auto& b = s.boxes[k];
      double best = 1e300;
      for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
          const double dist = std::abs(p[a] - (side ? b.hi[a] : b.lo[a]));
          if (dist < best) best = dist, n = Vec3<double>{}, n[a] = side ? 1 : -1;
        }
      break;
    }
  }
  if (is_zero(n) || !all_finite(n)) return {0, 0, 0};
  n = normalize(n);
  return dot(n, d) > 0 ? -n : n;
}

std::string verify_path(const RenderOptions& opt) {
  if (!opt.verify_out.empty()) return opt.verify_out;
  return (opt.out.size() > 4 ? opt.out.substr(0, opt.out.size() - 4) : opt.out) + "-verify.png";
}

int run_render_light(const RenderOptions& opt, const scene::Scene& s, const SceneCaster& caster,
                     const scene::SceneMethod& caster_method,
                     int w, int h, const std::vector<Ray<double>>& rays, const std::vector<CastHit>& hits) {
  if (s.lights.empty()) return fmt::print(stderr, "rayproof render: --light: the scene has no lights\n"), 2;
  LightOptions lo;
  lo.shadow_rays = opt.shadow_rays;
  lo.solid_angle = opt.estimator == "solid-angle";
  lo.spawn = opt.spawn == "none"            ? SpawnStrategy::none
             : opt.spawn == "epsilon"       ? SpawnStrategy::fixed_epsilon
             : opt.spawn == "error-bounded" ? SpawnStrategy::error_bounded
                                            : SpawnStrategy::certified;
  lo.epsilon = opt.epsilon;
  lo.seed = opt.seed;
  lo.threads = opt.threads;
  const scene::SceneMethod& sm = caster_method;
  lo.float_inputs = sm.generic ? sm.generic->precision == Precision::float32
                               : (sm.fast == FastKernel::mt_float || sm.fast == FastKernel::cramer_float ||
                                  sm.fast == FastKernel::watertight_float || sm.fast == FastKernel::robust);
  std::optional<SceneCaster> exact;
  if (opt.verify) {
    exact.emplace(s, scene::find_scene_method("exact", registry::all_methods()));
    lo.exact = &*exact;
  }
  const LightResult r = render_lit(s, caster, w, h, rays, hits, lo);
  std::string err;
  if (!write_png(opt.out, w, h, r.rgb, err)) return fmt::print(stderr, "rayproof render: {}\n", err), 2;
  fmt::print("{}: {}x{} pixels, {} hits, method {}, lit by {} light(s): {} shadow rays ({} per pixel, {} estimator, spawn {})\n",
             opt.out, w, h, r.hit_pixels, caster_method.name, s.lights.size(), r.shadow_rays, opt.shadow_rays, opt.estimator, opt.spawn);
  fmt::print("acne: {} shadow rays met the primitive they leave, in {} pixels\n", r.acne_rays, r.acne_pixels);
  if (lo.spawn == SpawnStrategy::certified && r.certified_fallbacks)
    fmt::print("certified walks that gave up after 64 ulp steps (error-bounded origin used): {}\n", r.certified_fallbacks);
  if (!opt.verify) return 0;
  const std::string vout = verify_path(opt);
  if (!write_png(vout, w, h, r.overlay, err)) return fmt::print(stderr, "rayproof render: {}\n", err), 2;
  fmt::print("{}: against exact visibility (exact kernels from the certified origin): {} false occlusions, {} leaks "
             "of {} shadow rays; {} pixels differ\n",
             vout, r.false_occlusions, r.leaks, r.shadow_rays, r.differing_pixels);
  return 0;
}

int run_render(const RenderOptions& opt) {
  auto loaded = load_scene_for_cli("render", opt.scene, opt.method, opt.builder, opt.verbose);
  if (!loaded) return 2;
  const scene::Scene& s = *loaded->scene;
  scene::Camera cam = s.camera ? *s.camera : scene::default_camera(s, 512, 384);
  const int w = opt.width ? opt.width : cam.width(), h = opt.height ? opt.height : cam.height();
  if (opt.width || opt.height) {
    if (auto* p = std::get_if<PerspectiveCamera<double>>(&cam.cam)) p->width = w, p->height = h;
    if (auto* o = std::get_if<OrthographicCamera<double>>(&cam.cam)) o->width = w, o->height = h;
  }
  std::vector<Ray<double>> rays;
  rays.reserve(std::size_t(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) rays.push_back(cam.generate(i, j));
  std::vector<CastHit> hits(rays.size());
  loaded->caster->closest(rays, hits, opt.threads);
  // Depth range over the hits, for the depth shading.
  double tlo = 1e300, thi = -1e300;
  for (const auto& x : hits)
    if (x.hit()) tlo = std::min(tlo, x.t), thi = std::max(thi, x.t);
  if (opt.light) return run_render_light(opt, s, *loaded->caster, loaded->method, w, h, rays, hits);
  std::vector<std::uint8_t> rgb(rays.size() * 3, 0);
  for (std::size_t p = 0; p < rays.size(); ++p) {
    const auto& x = hits[p];
    if (!x.hit()) {
      rgb[3 * p] = 30, rgb[3 * p + 1] = 30, rgb[3 * p + 2] = 40;
      continue;
    }
    const Vec3<double> d = normalize(rays[p].d);
    const Vec3<double> n = normal_at(s, x.triangle, rays[p].at(x.t), d);
    const double depth = thi > tlo ? 1 - 0.6 * (x.t - tlo) / (thi - tlo) : 1;
    for (int c = 0; c < 3; ++c) rgb[3 * p + c] = static_cast<std::uint8_t>(std::clamp((0.5 + 0.5 * n[c]) * depth * 255, 0.0, 255.0));
  }
  std::string err;
  if (!write_png(opt.out, w, h, rgb, err)) return fmt::print(stderr, "rayproof render: {}\n", err), 2;
  fmt::print("{}: {}x{} pixels, {} hits, method {}\n", opt.out, w, h,
             std::count_if(hits.begin(), hits.end(), [](const auto& x) { return x.hit(); }),
             loaded->method.name);
  if (!opt.verify) return 0;

  // Exact first hits: the registry's exact kernels under conservative traversal, through the scene
  // BVH (the public MeshCaster has no exact method).
  const scene::SceneMethod exact = scene::find_scene_method("exact", registry::all_methods());
  const SceneCaster exact_caster(s, exact);
  std::vector<CastHit> truth(rays.size());
  exact_caster.closest(rays, truth, opt.threads);
  std::uint64_t false_miss = 0, false_hit = 0, wrong = 0;
  std::vector<std::uint8_t> marks(rgb.size());
  for (std::size_t p = 0; p < rays.size(); ++p) {
    const bool a = hits[p].hit(), b = truth[p].hit();
    std::uint8_t c[3] = {std::uint8_t(rgb[3 * p] / 3), std::uint8_t(rgb[3 * p + 1] / 3), std::uint8_t(rgb[3 * p + 2] / 3)};
    if (!a && b) ++false_miss, c[0] = 255, c[1] = 0, c[2] = 0;
    else if (a && !b) ++false_hit, c[0] = 0, c[1] = 80, c[2] = 255;
    else if (a && (hits[p].triangle != truth[p].triangle || hits[p].contact != truth[p].contact)) ++wrong, c[0] = 255, c[1] = 230, c[2] = 0;
    std::copy(c, c + 3, marks.begin() + 3 * p);
  }
  const std::string vout = verify_path(opt);
  if (!write_png(vout, w, h, marks, err)) return fmt::print(stderr, "rayproof render: {}\n", err), 2;
  fmt::print("{}: false_miss {} false_hit {} wrong_feature {} (of {} pixels, against exact)\n", vout, false_miss,
             false_hit, wrong, rays.size());
  return 0;
}
}  // namespace

Run add_render(CLI::App& app) {
  auto opt = std::make_shared<RenderOptions>();
  auto* sub = app.add_subcommand("render", "Render a scene or mesh to PNG, shaded by normal and depth");
  sub->add_option("scene", opt->scene, "Mesh file, scene JSON, or 'default'")->required();
  sub->add_option("--out,-o", opt->out, "Output PNG")->required();
  sub->add_option("--method,-m", opt->method, "Method")->capture_default_str();
  sub->add_option("--builder", opt->builder, "BVH builder: sah or median")->check(CLI::IsMember({"sah", "median"}));
  sub->add_option("--width", opt->width, "Image width (default: the camera's)")->check(CLI::Range(1, 16384));
  sub->add_option("--height", opt->height, "Image height (default: the camera's)")->check(CLI::Range(1, 16384));
  sub->add_option("--threads,-j", opt->threads, "Threads (0: all)");
  sub->add_flag("--verify", opt->verify, "Compare every pixel's first hit with the exact method");
  sub->add_option("--verify-out", opt->verify_out, "Verification image (default: OUT-verify.png)");
  sub->add_flag("--light", opt->light, "Direct lighting from the scene's disk lights (shadow rays)");
  sub->add_option("--shadow-rays", opt->shadow_rays, "--light: shadow rays per pixel")->check(CLI::Range(1, 1024))
      ->capture_default_str();
  sub->add_option("--estimator", opt->estimator, "--light: area or solid-angle")
      ->check(CLI::IsMember({"area", "solid-angle"}))->capture_default_str();
  sub->add_option("--spawn", opt->spawn, "--light: shadow ray origins: none, epsilon, error-bounded, certified")
      ->check(CLI::IsMember({"none", "epsilon", "error-bounded", "certified"}))->capture_default_str();
  sub->add_option("--epsilon", opt->epsilon, "--light: the epsilon strategy's offset")
      ->check(CLI::Range(0.0, 1e30))->capture_default_str();
  sub->add_option("--seed", opt->seed, "--light: seed of the light samples")->capture_default_str();
  sub->add_flag("--verbose,-v", opt->verbose, "Say on stderr what was loaded and which reader read it");
  return [opt] { return run_render(*opt); };
}

}  // namespace rayproof::cli
