// rayproof advise: the scene analysis on hand-built meshes with known counts,
// advise on the default scene and a CGAL mesh at small ray counts, the sentences from known
// tallies, the JSON fields, and bad input.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>

#include "cli/advise_text.h"
#include "registry/registry.h"
#include "scene/advise.h"
#include "scene/analysis.h"
#include "tests/cli_support.h"

namespace rayproof {
namespace {

using scene::analyse_scene;
using scene::Scene;

/// A unit cube: 8 vertices, 12 triangles, closed.
mesh::Mesh cube(double scale = 1) {
  mesh::Mesh m;
  for (int i = 0; i < 8; ++i) m.vertices.push_back({scale * (i & 1), scale * ((i >> 1) & 1), scale * ((i >> 2) & 1)});
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

Scene scene_of(const mesh::Mesh& m) {
  Scene s;
  scene::add_mesh(s, m);
  return s;
}

TEST(AdviseAnalysis, CubeIsClosed) {
  const auto a = analyse_scene(scene_of(cube()));
  EXPECT_EQ(a.vertices, 8u);
  EXPECT_EQ(a.triangles, 12u);
  EXPECT_EQ(a.edges, 18u);
  EXPECT_EQ(a.open_edges, 0u);
  EXPECT_EQ(a.non_manifold_edges, 0u);
  EXPECT_EQ(a.components, 1u);
  EXPECT_EQ(a.closed_components, 1u);
  EXPECT_EQ(a.degenerate, 0u);
  EXPECT_EQ(a.slivers, 0u);
  EXPECT_NEAR(a.max_aspect, 2.0, 1e-12);  // a right isosceles half-square: diagonal^2 / (2 area) = 2
  EXPECT_EQ(a.welded, 0u);
  EXPECT_TRUE(a.all_float());
  EXPECT_TRUE(a.triangle_only());
  EXPECT_EQ(a.max_abs, 1.0);
  EXPECT_EQ(a.min_abs, 1.0);
  EXPECT_EQ(a.spread_binades, 0);
  EXPECT_EQ(a.zero_coordinates, 12u);
}

TEST(AdviseAnalysis, CubeWithAFaceRemovedIsOpen) {
  mesh::Mesh m = cube();
  m.triangles.erase(m.triangles.begin(), m.triangles.begin() + 2);  // the z = 0 face
  const auto a = analyse_scene(scene_of(m));
  EXPECT_EQ(a.open_edges, 4u);
  EXPECT_EQ(a.non_manifold_edges, 0u);
  EXPECT_EQ(a.components, 1u);
  EXPECT_EQ(a.closed_components, 0u);
}

TEST(AdviseAnalysis, TwoCubesAndAnUnweldedCopy) {
  // Two disjoint cubes, the second with every triangle's own vertices (as STL files store them):
  // welding by position makes it closed too.
  mesh::Mesh m = cube();
  const mesh::Mesh c = cube();
  for (const auto& t : c.triangles) {
    const auto base = std::uint32_t(m.vertices.size());
    for (int k = 0; k < 3; ++k) m.vertices.push_back(c.vertices[t[k]] + Vec3<double>{3, 0, 0});
    m.triangles.push_back({base, base + 1, base + 2});
  }
  const auto a = analyse_scene(scene_of(m));
  EXPECT_EQ(a.welded, 36u - 8u);
  EXPECT_EQ(a.components, 2u);
  EXPECT_EQ(a.closed_components, 2u);
  EXPECT_EQ(a.open_edges, 0u);
  EXPECT_EQ(a.max_abs, 4.0);
  const auto meshes = scene::closed_component_meshes(scene_of(m), a);
  ASSERT_EQ(meshes.size(), 2u);
  EXPECT_EQ(meshes[0].vertices.size(), 8u);
  EXPECT_EQ(meshes[1].vertices.size(), 36u);  // not welded: its own vertices
  EXPECT_EQ(meshes[1].triangles.size(), 12u);
  EXPECT_EQ(scene::closed_component_meshes(scene_of(m), a, 1).size(), 1u);
}

TEST(AdviseAnalysis, NonManifoldFan) {
  // Three triangles on the edge (0,0,0)-(1,0,0): that edge is non-manifold, the other 6 are open.
  mesh::Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}};
  m.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 1, 4}};
  const auto a = analyse_scene(scene_of(m));
  EXPECT_EQ(a.edges, 7u);
  EXPECT_EQ(a.non_manifold_edges, 1u);
  EXPECT_EQ(a.open_edges, 6u);
  EXPECT_EQ(a.components, 1u);
  EXPECT_EQ(a.closed_components, 0u);
}

TEST(AdviseAnalysis, DegenerateAndSliverTriangles) {
  mesh::Mesh m;
  // 0-2: collinear, exactly (p2 = 2 p1 in doubles: 2 * 0.1 is the double 0.2); 3-5: 2^-40 off the
  // line, not degenerate but a sliver; 6-8: a repeated vertex; 9-11: a sliver of aspect 10^6.
  m.vertices = {{0, 0, 0}, {0.1, 0.2, 0.3}, {0.2, 0.4, 0.6},
                {0, 0, 0}, {1, 1, 1}, {2, 2, 2 + 0x1p-40},
                {0, 0, 0}, {0, 0, 0}, {1, 0, 0},
                {0, 0, 0}, {1, 0, 0}, {0.5, 1e-6, 0}};
  m.triangles = {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}, {9, 10, 11}};
  const auto a = analyse_scene(scene_of(m), 1000);
  EXPECT_EQ(a.degenerate, 2u);
  EXPECT_EQ(a.slivers, 2u);
  EXPECT_GT(a.max_aspect, 1e12);
  EXPECT_EQ(a.undecided, 0u);
  EXPECT_EQ(scene::collinear_exact({0, 0, 0}, {0.1, 0.2, 0.3}, {0.2, 0.4, 0.6}), true);
  EXPECT_EQ(scene::collinear_exact({0, 0, 0}, {1, 1, 1}, {2, 2, 2 + 0x1p-40}), false);
  // Tiny and huge triangles: their products would underflow or overflow in place; scaled, decided.
  EXPECT_EQ(scene::collinear_exact({0, 0, 0}, {1e-300, 0, 0}, {0, 1e-300, 0}), false);
  EXPECT_EQ(scene::collinear_exact({1e-300, 1e-300, 0}, {2e-300, 2e-300, 0}, {3e-300, 3e-300, 0}), true);
  EXPECT_EQ(scene::collinear_exact({1e300, 0, 0}, {0, 1e300, 0}, {0, 0, 1e300}), false);
  EXPECT_EQ(scene::collinear_exact({1e300, 1e300, 1e300}, {-1e300, -1e300, -1e300}, {0, 0, 0}), true);
  // Cancellation: the double cross product of these is 0 or noise; exactly it is not zero.
  EXPECT_EQ(scene::collinear_exact({1, 1, 1}, {1 + 0x1p-52, 1 + 0x1p-52, 1}, {1 + 0x1p-51, 1 + 0x1p-51, 1 + 0x1p-52}), false);
  EXPECT_EQ(scene::collinear_exact({0, 0, 0}, {1, 1e-200, 0}, {1e200, 1, 0}), std::nullopt);  // spread beyond 2^400
  EXPECT_EQ(scene::collinear_exact({0, 0, 0}, {1, 0, 0}, {std::numeric_limits<double>::infinity(), 0, 0}), std::nullopt);
}

TEST(AdviseAnalysis, CoordinatesNotFloatsAndTheirSpread) {
  Scene s = scene_of(cube(0x1p-10));
  s.mesh.vertices[7] = {0x1p10, 0.1, 1};  // 0.1 is not a float; 2^10 and 2^-10 are
  s.spheres.push_back({{0, 0, 0.3}, 1});  // 0.3 is not a float
  const auto a = analyse_scene(s);
  EXPECT_EQ(a.non_float_vertices, 1u);
  EXPECT_EQ(a.non_float_analytic, 1u);
  EXPECT_FALSE(a.all_float());
  EXPECT_FALSE(a.triangle_only());
  EXPECT_EQ(a.spheres, 1u);
  EXPECT_EQ(a.max_abs, 0x1p10);
  EXPECT_EQ(a.min_abs, 0x1p-10);
  EXPECT_EQ(a.spread_binades, 20);
}

scene::AdviseOptions small_options() {
  scene::AdviseOptions o;
  o.rays = 600, o.slow_rays = 40, o.exact_sample = 25, o.threads = 2, o.max_timing_runs = 3;
  return o;
}

/// The structure every advise result must have.
void expect_consistent(const scene::AdviseResult& r) {
  EXPECT_EQ(r.exact_checked, r.exact_agree);
  EXPECT_GT(r.exact_checked, 0u);
  std::uint64_t all_rays = 0;
  for (const auto& s : r.sets) all_rays += s.rays;
  bool saw_certified = false;
  for (const auto& m : r.methods) {
    std::uint64_t by_set = 0;
    for (const auto& [set, n] : m.errors_by_set) by_set += n;
    EXPECT_EQ(by_set, m.errors()) << m.name;
    if (m.compiled) {
      EXPECT_EQ(m.rays, all_rays) << m.name;
    }
    if (m.name == "certified") {
      saw_certified = true;
      EXPECT_EQ(m.errors(), 0u);
    }
    // robust promises no false miss ahead of the origin on triangles: no leak.
    if (m.name == "robust" || m.name == "watertight" || m.name == "watertight-float") {
      EXPECT_EQ(m.leaks, 0u) << m.name;
    }
  }
  EXPECT_TRUE(saw_certified);
  ASSERT_TRUE(r.recommended.has_value());
  const auto it = std::find_if(r.methods.begin(), r.methods.end(), [&](const auto& m) { return m.name == *r.recommended; });
  ASSERT_NE(it, r.methods.end());
  EXPECT_TRUE(it->error_free());
  EXPECT_TRUE(it->compiled);
}

TEST(Advise, DefaultScene) {
  const Scene s = scene::default_scene();
  const auto r = scene::advise(s, registry::all_methods(), small_options());
  std::vector<std::string> names;
  for (const auto& set : r.sets) names.push_back(set.name);
  EXPECT_EQ(names, (std::vector<std::string>{"primary", "leak", "random", "shadow"}));
  expect_consistent(r);
  EXPECT_TRUE(r.kind_cost.empty());  // not triangle-only
  EXPECT_GT(r.paths.certified_tests[1], 0u);  // spheres were tested
  // Registry methods for triangles only have no code for the default scene's other kinds.
  for (const auto& m : r.methods)
    if (m.name == "plucker") {
      EXPECT_EQ(m.unsupported, (std::vector<std::string>{"sphere", "ellipsoid", "disk", "box"}));
    }
}

#ifdef RAYPROOF_CGAL_MESHES
TEST(Advise, CgalBunny) {
  const Scene s = scene::load_scene(std::string(RAYPROOF_CGAL_MESHES) + "/bunny00.off");
  auto o = small_options();
  o.compare_kinds = false;
  o.methods = {"float", "robust", "certified"};
  const auto r = scene::advise(s, registry::all_methods(), o);
  EXPECT_EQ(r.analysis.closed_components, 1u);
  EXPECT_EQ(r.sets.size(), 3u);
  expect_consistent(r);
  EXPECT_EQ(r.paths.certified_tests[1], 0u);  // no sphere
}
#endif

TEST(Advise, TriangleOnlyKindCost) {
  auto o = small_options();
  o.methods = {"float", "certified"};
  o.kind_cost_rays = 3000;
  const auto r = scene::advise(scene_of(cube()), registry::all_methods(), o);
  ASSERT_EQ(r.kind_cost.size(), 3u);
  for (const auto& k : r.kind_cost) EXPECT_TRUE(k.triangles_only > 0 && k.with_sphere > 0) << k.method;
  EXPECT_EQ(r.random_rays_for_kind_cost, 3000u);
  expect_consistent(r);
}

TEST(Advise, ExtremeMagnitudes) {
  // A cube at 1e300 (cubes of coordinates overflow: the leak rays' centroid is computed scaled) and
  // one at 1e-300 (below float: robust sees degenerate triangles, certified falls back to GMP).
  auto o = small_options();
  o.rays = 200, o.methods = {"robust", "certified"}, o.compare_kinds = false;
  const auto big = scene::advise(scene_of(cube(1e300)), registry::all_methods(), o);
  ASSERT_EQ(big.sets.size(), 3u);
  EXPECT_EQ(big.sets[1].name, "leak");
  EXPECT_EQ(big.sets[1].invalid, 0u);
  EXPECT_EQ(big.sets[1].reference_hits, big.sets[1].rays);
  EXPECT_EQ(big.exact_checked, big.exact_agree);
  const auto tiny = scene::advise(scene_of(cube(1e-300)), registry::all_methods(), o);
  EXPECT_EQ(tiny.sets[1].reference_hits, tiny.sets[1].rays);
  EXPECT_EQ(tiny.paths.robust_degenerate, tiny.paths.robust_tests);
  EXPECT_GT(tiny.paths.certified_fallbacks[0], 0u);
  EXPECT_EQ(tiny.exact_checked, tiny.exact_agree);
  const auto s = cli::advise_sentences(big);
  EXPECT_NE(std::find(s.begin(), s.end(),
                      "Some coordinates are beyond float's range (3.4e38): float methods see infinities there, and the "
                      "BVH's bounds (floats, rounded outward) are infinite."),
            s.end());
}

TEST(Advise, EmptySceneAndUnknownMethod) {
  EXPECT_THROW((void)scene::advise(Scene{}, registry::all_methods(), small_options()), scene::SceneError);
  auto o = small_options();
  o.methods = {"no-such-method"};
  EXPECT_THROW((void)scene::advise(scene_of(cube()), registry::all_methods(), o), scene::SceneError);
}

/// A result built by hand: known tallies.
scene::AdviseResult known() {
  scene::AdviseResult r;
  auto& a = r.analysis;
  a.vertices = 8, a.triangles = 12, a.edges = 18, a.components = 1, a.closed_components = 1;
  a.max_aspect = 2, a.sliver_aspect = 1000, a.min_abs = 1, a.max_abs = 1, a.coordinates = 24, a.zero_coordinates = 12;
  r.sets = {{"primary", 100, 60}, {"leak", 26, 26}, {"random", 100, 55, 2}};
  r.leak_components = 1;
  r.exact_checked = 30, r.exact_agree = 30;
  scene::MethodTally f;
  f.name = "float", f.compiled = true, f.float_precision = true, f.promise = "nothing";
  f.rays = 226, f.leak_rays = 26, f.leaks = 3, f.false_hits = 1, f.leak_wrong_prims = 2, f.max_ulps = 7;
  f.seconds = 226 / 4e6;
  f.errors_by_set = {{"leak", 5}, {"random", 1}};
  scene::MethodTally w = f;
  w.name = "watertight", w.float_precision = false, w.leaks = 0, w.false_hits = 0, w.leak_wrong_prims = 1;
  w.errors_by_set = {{"leak", 1}};
  w.seconds = 226 / 3e6;
  scene::MethodTally c;
  c.name = "certified", c.compiled = true, c.promise = "exact class, t within 1 ulp", c.tolerance = 1;
  c.rays = 226, c.leak_rays = 26, c.seconds = 226 / 1e6;
  r.methods = {f, w, c};
  r.recommended = "certified", r.recommended_except_grazes = "watertight";
  r.same_point = 0x1p-20;
  r.paths.rays = 50, r.paths.certified_tests[0] = 400, r.paths.certified_fallbacks[0] = 3;
  r.paths.robust_tests = 410;
  r.kind_cost = {{"float", 4.0, 3.0, 5, 4.04}, {"robust", 3.0, 3.06, 5, 3.0}};
  r.random_rays_for_kind_cost = 20000;
  return r;
}

TEST(AdviseText, SentencesFromKnownTallies) {
  const auto s = cli::advise_sentences(known());
  const std::vector<std::string> want = {
      "The scene has 12 triangles (8 vertices) and no analytic primitive; no camera (a default view is used), no light.",
      "No triangle has zero area (decided exactly).",
      "No triangle is a sliver (longest edge over its altitude above 1000); the largest ratio is 2.",
      "Of 18 edges, 0 open (one triangle) and 0 non-manifold (three or more triangles).",
      "1 connected component, 1 of them closed (every edge shared by exactly two triangles).",
      "Nonzero coordinates range from 1 to 1 in magnitude (0 binades); 12 of 24 are zero.",
      "Every coordinate is exactly a float: float methods see the scene as it is.",
      "Rays: 100 primary (60 hit by `certified`), 26 leak (26 hit by `certified`) from inside 1 closed component toward "
      "vertices and edge midpoints and 100 random (55 hit by `certified`, 2 invalid: a non-finite origin or direction).",
      "`certified` is the reference (proven equal to exact); checked against `exact` on 30 rays, it agreed on all.",
      "An error below is a leak, a false hit, a false miss or a wrong primitive against `certified`, or a t beyond what "
      "the method promises (a method that promises nothing about t: its largest t error is shown, not counted); another "
      "class on the right primitive (interior for edge) and another primitive at the same point (hit points within "
      "9.54e-07 along the ray: a neighbour at a shared edge or vertex) are counted apart, not as errors. A graze is a "
      "wrong primitive on a leak ray: aimed exactly at a vertex or edge midpoint, the ray grazes the surface there, and "
      "a hair's difference hits another surface.",
      "`float` made 6 errors on 226 rays: 3 of 26 leak rays leaked, 1 false hit and 2 wrong primitives on leak rays "
      "(grazes) (by ray set: 5 leak and 1 random).",
      "`watertight` made 1 error on 226 rays: 1 wrong primitive on leak rays (grazes) (by ray set: 1 leak).",
      "The cheapest method with no error on this scene is `certified` at 1 Mrays/s: every faster compiled method made an error.",
      "Not counting grazes, the cheapest is `watertight` at 3 Mrays/s (1 graze on leak rays).",
      "`watertight` promises nothing: it made no such error on these rays, but other rays may find one; for a guarantee "
      "use `robust` (no false miss on triangles ahead of the origin, nor on boxes) or `certified` (exact class, t within "
      "1 ulp).",
      "`certified` needs the certified tier (rayproof::scene_certified: GMP and MPFR).",
      "The scene has no spheres, ellipsoids, disks and boxes: their kernels are never run on it.",
      "On a sample of 50 rays, `certified` ran 400 triangle tests: its floating-point filter decided 397 and the exact "
      "(GMP) fallback 3.",
      "`robust` ran 410 triangle tests on the same sample; its special cases (a triangle degenerate in float, a ray "
      "parallel to a triangle's plane) were never reached.",
      "Triangle-only, then the same triangles plus one sphere, then triangle-only again (20000 random rays, best of 5 "
      "runs): `float` 4 Mrays/s, 3 with it (-25.0%), 4.04 again and `robust` 3 Mrays/s, 3.06 with it (+2.0%), 3 "
      "again.",
      "One sphere more slows `float` by 25.0% (against the slower of its two triangle-only series), beyond these "
      "timings' noise (5.0%): leaving the other kinds out saves about that here.",
  };
  ASSERT_EQ(s.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(s[i], want[i]) << i;
}

TEST(AdviseText, SentencesThatChangeWithTheNumbers) {
  auto r = known();
  r.exact_agree = 28;
  r.kind_cost = {{"float", 4.0, 3.9, 5, 4.0}, {"robust", 3.0, 3.6, 5, 3.0}};  // -2.5% and +20%: noise
  r.recommended = "watertight", r.recommended_except_grazes = "watertight";
  r.methods[1].leak_wrong_prims = 0;
  r.analysis.non_float_vertices = 3, r.analysis.degenerate = 1, r.analysis.slivers = 2, r.analysis.open_edges = 4;
  r.t_tolerance = 4;
  const auto s = cli::advise_sentences(r);
  auto has = [&](const std::string& want) { return std::find(s.begin(), s.end(), want) != s.end(); };
  EXPECT_TRUE(has("1 triangle of 12 have zero area (collinear vertices, decided exactly)."));
  EXPECT_TRUE(has("2 triangles are slivers (longest edge over its altitude above 1000); the largest ratio is 2."));
  EXPECT_TRUE(has("Of 18 edges, 4 open (one triangle) and 0 non-manifold (three or more triangles)."));
  EXPECT_TRUE(has("3 of 8 vertices and 0 of the analytic primitives have a coordinate that is not a float: float methods "
                  "answer for the scene rounded to float."));
  EXPECT_TRUE(has("`certified` is the reference (proven equal to exact); checked against `exact` on 30 rays, it agreed on "
                  "28. It disagreed on 2: the comparisons below are in doubt."));
  EXPECT_TRUE(has("No error on any ray compared: `watertight`."));
  EXPECT_TRUE(has("The cheapest method with no error on this scene is `watertight` at 3 Mrays/s (`certified`: 1 Mrays/s)."));
  r.methods[0].seconds = r.methods[1].seconds = 1;  // both now slower than certified: certified is the fastest
  r.recommended = "certified";
  EXPECT_EQ(cli::advise_sentences(r)[12], "The cheapest method with no error on this scene is `certified` at 1 Mrays/s, the "
                                          "fastest compiled method measured here.");
  r.methods[2].timing_runs = 3;
  EXPECT_EQ(cli::advise_sentences(r)[12], "The cheapest method with no error on this scene is `certified` at 1 Mrays/s (the "
                                          "fastest of 3 runs), the fastest compiled method measured here.");
  r.recommended = "watertight", r.methods[1].seconds = 226 / 3e6, r.methods[1].timing_runs = 3;
  EXPECT_EQ(cli::advise_sentences(r)[12], "The cheapest method with no error on this scene is `watertight` at 3 Mrays/s "
                                          "(`certified`: 1 Mrays/s; the fastest of 3 runs), the fastest compiled "
                                          "method measured here.");
  r.analysis.closed_components = 0, r.leak_components = 0;
  r.sets = {{"primary", 100, 7}, {"random", 100, 0}};
  EXPECT_EQ(cli::advise_sentences(r)[7], "Rays: 100 primary (7 hit by `certified`) and 100 random (0 hit by `certified`) "
                                         "(no closed component: no leak rays).");
  EXPECT_TRUE(has("`watertight` needs no exact arithmetic: GMP, MPFR and CGAL are not needed for this scene's queries."));
  EXPECT_TRUE(has("No method is slower with one sphere more by more than these timings' noise (20.0%: the largest of 5%, "
                  "the triangle-only scene against itself and any speed-up with the sphere): leaving the other kinds out "
                  "saves nothing measurable here."));
  r.kind_cost = {{"float", 4.0, 3.0, 5, 3.0}};  // -25%, but the triangle-only scene also moved by 25%
  EXPECT_EQ(cli::advise_sentences(r).back(),
            "No method is slower with one sphere more by more than these timings' noise (25.0%: the largest of 5%, the "
            "triangle-only scene against itself and any speed-up with the sphere): leaving the other kinds out saves "
            "nothing measurable here.");
  for (const auto& x : s) EXPECT_EQ(x.find("Not counting grazes"), std::string::npos) << x;
  r.exact_checked = r.exact_agree = 0;
  EXPECT_EQ(cli::advise_sentences(r)[8], "`certified` is the reference (proven equal to exact); no ray was checked against "
                                         "`exact` (--exact-sample 0).");
  EXPECT_NE(s[9].find("(else beyond 4 ulps of its precision)"), std::string::npos) << s[9];
}

TEST(AdviseText, JsonHasTheSameContent) {
  const auto r = known();
  const auto j = nlohmann::json::parse(cli::advise_json(r, "cube.off"));
  EXPECT_EQ(j["scene"], "cube.off");
  EXPECT_EQ(j["analysis"]["closed_components"], 1);
  EXPECT_EQ(j["analysis"]["edges"], 18);
  EXPECT_EQ(j["ray_sets"].size(), 3u);
  EXPECT_EQ(j["ray_sets"][1]["name"], "leak");
  EXPECT_EQ(j["reference"]["exact_checked"], 30);
  ASSERT_EQ(j["methods"].size(), 3u);
  EXPECT_EQ(j["methods"][0]["name"], "float");
  EXPECT_EQ(j["methods"][0]["leaks"], 3);
  EXPECT_EQ(j["methods"][0]["false_hits"], 1);
  EXPECT_EQ(j["methods"][0]["wrong_primitives_on_leak_rays"], 2);
  EXPECT_EQ(j["methods"][0]["errors"], 6);
  EXPECT_EQ(j["methods"][0]["errors_by_set"]["leak"], 5);
  EXPECT_EQ(j["methods"][0]["errors_by_set"]["random"], 1);
  EXPECT_EQ(j["methods"][0]["error_free"], false);
  EXPECT_EQ(j["methods"][1]["error_free_except_grazes"], true);
  EXPECT_EQ(j["methods"][0]["tolerance_ulps"], nullptr);
  EXPECT_EQ(j["methods"][2]["tolerance_ulps"], 1);
  EXPECT_NEAR(j["methods"][0]["mrays_per_s"].get<double>(), 4.0, 1e-9);
  EXPECT_EQ(j["paths"]["certified"]["triangle"]["exact_fallbacks"], 3);
  EXPECT_EQ(j["kind_cost"].size(), 2u);
  EXPECT_EQ(j["recommended"], "certified");
  EXPECT_EQ(j["recommended_except_grazes"], "watertight");
  EXPECT_EQ(j["methods"][0]["timing_runs"], 1);
  EXPECT_EQ(j["ray_sets"][2]["invalid"], 2);
  EXPECT_EQ(j["ray_sets"][2]["reference_hits"], 55);
  EXPECT_EQ(j["same_point_distance"], 0x1p-20);
  EXPECT_EQ(j["sentences"], nlohmann::json(cli::advise_sentences(r)));
}

TEST(AdviseCli, BadInput) {
  using testing::run_rayproof;
  auto r = run_rayproof("advise /nonexistent/mesh.off -q");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("rayproof advise: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/nonexistent/mesh.off"), std::string::npos) << r.err;
  const auto bad = testing::write_file("advise_bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n");
  r = run_rayproof("advise " + bad.string() + " -q");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("advise_bad.off"), std::string::npos) << r.err;
  const auto empty_off = testing::write_file("advise_empty.off", "OFF\n0 0 0\n");
  r = run_rayproof("advise " + empty_off.string() + " -q");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("advise_empty.off: no triangles"), std::string::npos) << r.err;
  const auto empty = testing::write_file("advise_empty.json", "{}\n");
  r = run_rayproof("advise " + empty.string() + " -q");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("the scene is empty"), std::string::npos) << r.err;
  for (const char* n : {"0", "1000000000000"}) {
    r = run_rayproof(std::string("advise default -q --rays ") + n);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--rays must be between 1 and 100000000"), std::string::npos) << r.err;
  }
  r = run_rayproof("advise default -q --sliver-aspect nan");
  EXPECT_EQ(r.status, 2);
  r = run_rayproof("advise default --methods nope -q");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("unknown method 'nope'"), std::string::npos) << r.err;
}

TEST(AdviseCli, JsonOnTheDefaultScene) {
  const auto r = testing::run_rayproof("advise default --rays 300 --slow-rays 20 --exact-sample 10 --methods "
                                       "float,robust,certified --json -q -j 2");
  ASSERT_EQ(r.status, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["methods"].size(), 3u);
  EXPECT_EQ(j["ray_sets"].size(), 4u);
  EXPECT_TRUE(j["recommended"].is_string());
  EXPECT_EQ(j["reference"]["exact_checked"], j["reference"]["exact_agree"]);
}

}  // namespace
}  // namespace rayproof
