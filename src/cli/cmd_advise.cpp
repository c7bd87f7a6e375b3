/// rayproof advise SCENE: what a scene needs. Its geometry (degenerate and sliver triangles, open
/// and non-manifold edges, closed components, coordinate magnitudes, float representability,
/// analytic kinds); its own rays (primary, leak, random, shadow) cast with every method and compared
/// with `certified`, a sample checked against `exact`; the cheapest method that made no error; what
/// the scene does not need (kinds, fallback paths never reached); and, for a triangle-only scene,
/// its speed against the same triangles plus one sphere.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <memory>

#include "cli/advise_text.h"
#include "cli/commands.h"
#include "registry/registry.h"
#include "cli/scene_input.h"
#include "scene/advise.h"

namespace rayproof::cli {

namespace {

struct AdviseCliOptions {
  std::string scene;
  scene::AdviseOptions opt;
  std::string methods;
  bool json = false, quiet = false, no_kind_cost = false;
  std::uint64_t t_ulps = 0;
};

int run_advise(AdviseCliOptions& o) {
  if (o.opt.rays == 0 || o.opt.rays > 100000000) {
    fmt::print(stderr, "rayproof advise: --rays must be between 1 and 100000000\n");
    return 2;
  }
  if (!(o.opt.sliver_aspect > 1)) {
    fmt::print(stderr, "rayproof advise: --sliver-aspect must be above 1\n");
    return 2;
  }
  for (std::size_t p = 0; p <= o.methods.size() && !o.methods.empty();) {
    const std::size_t q = std::min(o.methods.find(',', p), o.methods.size());
    if (q > p) o.opt.methods.push_back(o.methods.substr(p, q - p));
    p = q + 1;
  }
  o.opt.compare_kinds = !o.no_kind_cost;
  if (o.t_ulps) o.opt.t_tolerance = o.t_ulps;
  if (!o.quiet) o.opt.progress = [](const std::string& line) { fmt::print(stderr, "advise: {}\n", line); };
  try {
    if (!o.quiet) fmt::print(stderr, "advise: loading {}{}\n", o.scene, reader_note(o.scene));
    const auto s = std::make_unique<scene::Scene>(o.scene == "default" ? scene::default_scene() : scene::load_scene(o.scene));
    const scene::AdviseResult r = scene::advise(*s, registry::all_methods(), o.opt);
    if (o.json) {
      fmt::print("{}\n", advise_json(r, o.scene));
      return 0;
    }
    fmt::print("rayproof advise {}\n\n", o.scene);
    for (const auto& line : geometry_sentences(r.analysis)) fmt::print("{}\n", line);
    fmt::print("\n{}\n", advise_table(r));
    const auto all = advise_sentences(r);
    for (std::size_t i = geometry_sentences(r.analysis).size(); i < all.size(); ++i) fmt::print("{}\n", all[i]);
    fmt::print("\n({:.1f} s)\n", r.seconds);
    return 0;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rayproof advise: {}\n", e.what());
    return 2;
  }
}

}  // namespace

Run add_advise(CLI::App& app) {
  auto o = std::make_shared<AdviseCliOptions>();
  auto* sub = app.add_subcommand("advise", "What a scene needs: its geometry, its rays with every method, the cheapest error-free method");
  sub->add_option("scene", o->scene, "Mesh file (.off .obj .ply .stl .gltf .glb), scene JSON, or 'default'")->required();
  sub->add_option("--rays", o->opt.rays, "Rays per set (primary, leak, random, shadow)")->capture_default_str();
  sub->add_option("--seed", o->opt.seed, "Seed of the random and shadow rays")->capture_default_str();
  sub->add_option("--threads,-j", o->opt.threads, "Threads (0: all)")->capture_default_str();
  sub->add_flag("--json", o->json, "Print the result as JSON (same content)");
  sub->add_option("--methods", o->methods, "Comma-separated methods (default: every compiled and registry method but exact)");
  sub->add_option("--slow-rays", o->opt.slow_rays, "Rays per set for registry (non-compiled) methods and the path counts")
      ->capture_default_str();
  sub->add_option("--exact-sample", o->opt.exact_sample, "Rays per set checked against exact")->capture_default_str();
  sub->add_option("--sliver-aspect", o->opt.sliver_aspect, "A sliver: longest edge over its altitude above this")
      ->capture_default_str();
  sub->add_option("--t-ulps", o->t_ulps, "Count t errors beyond N ulps as errors for methods that promise nothing about t (0: only report them)")
      ->capture_default_str();
  sub->add_flag("--no-kind-cost", o->no_kind_cost, "Skip the triangle-only against one-sphere-more timing");
  sub->add_flag("--quiet,-q", o->quiet, "No progress on stderr");
  return [o] { return run_advise(*o); };
}

}  // namespace rayproof::cli
