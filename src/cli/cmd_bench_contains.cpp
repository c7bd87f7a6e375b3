/// rayproof bench contains [MESH...] [--points N] [--repeat R]: point containment side by side on
/// one thread. Methods: rayproof `contains` (ClosedMesh, exact), CGAL
/// Side_of_triangle_mesh with Epick and Epeck, Embree 3 one-ray parity along (1, 1, 1) as Open3D
/// casts it, and rayproof float and robust parity along (1, 1, 1) (MeshCaster::all, crossings
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
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "cli/bench_winding.h"
#include "cli/commands.h"
#include "mesh/mesh.h"
#include "rayproof/certified_expansion.h"
#include "rayproof/scene/contains.h"
#include "rayproof/scene/mesh_caster.h"
#include "scene/compare/contains_compare.h"

namespace rayproof::cli {

namespace {

using Codes = std::vector<std::uint8_t>;
using Pts = std::vector<Vec3<double>>;
using Runner = std::function<void(std::span<const Vec3<double>>, std::span<std::uint8_t>)>;

struct Options {
  std::vector<std::string> meshes;
  std::size_t points = 200000, hard_vertices = 20000;
  int repeat = 3;
  bool no_epeck = false;
  std::vector<std::string> open;  ///< meshes for the generalized winding number ("none": skip)
};

struct Method {
  std::string name;
  Runner run;
  bool once = false;  ///< timed once (slow: Epeck)
  bool parity = false;  ///< cannot answer `surface`: judged on the points off the surface only
  std::vector<double> rates;  ///< Mpoints/s per run
  std::size_t wrong = 0;
  bool ran = false;
};

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

template <class Caster>
Runner parity_runner(std::shared_ptr<Caster> c) {
  return [c](std::span<const Vec3<double>> p, std::span<std::uint8_t> out) {
    for (std::size_t i = 0; i < p.size(); ++i) out[i] = c->all(Ray<double>{p[i], {1, 1, 1}}).size() & 1;
  };
}

/// Runs every method `repeat` times, interleaved, on `pts`; wrong answers against `truth` (when given).
void measure(std::vector<Method>& ms, const Pts& pts, const Codes* truth, int repeat) {
  Codes out(pts.size());
  for (auto& m : ms) m.rates.clear(), m.wrong = 0, m.ran = false;
  for (int r = 0; r < repeat; ++r)
    for (auto& m : ms) {
      if (!m.run || (m.once && r > 0)) continue;
      const double t0 = now();
      m.run(pts, out);
      const double dt = now() - t0;
      m.rates.push_back(double(pts.size()) / dt * 1e-6);
      if (truth && !m.ran) {
        for (std::size_t i = 0; i < pts.size(); ++i) {
          const bool bad = out[i] != (*truth)[i] && !(m.parity && (*truth)[i] == 2);
          if (bad && m.name == "contains" && m.wrong < 3)  // an exact method's disagreement: show it
            fmt::print("  contains disagrees at ({:a}, {:a}, {:a}): {} against {}\n", pts[i].x, pts[i].y, pts[i].z, out[i], (*truth)[i]);
          m.wrong += bad;
        }
      }
      m.ran = true;
    }
}

struct Verdicts {
  std::size_t contains_wrong = 0;
  std::vector<std::string> lines;
};

void print_table(const std::string& title, const Codes* truth, std::size_t n, const std::vector<Method>& ms, const char* truth_name,
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

/// Vertices (surface), one ulp off them along each axis, points whose +x and (1, 1, 1) rays pass
/// through a vertex, edge midpoints (rounded to double).
Pts hard_points(const mesh::Mesh& m, std::size_t nv, double extent, std::mt19937_64& rng) {
  Pts out;
  const double s = std::exp2(std::floor(std::log2(extent)) - 6);  // a power of two: v - s is exact near v
  for (std::size_t k = 0; k < nv; ++k) {
    const Vec3<double> v = m.vertices[rng() % m.vertices.size()];
    out.push_back(v);
    for (int a = 0; a < 3; ++a)
      for (double dir : {-1.0, 1.0}) {
        Vec3<double> q = v;
        double* c = reinterpret_cast<double*>(&q) + a;
        *c = std::nextafter(*c, dir * 1e300);
        out.push_back(q);
      }
    out.push_back({v.x - s, v.y, v.z});
    out.push_back({v.x - s, v.y - s, v.z - s});
    const auto& t = m.triangles[rng() % m.triangles.size()];
    const Vec3<double>&a = m.vertices[t[0]], &b = m.vertices[t[1]];
    out.push_back({(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2});
  }
  return out;
}

/// The three shapes whose inside is known: [0, 2]^3, the cube dented to (1, 1, 1) from its top,
/// and |x| + |y| + |z| <= 1 (outward triangles), with the exact side of a point (for the dyadic
/// lattice points and one-ulp neighbours used, the arithmetic below is exact or its rounding
/// cannot cross the surface: a one-ulp neighbour is compared coordinate-wise).
struct KnownShape {
  std::string name;
  mesh::Mesh mesh;
  std::function<std::uint8_t(const Vec3<double>&)> truth;
  double lo, hi, step;
};

/// Exact sign of a sum of expansions (the closed forms evaluated without rounding).
int sign_of(const certified::Expansion& e) { return e.sign(); }
certified::Expansion abs_diff(double x, double y) {
  certified::Expansion d = certified::diff(x, y);
  return d.sign() < 0 ? -d : d;
}

std::vector<KnownShape> known_shapes() {
  mesh::Mesh cube;
  for (int i = 0; i < 8; ++i) cube.vertices.push_back({2.0 * (i & 1), 2.0 * (i >> 1 & 1), 2.0 * (i >> 2 & 1)});
  cube.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                    {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  mesh::Mesh dent = cube;
  dent.triangles.erase(dent.triangles.begin() + 2, dent.triangles.begin() + 4);
  dent.vertices.push_back({1, 1, 1});
  for (std::array<std::uint32_t, 3> t : {std::array<std::uint32_t, 3>{4, 5, 8}, {5, 7, 8}, {7, 6, 8}, {6, 4, 8}}) dent.triangles.push_back(t);
  mesh::Mesh octa;
  octa.vertices = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (std::uint32_t sx : {0u, 1u})
    for (std::uint32_t sy : {2u, 3u})
      for (std::uint32_t sz : {4u, 5u})
        octa.triangles.push_back(((sx == 1) + (sy == 3) + (sz == 5)) % 2 ? std::array<std::uint32_t, 3>{sx, sz, sy}
                                                                        : std::array<std::uint32_t, 3>{sx, sy, sz});
  auto box = [](const Vec3<double>& p, double top) -> std::uint8_t {
    if (p.x < 0 || p.x > 2 || p.y < 0 || p.y > 2 || p.z < 0 || p.z > top) return 0;
    if (p.x == 0 || p.x == 2 || p.y == 0 || p.y == 2 || p.z == 0 || p.z == top) return 2;
    return 1;
  };
  std::vector<KnownShape> out;
  out.push_back({"cube", cube, [box](const Vec3<double>& p) { return box(p, 2); }, -0.5, 2.5, 0.125});
  out.push_back({"dented cube", dent,
                 [box](const Vec3<double>& p) -> std::uint8_t {
                   // The top: z = 1 + max(|x - 1|, |y - 1|), compared exactly.
                   const std::uint8_t side = box(p, 3);
                   if (side == 0) return 0;
                   const certified::Expansion a = abs_diff(p.x, 1), b = abs_diff(p.y, 1);
                   const certified::Expansion m = sign_of(a - b) >= 0 ? a : b;
                   const int top = sign_of(certified::diff(p.z, 1) - m);  // z - h
                   return top > 0 ? 0 : (top == 0 ? 2 : side);
                 },
                 -0.5, 2.5, 0.125});
  out.push_back({"octahedron", octa, [](const Vec3<double>& p) -> std::uint8_t {
                   const certified::Expansion r = certified::Expansion(std::fabs(p.x)) + certified::Expansion(std::fabs(p.y)) +
                                                  certified::Expansion(std::fabs(p.z)) - certified::Expansion(1.0);
                   const int s = sign_of(r);  // exact |x| + |y| + |z| - 1
                   return s < 0 ? 1 : (s == 0 ? 2 : 0);
                 },
                 -1.25, 1.25, 0.0625});
  return out;
}

std::vector<Method> methods_for(const mesh::Mesh& m, const ClosedMesh& cm, bool epeck) {
  std::vector<Method> ms;
  ms.push_back({"contains", [&cm](std::span<const Vec3<double>> p, std::span<std::uint8_t> o) {
                  cm.contains(std::span<const Vec3<double>>(p), std::span<Side>(reinterpret_cast<Side*>(o.data()), o.size()), 1);
                }, false, false, {}});
  for (auto& c : scene::compare::make_contains_competitors(m.vertices, m.triangles,
                                                           epeck ? "cgal-epick,cgal-epeck,embree-parity" : "cgal-epick,embree-parity")) {
    if (!c.run) fmt::print("  {}: {}\n", c.name, c.note);
    ms.push_back({c.name, c.run, c.name == "cgal-epeck", c.name == "embree-parity", {}});
  }
  const VertexArray va(&m.vertices[0].x, m.vertices.size());
  const IndexArray ia{m.triangles.front().data(), m.triangles.size()};
  ms.push_back({"rayproof-float", parity_runner(std::make_shared<MeshCaster<cast::Float>>(va, ia)), false, true, {}});
  ms.push_back({"rayproof-robust", parity_runner(std::make_shared<MeshCaster<cast::Robust>>(va, ia)), false, true, {}});
  return ms;
}

int run_bench_contains(const Options& opt) {
  std::vector<std::string> meshes = opt.meshes;
#ifdef RAYPROOF_BENCH_MESH_DIR
  if (meshes.empty())
    for (const char* n : {"bunny00.off", "armadillo.off", "refined_elephant.off"})
      if (std::filesystem::exists(std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + n)) meshes.push_back(std::string(RAYPROOF_BENCH_MESH_DIR) + "/" + n);
#endif
  fmt::print("rayproof bench contains: one thread; {} repeats, methods interleaved (a shared machine: read the ranges)\n", opt.repeat);
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
    std::unique_ptr<ClosedMesh> cm, nz;
    try {
      // CGAL's Side_of_triangle_mesh counts crossings mod 2: contains is measured with the parity
      // rule, and its nonzero answers (the default) are compared with it below.
      cm = std::make_unique<ClosedMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()},
                                        ContainsRule::parity);
      nz = std::make_unique<ClosedMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()});
    } catch (const std::invalid_argument& e) {
      fmt::print("\n{}: skipped: {}\n", path, e.what());
      continue;
    }
    const std::string name = std::filesystem::path(path).stem().string();
    fmt::print("\n== {} ({} triangles, {}; contains below uses the parity rule, as CGAL does)\n", name, m.triangles.size(),
               cm->oriented() ? "oriented" : "closed, not oriented");
    std::vector<Method> ms = methods_for(m, *cm, !opt.no_epeck);
    Vec3<double> lo = m.vertices[0], hi = lo;
    for (const auto& p : m.vertices)
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    std::uniform_real_distribution<double> u(0, 1);
    Pts random(opt.points);
    for (auto& p : random) p = {lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y), lo.z + u(rng) * (hi.z - lo.z)};
    const Pts hard = hard_points(m, opt.hard_vertices, std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z}), rng);
    for (const Pts* set : {static_cast<const Pts*>(&random), &hard}) {
      // The reference: Epeck's answers (its run is the first, timed once).
      Codes truth;
      const Method* ref = nullptr;
      for (const auto& me : ms)
        if (me.name == "cgal-epeck" && me.run) ref = &me;
      if (ref) truth.resize(set->size()), ref->run(*set, truth);
      measure(ms, *set, ref ? &truth : nullptr, opt.repeat);
      print_table(name + (set == &random ? " random" : " hard"), ref ? &truth : nullptr, set->size(), ms, "cgal-epeck", v);
      std::vector<Side> a(set->size()), b(set->size());
      cm->contains(*set, a, 1), nz->contains(*set, b, 1);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < a.size(); ++i) differ += a[i] != b[i];
      fmt::print("  contains with the nonzero rule (the default) differs from parity at {} points{}\n", differ,
                 differ ? " (winding number even and nonzero: the mesh overlaps itself there)" : "");
    }
  }
  for (auto& shape : known_shapes()) {
    const ClosedMesh cm(VertexArray(&shape.mesh.vertices[0].x, shape.mesh.vertices.size()),
                        IndexArray{shape.mesh.triangles.front().data(), shape.mesh.triangles.size()});
    std::vector<Method> ms = methods_for(shape.mesh, cm, !opt.no_epeck);
    Pts pts;
    for (double x = shape.lo; x <= shape.hi; x += shape.step)
      for (double y = shape.lo; y <= shape.hi; y += shape.step)
        for (double z = shape.lo; z <= shape.hi; z += shape.step) pts.push_back({x, y, z});
    // One ulp off the lattice points that are on the surface, along each axis.
    const std::size_t lattice = pts.size();
    for (std::size_t i = 0; i < lattice; ++i)
      if (shape.truth(pts[i]) == 2)
        for (int a = 0; a < 3; ++a)
          for (double dir : {-1.0, 1.0}) {
            Vec3<double> q = pts[i];
            double* c = reinterpret_cast<double*>(&q) + a;
            *c = std::nextafter(*c, dir * 1e300);
            pts.push_back(q);
          }
    Codes truth(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i) truth[i] = shape.truth(pts[i]);
    measure(ms, pts, &truth, opt.repeat);
    print_table(shape.name + " lattice+ulp", &truth, pts.size(), ms, "closed form", v);
  }
  // Open meshes: the generalized winding number beside a brute force (cli/bench_winding.cpp).
  std::vector<std::string> open = opt.open;
  std::string closed_ref;
#ifdef RAYPROOF_BENCH_MESH_DIR
  const std::string dir = RAYPROOF_BENCH_MESH_DIR;
  if (open.empty() && opt.meshes.empty())  // the default run; named meshes alone skip this section
    for (const char* n : {"elephant-with-holes.off", "cube-ouvert.off", "bunny00.off"})
      if (std::filesystem::exists(dir + "/" + n)) open.push_back(dir + "/" + n);
  if (std::filesystem::exists(dir + "/bunny00.off")) closed_ref = dir + "/bunny00.off";
#endif
  if (!open.empty() && !(open.size() == 1 && open[0] == "none"))
    v.contains_wrong += bench_open_meshes(open, closed_ref, opt.points, opt.repeat, v.lines);
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
  sub->add_flag("--no-epeck", opt->no_epeck, "Skip CGAL Epeck (then the meshes have no reference)");
  sub->add_option("--open", opt->open,
                  "Meshes for the generalized winding number beside a brute force (a closed one gets 1% of its triangles "
                  "removed; 'generated': the 1.31M-triangle bumpy sphere; default when no MESH is named: elephant-with-holes, "
                  "cube-ouvert, bunny00 where extracted; none: skip)");
  return [opt] { return run_bench_contains(*opt); };
}

}  // namespace rayproof::cli
