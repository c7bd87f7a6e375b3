// The measuring half of `rayproof bench contains` (contains_bench.h).
#include "scene/compare/contains_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <filesystem>
#include <memory>

#include "rayproof/certified_expansion.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/scene/winding.h"
#include "scene/compare/contains_compare.h"
#include "scene/watertight.h"
#include "scene/winding_tree.h"

namespace rayproof::scene::compare {

namespace {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }
/// The calling thread's CPU time in seconds.
double thread_cpu() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

template <class Caster>
PointRunner parity_runner(std::shared_ptr<Caster> c) {
  return [c](std::span<const Vec3<double>> p, std::span<std::uint8_t> out) {
    for (std::size_t i = 0; i < p.size(); ++i) out[i] = c->all(Ray<double>{p[i], {1, 1, 1}}).size() & 1;
  };
}

/// Exact sign of a sum of expansions (the closed forms evaluated without rounding).
int sign_of(const certified::Expansion& e) { return e.sign(); }
certified::Expansion abs_diff(double x, double y) {
  certified::Expansion d = certified::diff(x, y);
  return d.sign() < 0 ? -d : d;
}


ExactMesh closed_mesh(const mesh::Mesh& m, ContainsRule rule = ContainsRule::automatic) {
  return ExactMesh(VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()},
                    rule);
}

}  // namespace

std::vector<Disagreement> measure(std::vector<TimedMethod>& ms, const Points& pts, const PointCodes* truth, int repeat) {
  std::vector<Disagreement> shown;
  PointCodes out(pts.size());
  for (auto& m : ms) m.rates.clear(), m.wrong = 0, m.ran = false;
  for (int r = 0; r < repeat; ++r)
    for (auto& m : ms) {
      if (!m.run || (m.once && r > 0)) continue;
      const double t0 = now();
      m.run(pts, out);
      const double dt = now() - t0;
      m.rates.push_back(double(pts.size()) / dt * 1e-6);
      if (truth && !m.ran)
        for (std::size_t i = 0; i < pts.size(); ++i) {
          const bool bad = out[i] != (*truth)[i] && !(m.parity && (*truth)[i] == 2);
          if (bad && m.name == "contains" && shown.size() < 3) shown.push_back({pts[i], out[i], (*truth)[i]});
          m.wrong += bad;
        }
      m.ran = true;
    }
  return shown;
}

std::vector<TimedMethod> contains_methods(const mesh::Mesh& m, const ExactMesh& cm, bool epeck) {
  std::vector<TimedMethod> ms;
  auto add = [&ms](std::string name, PointRunner run, bool once, bool parity, std::string note = {}) {
    TimedMethod t;
    t.name = std::move(name), t.run = std::move(run), t.once = once, t.parity = parity, t.note = std::move(note);
    ms.push_back(std::move(t));
  };
  add("contains",
      [&cm](std::span<const Vec3<double>> p, std::span<std::uint8_t> o) {
        cm.contains(std::span<const Vec3<double>>(p), std::span<Side>(reinterpret_cast<Side*>(o.data()), o.size()), 1);
      },
      false, false);
  for (auto& c : make_contains_competitors(m.vertices, m.triangles,
                                           epeck ? "cgal-epick,cgal-epeck,embree-parity" : "cgal-epick,embree-parity"))
    add(c.name, c.run, c.name == "cgal-epeck", c.name == "embree-parity", c.note);
  const VertexArray va(&m.vertices[0].x, m.vertices.size());
  const IndexArray ia{m.triangles.front().data(), m.triangles.size()};
  add("rayproof-float", parity_runner(std::make_shared<MeshCaster<cast::Float>>(va, ia)), false, true);
  add("rayproof-robust", parity_runner(std::make_shared<MeshCaster<cast::Robust>>(va, ia)), false, true);
  return ms;
}

Points box_points(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng) {
  const auto [lo, hi] = mesh::vertex_bounds(m, false);
  std::uniform_real_distribution<double> u(0, 1);
  Points pts(n);
  for (auto& p : pts) p = {lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y), lo.z + u(rng) * (hi.z - lo.z)};
  return pts;
}

Points hard_points(const mesh::Mesh& m, std::size_t nv, double extent, std::mt19937_64& rng) {
  Points out;
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

Points lattice_points(const KnownShape& shape) {
  Points pts;
  for (double x = shape.lo; x <= shape.hi; x += shape.step)
    for (double y = shape.lo; y <= shape.hi; y += shape.step)
      for (double z = shape.lo; z <= shape.hi; z += shape.step) pts.push_back({x, y, z});
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
  return pts;
}

namespace {

/// `m` with 1% of its triangles removed (seeded by `rng`).
mesh::Mesh cut_holes(mesh::Mesh m, std::mt19937_64& rng) {
  std::vector<std::array<std::uint32_t, 3>> kept;
  for (const auto& t : m.triangles)
    if (rng() % 100 != 0) kept.push_back(t);
  m.triangles = std::move(kept);
  return m;
}

mesh::Mesh load(const std::string& path) { return path == "generated" ? bumpy_sphere(std::size_t(1) << 20) : mesh::read_mesh(path); }

/// A ExactMesh of `m` built with `tuning` (the winding trees read it when built).
std::unique_ptr<ExactMesh> build_with(const mesh::Mesh& m, const rayproof::scene::detail::WindingTuning& tuning) {
  const rayproof::scene::detail::WindingTuning saved = rayproof::scene::detail::winding_tuning();
  rayproof::scene::detail::winding_tuning() = tuning;
  std::unique_ptr<ExactMesh> cm;
  try {
    cm = std::make_unique<ExactMesh>(closed_mesh(m));
  } catch (...) {
    rayproof::scene::detail::winding_tuning() = saved;
    throw;
  }
  rayproof::scene::detail::winding_tuning() = saved;
  return cm;
}

}  // namespace

OpenRun time_open_mesh(const std::string& path, const std::string& closed_path, std::size_t points, int repeat, int threads,
                       std::mt19937_64& rng) {
  OpenRun run;
  mesh::Mesh m, orig;
  std::unique_ptr<ExactMesh> cm, ref;
  try {
    m = load(path);
    run.name = path == "generated" ? "generated" : std::filesystem::path(path).stem().string();
    cm = std::make_unique<ExactMesh>(closed_mesh(m));
    if (cm->closed()) {  // cut holes; the input is then the closed original
      orig = std::move(m);
      run.closed_name = run.name;
      m = cut_holes(orig, rng);
      run.name += " minus 1% of its triangles";
      cm = std::make_unique<ExactMesh>(closed_mesh(m));
    }
  } catch (const std::exception& e) {
    run.error = e.what();
    return run;
  }
  if (!closed_path.empty() && run.closed_name.empty()) {
    try {
      orig = load(closed_path);
      run.closed_name = closed_path == "generated" ? "generated" : std::filesystem::path(closed_path).stem().string();
    } catch (const std::exception& e) {
      run.closed_error = e.what();
    }
  }
  if (!run.closed_name.empty()) {
    try {
      ref = std::make_unique<ExactMesh>(closed_mesh(orig));
      if (!ref->closed()) throw std::invalid_argument("not closed");
      run.closed_triangles = orig.triangles.size();
    } catch (const std::exception& e) {
      run.closed_error = run.closed_name + ": " + e.what(), run.closed_name.clear(), ref.reset();
    }
  }
  run.triangles = m.triangles.size();
  run.closed = cm->closed();
  const Points pts = box_points(m, points, rng);
  run.points = pts.size();
  // The rows, timed interleaved. The ablation: the open mesh built with one speed-up turned off.
  struct Timed {
    OpenRow row;
    const ExactMesh* mesh;
  };
  std::vector<Timed> rows;
  std::vector<std::unique_ptr<ExactMesh>> held;
  rows.push_back({{"contains (rule winding)", 1, false}, cm.get()});
  if (ref) rows.push_back({{"contains on the closed " + run.closed_name, 1, true}, ref.get()});
  const rayproof::scene::detail::WindingTuning best = rayproof::scene::detail::winding_tuning();
  auto variant = [&](std::string name, rayproof::scene::detail::WindingTuning t) {
    held.push_back(build_with(m, t));
    rows.push_back({{std::move(name), 1, false}, held.back().get()});
  };
  if (best.near_bound) {
    auto t = best;
    t.near_bound = false;
    variant("  without the near bound", t);
  }
  if (best.caps_field) {
    auto t = best;
    t.caps_field = false;
    variant("  without the caps' field", t);
  }
  {
    auto t = best;
    t.compact_caps = !best.compact_caps;
    variant(best.compact_caps ? "  caps as cones" : "  caps as hierarchical fans", t);
  }
  if (best.caps_leaf != 6) {
    auto t = best;
    t.caps_leaf = 6;
    variant("  caps' leaves of 6", t);
  }
  if (threads > 1 && pts.size() >= 2048) {
    rows.push_back({{"contains (rule winding)", threads, false}, cm.get()});
    if (ref) rows.push_back({{"contains on the closed " + run.closed_name, threads, true}, ref.get()});
  }
  std::vector<Side> out(pts.size()), other(pts.size());
  const double f0 = now();
  cm->contains(pts, out, 1);
  run.first_batch = now() - f0;
  for (auto& r : rows) {
    if (r.row.closed || r.mesh == cm.get()) continue;
    r.mesh->contains(pts, other, 1);
    for (std::size_t i = 0; i < pts.size(); ++i) r.row.differ += other[i] != out[i];
  }
  for (int k = 0; k < repeat; ++k)
    for (auto& r : rows) {
      const double t0 = now(), c0 = thread_cpu();
      r.mesh->contains(pts, other, r.row.threads);
      const double rate = double(pts.size()) / (now() - t0) * 1e-6;
      if (r.row.threads == 1) r.row.cpu = std::max(r.row.cpu, double(pts.size()) / (thread_cpu() - c0) * 1e-6);
      r.row.hi = std::max(r.row.hi, rate);
      r.row.lo = k == 0 ? rate : std::min(r.row.lo, rate);
    }
  for (auto& r : rows) run.rows.push_back(r.row);
  // The brute force on a prefix sized to take about a second or two.
  const std::size_t nb = std::clamp<std::size_t>(std::size_t(4e7 / double(m.triangles.size())), 20, pts.size());
  std::vector<double> wb(nb);
  for (int r = 0; r < repeat; ++r) {
    const double t0 = now();
    for (std::size_t i = 0; i < nb; ++i) wb[i] = winding_plain_double(m.vertices, m.triangles, pts[i]);
    run.brute = std::max(run.brute, double(nb) / (now() - t0) * 1e-6);
  }
  run.brute_points = nb;
  for (std::size_t i = 0; i < nb; ++i) {
    if (!(std::fabs(wb[i] - 0.5) >= 1e-6) || out[i] == Side::surface) continue;
    ++run.compared;
    run.inside += wb[i] > 0.5;
    run.wrong += out[i] != (wb[i] > 0.5 ? Side::inside : Side::outside);
  }
  for (Side s : out) ++run.sides[std::size_t(s)];
  return run;
}

}  // namespace rayproof::scene::compare
