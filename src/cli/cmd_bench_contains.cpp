/// rayproof bench contains [MESH...] [--points N] [--repeat R] [--open MESH...] [--threads T]: point
/// containment side by side on one thread; the open meshes' section also at T threads. Methods:
/// rayproof `contains` (ExactMesh, exact), CGAL Side_of_triangle_mesh with Epick and Epeck,
/// Embree 3 one-ray parity along (1, 1, 1) as Open3D casts it, and rayproof float and robust parity along (1, 1, 1) (MeshCaster::all, crossings
/// counted). Point sets per mesh: random points in the bounding box, and hard points: the vertices
/// (on the surface), one ulp off them along each axis, points whose axis and diagonal rays pass
/// exactly through a vertex, and edge midpoints (rounded). Wrong answers against an exact reference:
/// CGAL Epeck on the meshes; the closed form on a cube, a dented cube and an octahedron (lattice
/// points on and around them, one ulp off their faces). Printed: wrong answers and Mpoints/s per
/// method (min-max over the repeats, the methods interleaved), the ratio of each to `contains`
/// from the best runs, and the targets with a verdict computed from the numbers beside them.
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "cli/bench_text.h"
#include "cli/commands.h"
#include "mesh/mesh.h"
#include "rayproof/scene/exact_mesh.h"
#include "scene/compare/contains_bench.h"

namespace rayproof::cli {

namespace {

using scene::compare::TimedMethod;
using Codes = scene::compare::PointCodes;
using Pts = scene::compare::Points;

struct Options {
  std::vector<std::string> meshes;
  std::size_t points = 200000, hard_vertices = 20000;
  int repeat = 3, threads = 2;
  bool no_epeck = false;
  std::vector<std::string> open;  ///< meshes for the generalized winding number ("none": skip)
};

/// The methods for a mesh; those that cannot run here are named with the reason.
std::vector<TimedMethod> methods(const mesh::Mesh& m, const ExactMesh& cm, bool epeck) {
  std::vector<TimedMethod> ms = scene::compare::contains_methods(m, cm, epeck);
  for (const auto& t : ms)
    if (!t.run) fmt::print("  {}: {}\n", t.name, t.note);
  return ms;
}

/// Times the methods; an exact method's disagreement with the reference is shown.
void measure_and_show(std::vector<TimedMethod>& ms, const Pts& pts, const Codes* truth, int repeat) {
  for (const auto& d : scene::compare::measure(ms, pts, truth, repeat))
    fmt::print("  contains disagrees at ({:a}, {:a}, {:a}): {} against {}\n", d.p.x, d.p.y, d.p.z, d.got, d.want);
}

struct Verdicts {
  std::size_t contains_wrong = 0;
  std::vector<std::string> lines;
};

void print_table(const std::string& title, const Codes* truth, std::size_t n, const std::vector<TimedMethod>& ms, const char* truth_name,
                 Verdicts& v) {
  const bool have_truth = truth != nullptr;
  const std::size_t on = have_truth ? std::size_t(std::count(truth->begin(), truth->end(), std::uint8_t(2))) : 0;
  fmt::print("\n{}: {} points, {} of them on the surface (reference: {}; parity methods, marked *, are judged on the "
             "others)\n",
             title, n, on, have_truth ? truth_name : "none");
  fmt::print("  {:<16} {:>8} {:>20} {:>12}\n", "method", "wrong", "Mpoints/s (min-max)", "vs contains");
  double best_contains = 0;
  for (const auto& m : ms)
    if (m.name == "contains" && !m.rates.empty()) best_contains = *std::max_element(m.rates.begin(), m.rates.end());
  for (const auto& m : ms) {
    if (!m.run || m.rates.empty()) continue;
    const double lo = *std::min_element(m.rates.begin(), m.rates.end()), hi = *std::max_element(m.rates.begin(), m.rates.end());
    const std::string wrong = have_truth ? std::to_string(m.wrong) : "-";
    fmt::print("  {:<16} {:>8} {:>9.3f}-{:<10.3f} {:>11.2f}x\n", m.name + (m.parity ? " *" : ""), wrong, lo, hi, best_contains > 0 ? hi / best_contains : 0.0);
    if (m.name == "contains" && have_truth) v.contains_wrong += m.wrong;
  }
  auto best = [&](const char* name) {
    for (const auto& m : ms)
      if (m.name == name && !m.rates.empty() && !m.once) return *std::max_element(m.rates.begin(), m.rates.end());
    return 0.0;
  };
  if (const double e = best("cgal-epick"); e > 0 && best_contains > 0)
    v.lines.push_back(fmt::format("{}: contains / cgal-epick = {:.2f} (target >= 2): {}", title, best_contains / e,
                                  best_contains >= 2 * e ? "met" : "missed"));
  if (const double e = best("embree-parity"); e > 0 && best_contains > 0)
    v.lines.push_back(fmt::format("{}: contains / embree-parity = {:.2f} (target >= 1.0): {}", title, best_contains / e,
                                  best_contains >= e ? "met" : "missed"));
}

/// The closed original of an open mesh named OPEN=CLOSED, or X-with-holes.off beside an X.off.
std::pair<std::string, std::string> open_and_original(const std::string& arg) {
  if (const auto eq = arg.find('='); eq != std::string::npos) return {arg.substr(0, eq), arg.substr(eq + 1)};
  const std::filesystem::path p(arg);
  const std::string stem = p.stem().string(), tag = "-with-holes";
  if (stem.size() > tag.size() && stem.ends_with(tag)) {
    const auto orig = p.parent_path() / (stem.substr(0, stem.size() - tag.size()) + p.extension().string());
    if (std::filesystem::exists(orig)) return {arg, orig.string()};
  }
  return {arg, ""};
}

/// The open meshes: contains by the winding rule beside contains on the closed original, the
/// ablation and a brute force. Appends the target lines; returns the wrong answers.
std::size_t bench_open_meshes(const std::vector<std::string>& args, std::size_t points, int repeat, int threads,
                              std::vector<std::string>& verdicts) {
  std::mt19937_64 rng(30);
  fmt::print("\n== open meshes: the generalized winding number (contains, rule winding) beside contains on the closed "
             "original, same points, rows interleaved over the repeats\n");
  std::size_t wrong_total = 0;
  for (const auto& arg : args) {
    const auto [path, original] = open_and_original(arg);
    const scene::compare::OpenRun r = scene::compare::time_open_mesh(path, original, points, repeat, threads, rng);
    if (!r.error.empty()) {
      fmt::print("  {}: skipped: {}\n", path, r.error);
      continue;
    }
    wrong_total += r.wrong;
    fmt::print("\n{} ({} triangles, {}): {} random points in its box: {} inside, {} outside, {} surface\n", r.name, r.triangles,
               r.closed ? "closed" : "not closed", r.points, r.sides[1], r.sides[0], r.sides[2]);
    if (!r.closed_error.empty()) fmt::print("  closed original not measured: {}\n", r.closed_error);
    // Ratios from the best runs: each row against the closed original at the same thread count.
    auto find = [&](bool closed, int th) -> const scene::compare::OpenRow* {
      for (const auto& row : r.rows)
        if (row.closed == closed && row.threads == th && row.name[0] != ' ') return &row;
      return nullptr;
    };
    fmt::print("  {:<40} {:>7} {:>20} {:>10} {:>11} {:>11} {:>7}\n", "method", "threads", "Mpoints/s (min-max)", "vs closed",
               "Mpts/CPU-s", "vs closed", "differ");
    for (const auto& row : r.rows) {
      const auto* c = find(true, row.threads);
      const std::string vs = row.closed || !c ? "-" : fmt::format("{:.3f}x", row.hi / c->hi);
      const std::string cpu = row.threads == 1 ? fmt::format("{:.4f}", row.cpu) : "-";
      const std::string vs_cpu = row.closed || !c || row.threads != 1 ? "-" : fmt::format("{:.3f}x", row.cpu / c->cpu);
      const std::string differ = row.closed || (row.name[0] != ' ' && row.threads == 1) ? "-" : std::to_string(row.differ);
      fmt::print("  {:<40} {:>7} {:>9.4f}-{:<10.4f} {:>10} {:>11} {:>11} {:>7}\n", row.name, row.threads, row.lo, row.hi, vs, cpu,
                 vs_cpu, differ);
    }
    const auto *o1 = find(false, 1), *c1 = find(true, 1);
    const double open1 = o1 ? o1->hi : 0;
    fmt::print("  {:<40} {:>7} {:>9.4f}{:<11} {:>12}   ({} points; contains is {:.1f}x it)\n", "brute-force double winding", 1,
               r.brute, "", "", r.brute_points, open1 / r.brute);
    fmt::print("  contains against the brute force where |w - 1/2| >= 1e-6: {} wrong of {} ({} inside)\n", r.wrong, r.compared,
               r.inside);
    // A batch of 4096 points or more tabulates the caps' field when the caps have 16 triangles or
    // more (docs/contains.md, step 7): the first batch pays for it.
    if (o1 && r.points >= 4096 && open1 > 0) fmt::print("  {}\n", first_batch_line(r.first_batch, r.points, open1));
    for (const auto& row : r.rows)
      if (row.differ)
        fmt::print("  {}: {} answers differ from the default build (a certified variant must not)\n", row.name, row.differ);
    if (o1 && c1)
      verdicts.push_back(fmt::format("{}: winding contains / contains on the closed {}, one thread = {:.2f} by CPU time, {:.2f} by "
                                     "wall time (target >= 0.5): {}",
                                     r.name, r.closed_name, o1->cpu / c1->cpu, o1->hi / c1->hi,
                                     o1->cpu >= 0.5 * c1->cpu ? "met" : "missed"));
    if (const auto* on = find(false, threads); on && threads > 1)
      verdicts.push_back(fmt::format("{}: winding contains, {} threads / one = {:.2f} by wall time (target >= {:.1f}): {}", r.name,
                                     threads, on->hi / open1, 0.9 * threads, on->hi >= 0.9 * threads * open1 ? "met" : "missed"));
    else if (threads > 1)
      fmt::print("  {} threads not timed: below 2048 points the batch runs on one thread\n", threads);
  }
  return wrong_total;
}

int run_bench_contains(const Options& opt) {
  std::vector<std::string> meshes = opt.meshes;
#ifdef RAYPROOF_BENCH_MESH_DIR
  if (meshes.empty())
    for (const char* n : {"bunny00.off", "armadillo.off", "refined_elephant.off"})
      if (std::filesystem::exists(std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + n)) meshes.push_back(std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + n);
#endif
  fmt::print("rayproof bench contains: one thread (open meshes: also {} threads); {} repeats, methods interleaved (a shared "
             "machine: read the ranges)\n",
             opt.threads, opt.repeat);
  Verdicts v;
  std::mt19937_64 rng(23);
  for (const auto& path : meshes) {
    mesh::Mesh m;
    try {
      m = mesh::read_mesh(path);
    } catch (const mesh::MeshError& e) {
      fmt::print(stderr, "rayproof bench contains: {}\n", e.what());
      return 2;
    }
    std::unique_ptr<ExactMesh> cm, nz;
    try {
      // CGAL's Side_of_triangle_mesh counts crossings mod 2: contains is measured with the parity
      // rule, and its nonzero answers (the default) are compared with it below.
      cm = std::make_unique<ExactMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()},
                                        ContainsRule::parity);
      nz = std::make_unique<ExactMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()});
    } catch (const std::invalid_argument& e) {
      fmt::print("\n{}: skipped: {}\n", path, e.what());
      continue;
    }
    const std::string name = std::filesystem::path(path).stem().string();
    fmt::print("\n== {} ({} triangles, {}; contains below uses the parity rule, as CGAL does)\n", name, m.triangles.size(),
               cm->oriented() ? "oriented" : "closed, not oriented");
    std::vector<TimedMethod> ms = methods(m, *cm, !opt.no_epeck);
    const Vec3<double> ext = mesh::vertex_bounds(m, false).extent();
    const Pts random = scene::compare::box_points(m, opt.points, rng);
    const Pts hard = scene::compare::hard_points(m, opt.hard_vertices, std::max({ext.x, ext.y, ext.z}), rng);
    for (const Pts* set : {static_cast<const Pts*>(&random), &hard}) {
      // The reference: Epeck's answers (its run is the first, timed once).
      Codes truth;
      const TimedMethod* ref = nullptr;
      for (const auto& me : ms)
        if (me.name == "cgal-epeck" && me.run) ref = &me;
      if (ref) truth.resize(set->size()), ref->run(*set, truth);
      measure_and_show(ms, *set, ref ? &truth : nullptr, opt.repeat);
      print_table(name + (set == &random ? " random" : " hard"), ref ? &truth : nullptr, set->size(), ms, "cgal-epeck", v);
      std::vector<Side> a(set->size()), b(set->size());
      cm->contains(*set, a, 1), nz->contains(*set, b, 1);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
      fmt::print("  contains with the nonzero rule (the default) differs from parity at {} points{}\n", differ,
                 differ ? " (winding number even and nonzero: the mesh overlaps itself there)" : "");
    }
  }
  for (auto& shape : scene::compare::known_shapes()) {
    const ExactMesh cm(VertexArray(&shape.mesh.vertices[0].x, shape.mesh.vertices.size()),
                        IndexArray{shape.mesh.triangles.front().data(), shape.mesh.triangles.size()});
    std::vector<TimedMethod> ms = methods(shape.mesh, cm, !opt.no_epeck);
    const Pts pts = scene::compare::lattice_points(shape);
    Codes truth(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) truth[i] = shape.truth(pts[i]);
    measure_and_show(ms, pts, &truth, opt.repeat);
    print_table(shape.name + " lattice+ulp", &truth, pts.size(), ms, "closed form", v);
  }
  // Open meshes: the generalized winding number beside a brute force.
  std::vector<std::string> open = opt.open;
#ifdef RAYPROOF_BENCH_MESH_DIR
  const std::string dir = RAYPROOF_BENCH_MESH_DIR;
  if (open.empty() && opt.meshes.empty()) {  // the default run; named meshes alone skip this section
    for (const char* n : {"elephant-with-holes.off", "cube-ouvert.off", "bunny00.off"})
      if (std::filesystem::exists(dir + "/" + n)) open.push_back(dir + "/" + n);
    open.push_back("generated");
  }
#endif
  if (!open.empty() && !(open.size() == 1 && open[0] == "none"))
    v.contains_wrong += bench_open_meshes(open, opt.points, opt.repeat, opt.threads, v.lines);
  fmt::print("\ntargets:\n  contains: {} wrong answers over every point set with a reference (target 0): {}\n", v.contains_wrong,
             v.contains_wrong == 0 ? "met" : "missed");
  for (const auto& l : v.lines)
    if (l.find("lattice") == std::string::npos) fmt::print("  {}\n", l);
  return v.contains_wrong == 0 ? 0 : 1;
}

}  // namespace

Run add_bench_contains(CLI::App& bench) {
  auto opt = std::make_shared<Options>();
  auto* sub = bench.add_subcommand("contains", "Point containment side by side (contains, CGAL, Embree parity), one thread");
  sub->add_option("meshes", opt->meshes, "Closed meshes (default: bunny00, armadillo, refined_elephant where extracted)");
  sub->add_option("--points", opt->points, "Random points per mesh")->capture_default_str();
  sub->add_option("--hard-vertices", opt->hard_vertices, "Vertices sampled for the hard points (10 points each)")->capture_default_str();
  sub->add_option("--repeat", opt->repeat, "Timed runs per method")->capture_default_str();
  sub->add_option("--threads", opt->threads,
                  "Threads for the open meshes' batch, timed beside one thread (1: one thread only)")
      ->capture_default_str()
      ->check(CLI::Range(1, 256));
  sub->add_flag("--no-epeck", opt->no_epeck, "Skip CGAL Epeck (then the meshes have no reference)");
  sub->add_option("--open", opt->open,
                  "Meshes for the generalized winding number beside contains on their closed original and a brute force: "
                  "OPEN=CLOSED names the original; X-with-holes.off is paired with an X.off beside it; a closed mesh gets 1% "
                  "of its triangles removed and is its own original; 'generated': the 1.31M-triangle bumpy sphere; default "
                  "when no MESH is named: elephant-with-holes, cube-ouvert, bunny00 where extracted, and generated; none: skip)");
  return [opt] { return run_bench_contains(*opt); };
}

}  // namespace rayproof::cli
