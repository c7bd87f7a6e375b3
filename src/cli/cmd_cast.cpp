/// rayproof cast SCENE RAYS [--method M] [--query closest|any|all]: one result line per ray.
///   closest: `CLASS T PRIM` or `miss - -`;  any: `hit` or `miss`;
///   all: every crossing `CLASS T PRIM ...` sorted by t, or `miss - -`;
///   crossings (a mesh file): `N t:in|out ...`, each crossing once (cli/cast_crossings.h).
/// A ray line is `ox oy oz dx dy dz` (# comments); a bad line is named on stderr and answered
/// `error - -`; a ray with a NaN or infinite component or d = 0 is `invalid - -`.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <cstdio>
#include <memory>
#include <string>

#include "cli/cast_crossings.h"
#include "cli/commands.h"
#include "cli/input.h"
#include "registry/registry.h"
#include "cli/scene_input.h"
#include "scene/ray_file.h"

namespace rayproof::cli {

namespace {
struct CastOptions {
  std::string scene, rays, method = "double", query = "closest", builder = "sah";
  int threads = 0;
  double tmin = 0, tmax = std::numeric_limits<double>::infinity();
  bool verbose = false;
  bool touches = false;  ///< --query crossings: print the touches too
};

std::string format_hit(const CastHit& h) {
  if (!h.hit()) return std::string(to_string(h.contact)) + " - -";
  return fmt::format("{} {} {}", to_string(h.contact), io::format_double(h.t), h.triangle);
}

int run_cast(const CastOptions& opt) {
  if (opt.query == "crossings")
    return run_cast_crossings({opt.scene, opt.rays, opt.tmin, opt.tmax, opt.touches, opt.verbose, opt.threads});
  if (opt.touches) {
    fmt::print(stderr, "rayproof cast: --touches goes with --query crossings\n");
    return 2;
  }
  const auto loaded = load_scene_for_cli("cast", opt.scene, opt.method, opt.builder, opt.verbose);
  if (!loaded) return 2;
  Input in = open_input(opt.rays);
  if (!in.stream) {
    fmt::print(stderr, "rayproof cast: {}\n", in.error);
    return 2;
  }
  std::vector<Ray<double>> rays;
  std::vector<std::string> errors;  // per ray line: empty, or the message
  try {
    for (auto& r : scene::read_rays(*in.stream, opt.rays)) rays.push_back(r.ray), errors.push_back(std::move(r.error));
  } catch (const scene::SceneError& e) {
    fmt::print(stderr, "rayproof cast: {}\n", e.what());
    return 2;
  }
  if (rays.empty()) {
    fmt::print(stderr, "rayproof cast: {}: no rays (expected lines 'ox oy oz dx dy dz')\n", opt.rays);
    return 2;
  }
  const SceneCaster& caster = *loaded->caster;
  const TRange q{opt.tmin, opt.tmax};
  std::string out;
  int bad = 0;
  std::vector<CastHit> hits;
  std::vector<std::uint8_t> any;
  if (opt.query == "closest") hits.resize(rays.size()), caster.closest(rays, hits, opt.threads, q);
  if (opt.query == "any") any.resize(rays.size()), caster.any(rays, any, opt.threads, q);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    if (!errors[i].empty()) {
      fmt::print(stderr, "rayproof cast: {}\n", errors[i]);
      out += "error - -\n";
      ++bad;
      continue;
    }
    if (!rays[i].valid()) {
      out += "invalid - -\n";
    } else if (opt.query == "closest") {
      out += format_hit(hits[i]) + "\n";
    } else if (opt.query == "any") {
      out += any[i] ? "hit\n" : "miss\n";
    } else {
      const auto all = caster.all(rays[i], q);
      if (all.empty()) out += "miss - -";
      for (std::size_t k = 0; k < all.size(); ++k) out += (k ? " " : "") + format_hit(all[k]);
      out += "\n";
    }
    if (out.size() > (1 << 16)) std::fwrite(out.data(), 1, out.size(), stdout), out.clear();
  }
  std::fwrite(out.data(), 1, out.size(), stdout);
  if (bad) fmt::print(stderr, "rayproof cast: {} line(s) could not be read\n", bad);
  return bad ? 1 : 0;
}
}  // namespace

Run add_cast(CLI::App& app) {
  auto opt = std::make_shared<CastOptions>();
  auto* sub = app.add_subcommand("cast", "Cast rays into a scene or mesh: one result line per ray");
  sub->add_option("scene", opt->scene, "Mesh file (.off .obj .ply .stl .gltf .glb), scene JSON, or 'default'")->required();
  sub->add_option("rays", opt->rays, "Ray file (ox oy oz dx dy dz per line), or - for standard input")->required();
  sub->add_option("--method,-m", opt->method, "Method: any registry method (float, double, cramer-*, watertight*, robust and certified run compiled BVH kernels)")
      ->capture_default_str();
  sub->add_option("--query,-q", opt->query, "closest, any, all or crossings (a mesh's crossings, each once, with direction)")
      ->check(CLI::IsMember({"closest", "any", "all", "crossings"}))
      ->capture_default_str();
  sub->add_option("--builder", opt->builder, "BVH builder: sah or median")
      ->check(CLI::IsMember({"sah", "median"}))
      ->capture_default_str();
  sub->add_option("--threads,-j", opt->threads, "Threads (0: all)")->capture_default_str();
  sub->add_option("--tmin", opt->tmin, "Smallest t counted")->capture_default_str();
  sub->add_option("--tmax", opt->tmax, "Largest t counted");
  sub->add_flag("--touches", opt->touches, "With --query crossings: also the touches (silhouette edges, vertices, faces along the ray)");
  sub->add_flag("--verbose,-v", opt->verbose, "Say on stderr what was loaded and which reader read it");
  return [opt] { return run_cast(*opt); };
}

}  // namespace rayproof::cli
