// The words of `rayproof advise` (see advise_text.h).
#include "cli/advise_text.h"

#include <fmt/core.h>

#include <cmath>
#include <nlohmann/json.hpp>

namespace rayproof::cli {

namespace {

/// "1 triangle", "3 triangles".
std::string count(std::uint64_t n, const std::string& one, const std::string& many) {
  return fmt::format("{} {}", n, n == 1 ? one : many);
}

/// "a", "a and b", "a, b and c".
std::string and_list(const std::vector<std::string>& v) {
  std::string s;
  for (std::size_t i = 0; i < v.size(); ++i) s += (i == 0 ? "" : i + 1 == v.size() ? " and " : ", ") + v[i];
  return s;
}

std::string mrays(double x) { return fmt::format("{:.3g}", x); }

const char* kKindNames[5] = {"triangle", "sphere", "ellipsoid", "disk", "box"};

}  // namespace

std::string advise_table(const scene::AdviseResult& r) {
  std::string s = fmt::format("{:<17} {:>8} {:>13} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>9} {:>9}  {}\n", "method", "rays",
                              "leaks", "graze", "f.hit", "f.miss", "w.prim", "w.class", "t>tol", "max ulps", "Mrays/s",
                              "promise");
  for (const auto& m : r.methods) {
    const std::string leaks = m.leak_rays ? fmt::format("{}/{}", m.leaks, m.leak_rays) : std::string("-");
    s += fmt::format("{:<17} {:>8} {:>13} {:>7} {:>7} {:>7} {:>7} {:>7} {:>7} {:>9} {:>9}  {}{}\n", m.name, m.rays, leaks,
                     m.leak_wrong_prims, m.false_hits, m.false_misses, m.wrong_prims, m.wrong_class,
                     fmt::format("{}", m.t_over), m.t_compared ? fmt::format("{:.3g}", double(m.max_ulps)) : "-",
                     mrays(m.mrays()), m.promise, m.name == "certified" ? " (reference)" : m.compiled ? "" : " (registry, sample)");
  }
  return s;
}

std::vector<std::string> geometry_sentences(const scene::SceneAnalysis& a) {
  std::vector<std::string> out;
  std::vector<std::string> kinds;
  if (a.spheres) kinds.push_back(count(a.spheres, "sphere", "spheres"));
  if (a.ellipsoids) kinds.push_back(count(a.ellipsoids, "ellipsoid", "ellipsoids"));
  if (a.disks) kinds.push_back(count(a.disks, "disk", "disks"));
  if (a.boxes) kinds.push_back(count(a.boxes, "box", "boxes"));
  out.push_back(fmt::format("The scene has {} ({}){}; {}, {}.", count(a.triangles, "triangle", "triangles"),
                            count(a.vertices, "vertex", "vertices"),
                            kinds.empty() ? std::string(" and no analytic primitive") : ", " + and_list(kinds),
                            a.has_camera ? "its own camera" : "no camera (a default view is used)",
                            a.lights ? count(a.lights, "light", "lights") : std::string("no light")));
  if (a.triangles) {
    out.push_back(a.degenerate ? fmt::format("{} of {} have zero area (collinear vertices, decided exactly).",
                                             count(a.degenerate, "triangle", "triangles"), a.triangles)
                               : std::string("No triangle has zero area (decided exactly)."));
    if (a.undecided)
      out.push_back(fmt::format("For {} it was not decided (a coordinate not finite, or coordinates more than 2^400 apart).",
                                count(a.undecided, "triangle", "triangles")));
    const std::string ratio = a.max_aspect > 0 ? fmt::format("; the largest ratio is {:.3g}", a.max_aspect) : "";
    out.push_back(a.slivers ? fmt::format("{} are slivers (longest edge over its altitude above {:g}){}.",
                                          count(a.slivers, "triangle", "triangles"), a.sliver_aspect, ratio)
                            : fmt::format("No triangle is a sliver (longest edge over its altitude above {:g}){}.",
                                          a.sliver_aspect, ratio));
    out.push_back(fmt::format("Of {}, {} open (one triangle) and {} non-manifold (three or more triangles).",
                              count(a.edges, "edge", "edges"), a.open_edges, a.non_manifold_edges));
    out.push_back(fmt::format("{}, {} of them closed (every edge shared by exactly two triangles){}.",
                              count(a.components, "connected component", "connected components"), a.closed_components,
                              a.welded ? fmt::format("; {} repeat the position of another and count as one",
                                                     count(a.welded, "vertex", "vertices"))
                                       : std::string()));
  }
  if (a.max_abs > 0)
    out.push_back(fmt::format("Nonzero coordinates range from {:.3g} to {:.3g} in magnitude ({}){}.", a.min_abs,
                              a.max_abs, count(std::uint64_t(a.spread_binades), "binade", "binades"),
                              a.zero_coordinates ? fmt::format("; {} of {} are zero", a.zero_coordinates, a.coordinates) : ""));
  else
    out.push_back(fmt::format("Every coordinate ({}) is zero.", a.coordinates));
  if (a.max_abs > 3.4028234663852886e38)
    out.push_back("Some coordinates are beyond float's range (3.4e38): float methods see infinities there, and the BVH's "
                  "bounds (floats, rounded outward) are infinite.");
  if (a.all_float())
    out.push_back("Every coordinate is exactly a float: float methods see the scene as it is.");
  else
    out.push_back(fmt::format("{} of {} and {} of the analytic primitives have a coordinate that is not a float: float "
                              "methods answer for the scene rounded to float.",
                              a.non_float_vertices, count(a.vertices, "vertex", "vertices"), a.non_float_analytic));
  return out;
}

std::vector<std::string> advise_sentences(const scene::AdviseResult& r) {
  std::vector<std::string> out = geometry_sentences(r.analysis);
  const auto& a = r.analysis;

  // The rays.
  std::vector<std::string> sets;
  for (const auto& s : r.sets) {
    std::string what = fmt::format("{} {} ({} hit by `certified`{})", s.rays, s.name, s.reference_hits,
                                   s.invalid ? fmt::format(", {} invalid: a non-finite origin or direction", s.invalid) : "");
    if (s.name == "leak")
      what += fmt::format(" from inside {} toward vertices and edge midpoints",
                          count(r.leak_components, "closed component", "closed components"));
    if (s.name == "shadow") what += " from a point on a light to each primary hit";
    sets.push_back(what);
  }
  out.push_back("Rays: " + and_list(sets) + (a.triangles && !a.closed_components ? " (no closed component: no leak rays)" : "") + ".");

  // The reference.
  if (r.exact_checked == 0)
    out.push_back("`certified` is the reference (proven equal to exact); no ray was checked against `exact` "
                  "(--exact-sample 0).");
  std::string ref = r.exact_checked == 0 ? std::string() : fmt::format("`certified` is the reference (proven equal to exact); checked against `exact` on {}, "
                                "it agreed on {}.",
                                count(r.exact_checked, "ray", "rays"), r.exact_checked == r.exact_agree ? std::string("all")
                                                                                                         : std::to_string(r.exact_agree));
  if (r.exact_checked != r.exact_agree)
    ref += fmt::format(" It disagreed on {}: the comparisons below are in doubt.", r.exact_checked - r.exact_agree);
  if (!ref.empty()) out.push_back(ref);
  if (r.reference_misses_on_leak_rays)
    out.push_back(fmt::format("`certified` itself finds no hit for {} of the leak rays: their origin (the volume centroid) "
                              "is not inside its component, so a method's miss there is no leak.",
                              r.reference_misses_on_leak_rays));

  // Per method.
  out.push_back(fmt::format(
      "An error below is a leak, a false hit, a false miss or a wrong primitive against `certified`, or a t beyond what "
      "the method promises{}; another class on the right primitive (interior for edge) and another primitive at the "
      "same point (hit points within {:.3g} along the ray: a neighbour at a shared edge or vertex) are counted apart, "
      "not as errors. A graze is a wrong primitive on a leak ray: aimed exactly at a vertex or edge midpoint, the ray "
      "grazes the surface there, and a hair's difference hits another surface.",
      r.t_tolerance ? fmt::format(" (else beyond {} of its precision)", count(*r.t_tolerance, "ulp", "ulps"))
                    : std::string(" (a method that promises nothing about t: its largest t error is shown, not counted)"),
      r.same_point));
  std::vector<std::string> clean;
  for (const auto& m : r.methods) {
    if (m.name == "certified") continue;
    if (!m.unsupported.empty()) {
      out.push_back(fmt::format("`{}` has no code for the scene's {} (it misses them): it cannot serve this scene.", m.name,
                                and_list(m.unsupported)));
      continue;
    }
    if (m.errors() == 0) {
      clean.push_back("`" + m.name + "`");
      continue;
    }
    std::vector<std::string> parts;
    if (m.leaks) parts.push_back(fmt::format("{} of {} leak rays leaked", m.leaks, m.leak_rays));
    if (m.false_hits) parts.push_back(count(m.false_hits, "false hit", "false hits"));
    if (m.false_misses) parts.push_back(count(m.false_misses, "false miss", "false misses"));
    if (m.wrong_prims) parts.push_back(count(m.wrong_prims, "wrong primitive", "wrong primitives"));
    if (m.leak_wrong_prims)
      parts.push_back(fmt::format("{} on leak rays (grazes)", count(m.leak_wrong_prims, "wrong primitive", "wrong primitives")));
    if (m.t_over)
      parts.push_back(fmt::format("{} with t beyond {} (up to {:.3g} {} ulps)", m.t_over, count(m.tolerance.value_or(0), "ulp", "ulps"),
                                  double(m.max_ulps), m.float_precision ? "float" : "double"));
    std::vector<std::string> where;
    for (const auto& [set, n] : m.errors_by_set) where.push_back(fmt::format("{} {}", n, set));
    out.push_back(fmt::format("`{}` made {} on {}{}: {}{}.", m.name, count(m.errors(), "error", "errors"),
                              count(m.rays, "ray", "rays"), m.compiled ? "" : " (a sample)", and_list(parts),
                              where.size() > 0 ? " (by ray set: " + and_list(where) + ")" : std::string()));
  }
  if (!clean.empty()) out.push_back("No error on any ray compared: " + and_list(clean) + ".");

  // The recommendation.
  auto find = [&](const std::optional<std::string>& name) -> const scene::MethodTally* {
    for (const auto& m : r.methods)
      if (name && m.name == *name) return &m;
    return nullptr;
  };
  const scene::MethodTally* rec = find(r.recommended);
  const scene::MethodTally* cert = find(std::string("certified"));
  const scene::MethodTally* loose = find(r.recommended_except_grazes);
  if (!rec) {
    out.push_back("No method made no error on this scene.");
  } else {
    std::string s = fmt::format("The cheapest method with no error on this scene is `{}` at {} Mrays/s", rec->name,
                                mrays(rec->mrays()));
    std::vector<std::string> notes;
    if (cert && cert != rec) notes.push_back(fmt::format("`certified`: {} Mrays/s", mrays(cert->mrays())));
    if (rec->timing_runs > 1) notes.push_back(fmt::format("the fastest of {} runs", rec->timing_runs));
    if (!notes.empty()) s += " (" + notes[0] + (notes.size() > 1 ? "; " + notes[1] : "") + ")";
    bool faster = false;  // a compiled method measured faster (each made an error: rec is the fastest without)
    for (const auto& m : r.methods) faster = faster || (m.compiled && m.mrays() > rec->mrays());
    s += !faster ? ", the fastest compiled method measured here." : rec->name == "certified" ? ": every faster compiled method made an error." : ".";
    out.push_back(s);
  }
  if (loose && loose != rec)
    out.push_back(fmt::format("Not counting grazes, the cheapest is `{}` at {} Mrays/s ({} on leak rays).", loose->name,
                              mrays(loose->mrays()), count(loose->leak_wrong_prims, "graze", "grazes")));
  const scene::MethodTally* fastest_ok = loose ? loose : rec;
  if (fastest_ok && fastest_ok->promise == "nothing")
    out.push_back(fmt::format("`{}` promises nothing: it made no such error on these rays, but other rays may find one; "
                              "for a guarantee use {}`certified` (exact class, t within 1 ulp).",
                              fastest_ok->name,
                              a.spheres + a.ellipsoids + a.disks == 0
                                  ? "`robust` (no false miss on triangles ahead of the origin, nor on boxes) or "
                                  : ""));
  if (rec) {
    if (rec->name == "certified")
      out.push_back("`certified` needs the certified tier (rayproof::scene_certified: GMP and MPFR).");
    else
      out.push_back(fmt::format("`{}` needs no exact arithmetic: GMP, MPFR and CGAL are not needed for this scene's queries.",
                                rec->name));
  }

  // What the scene does not need.
  std::vector<std::string> absent;
  if (!a.spheres) absent.push_back("spheres");
  if (!a.ellipsoids) absent.push_back("ellipsoids");
  if (!a.disks) absent.push_back("disks");
  if (!a.boxes) absent.push_back("boxes");
  if (!a.triangles) absent.insert(absent.begin(), "triangles");
  if (!absent.empty())
    out.push_back("The scene has no " + and_list(absent) + ": their kernels are never run on it.");
  const auto& p = r.paths;
  if (p.rays) {
    for (int k = 0; k < 5; ++k) {
      const std::uint64_t t = p.certified_tests[k], f = p.certified_fallbacks[k];
      if (!t) continue;
      out.push_back(f == 0 ? fmt::format("On a sample of {}, `certified` ran {}: its floating-point filter decided all; "
                                         "the exact (GMP) fallback was never reached.",
                                         count(p.rays, "ray", "rays"), count(t, std::string(kKindNames[k]) + " test",
                                                                             std::string(kKindNames[k]) + " tests"))
                           : fmt::format("On a sample of {}, `certified` ran {}: its floating-point filter decided {} and "
                                         "the exact (GMP) fallback {}.",
                                         count(p.rays, "ray", "rays"),
                                         count(t, std::string(kKindNames[k]) + " test", std::string(kKindNames[k]) + " tests"),
                                         t - f, f));
    }
    if (p.robust_tests)
      out.push_back(p.robust_degenerate + p.robust_parallel == 0
                        ? fmt::format("`robust` ran {} on the same sample; its special cases (a triangle degenerate in "
                                      "float, a ray parallel to a triangle's plane) were never reached.",
                                      count(p.robust_tests, "triangle test", "triangle tests"))
                        : fmt::format("`robust` ran {} on the same sample: {} on triangles degenerate in float and {} "
                                      "with the ray parallel to the triangle's plane (its special cases).",
                                      count(p.robust_tests, "triangle test", "triangle tests"), p.robust_degenerate,
                                      p.robust_parallel));
  }

  // One sphere more.
  if (!r.kind_cost.empty()) {
    std::vector<std::string> parts;
    double slowest = 0, fastest = 0, noise = 0;  // the largest slowdown and speed-up with the sphere; self-noise
    std::string slowed;
    for (const auto& k : r.kind_cost) {
      const double change = k.triangles_only > 0 ? k.with_sphere / k.triangles_only - 1 : 0;
      // Against the bracketing triangle-only series: slower than the slower one, faster than the faster one.
      const double lo = std::min(k.triangles_only, k.triangles_only_again), hi = std::max(k.triangles_only, k.triangles_only_again);
      const double slow = lo > 0 ? 1 - k.with_sphere / lo : 0, fast = hi > 0 ? k.with_sphere / hi - 1 : 0;
      if (slow > slowest) slowest = slow, slowed = k.method;
      fastest = std::max(fastest, fast);
      noise = std::max(noise, k.noise());
      parts.push_back(fmt::format("`{}` {} Mrays/s, {} with it ({:+.1f}%), {} again", k.method, mrays(k.triangles_only),
                                  mrays(k.with_sphere), 100 * change, mrays(k.triangles_only_again)));
    }
    const int reps = r.kind_cost.front().repeats;
    out.push_back(fmt::format("Triangle-only, then the same triangles plus one sphere, then triangle-only again ({} random "
                              "rays, best of {}): {}.",
                              r.random_rays_for_kind_cost, count(std::uint64_t(reps), "run", "runs"), and_list(parts)));
    // Timings on a shared machine move both ways: a slowdown counts only beyond the noise, the
    // largest of 5%, the triangle-only scene's difference from itself and any speed-up with the
    // sphere (which can only be noise).
    const double floor = std::max({0.05, noise, fastest});
    out.push_back(slowest <= floor
                      ? fmt::format("No method is slower with one sphere more by more than these timings' noise ({:.1f}%: "
                                    "the largest of 5%, the triangle-only scene against itself and any speed-up with the "
                                    "sphere): leaving the other kinds out saves nothing measurable here.",
                                    100 * floor)
                      : fmt::format("One sphere more slows `{}` by {:.1f}% (against the slower of its two triangle-only "
                                    "series), beyond these timings' noise ({:.1f}%): leaving the other kinds out saves about "
                                    "that here.",
                                    slowed, 100 * slowest, 100 * floor));
  }
  return out;
}

std::string advise_json(const scene::AdviseResult& r, const std::string& scene_name) {
  using nlohmann::json;
  const auto& a = r.analysis;
  json j;
  j["scene"] = scene_name;
  j["analysis"] = {{"vertices", a.vertices}, {"triangles", a.triangles}, {"spheres", a.spheres},
                   {"ellipsoids", a.ellipsoids}, {"disks", a.disks}, {"boxes", a.boxes}, {"lights", a.lights},
                   {"has_camera", a.has_camera}, {"degenerate", a.degenerate}, {"degenerate_undecided", a.undecided}, {"slivers", a.slivers},
                   {"sliver_aspect", a.sliver_aspect}, {"max_aspect", a.max_aspect}, {"welded_vertices", a.welded},
                   {"edges", a.edges}, {"open_edges", a.open_edges}, {"non_manifold_edges", a.non_manifold_edges},
                   {"components", a.components}, {"closed_components", a.closed_components},
                   {"min_abs", a.min_abs}, {"max_abs", a.max_abs}, {"spread_binades", a.spread_binades},
                   {"zero_coordinates", a.zero_coordinates}, {"coordinates", a.coordinates},
                   {"non_float_vertices", a.non_float_vertices}, {"non_float_analytic", a.non_float_analytic}};
  j["ray_sets"] = json::array();
  for (const auto& s : r.sets)
    j["ray_sets"].push_back({{"name", s.name}, {"rays", s.rays}, {"reference_hits", s.reference_hits}, {"invalid", s.invalid}});
  j["reference"] = {{"method", "certified"}, {"exact_checked", r.exact_checked}, {"exact_agree", r.exact_agree},
                    {"misses_on_leak_rays", r.reference_misses_on_leak_rays}};
  j["leak_components"] = r.leak_components;
  j["methods"] = json::array();
  for (const auto& m : r.methods)
    j["methods"].push_back({{"name", m.name}, {"compiled", m.compiled},
                            {"precision", m.float_precision ? "float" : "double"}, {"promise", m.promise},
                            {"tolerance_ulps", m.tolerance ? json(*m.tolerance) : json(nullptr)}, {"unsupported_kinds", m.unsupported}, {"rays", m.rays},
                            {"leak_rays", m.leak_rays}, {"leaks", m.leaks}, {"false_hits", m.false_hits},
                            {"false_misses", m.false_misses}, {"wrong_primitives", m.wrong_prims},
                            {"wrong_primitives_on_leak_rays", m.leak_wrong_prims}, {"ties", m.ties},
                            {"wrong_class", m.wrong_class}, {"t_compared", m.t_compared}, {"t_over_tolerance", m.t_over},
                            {"max_ulps", m.max_ulps}, {"seconds", m.seconds}, {"timing_runs", m.timing_runs}, {"mrays_per_s", m.mrays()},
                            {"errors", m.errors()}, {"error_free", m.error_free()},
                            {"errors_by_set", [&] {
                               json e = json::object();
                               for (const auto& [set, n] : m.errors_by_set) e[set] = n;
                               return e;
                             }()},
                            {"error_free_except_grazes", m.error_free(false)}});
  const auto& p = r.paths;
  json cert = json::object();
  for (int k = 0; k < 5; ++k)
    cert[kKindNames[k]] = {{"tests", p.certified_tests[k]}, {"exact_fallbacks", p.certified_fallbacks[k]}};
  j["paths"] = {{"sample_rays", p.rays}, {"certified", cert},
                {"robust_triangles", {{"tests", p.robust_tests}, {"degenerate_in_float", p.robust_degenerate},
                                      {"parallel", p.robust_parallel}}}};
  j["kind_cost"] = json::array();
  for (const auto& k : r.kind_cost)
    j["kind_cost"].push_back({{"method", k.method}, {"triangles_only_mrays_per_s", k.triangles_only},
                              {"with_one_sphere_mrays_per_s", k.with_sphere},
                              {"triangles_only_again_mrays_per_s", k.triangles_only_again}, {"repeats", k.repeats},
                              {"random_rays", r.random_rays_for_kind_cost}});
  j["recommended"] = r.recommended ? json(*r.recommended) : json(nullptr);
  j["recommended_except_grazes"] = r.recommended_except_grazes ? json(*r.recommended_except_grazes) : json(nullptr);
  j["sentences"] = advise_sentences(r);
  j["t_tolerance_ulps"] = r.t_tolerance ? json(*r.t_tolerance) : json(nullptr);
  j["same_point_distance"] = r.same_point;
  j["seconds"] = r.seconds;
  return j.dump(2);
}

}  // namespace rayproof::cli
