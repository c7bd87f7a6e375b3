// rayproof bench contains --open: contains by the generalized winding number (ClosedMesh with
// ContainsRule::winding) on open meshes, timed against a plain brute-force double winding number
// (every triangle's solid angle, no tree, no bound) in the same run, and against contains on a closed
// mesh (the exact integer rule).
#include "cli/bench_winding.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <random>
#include <span>

#include "mesh/mesh.h"
#include "rayproof/scene/contains.h"
#include "rayproof/scene/winding.h"
#include "scene/watertight.h"

namespace rayproof::cli {

namespace open_bench {

double now() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

std::vector<Vec3<double>> box_points(const mesh::Mesh& m, std::size_t n, std::mt19937_64& rng) {
  Vec3<double> lo = m.vertices[0], hi = lo;
  for (const auto& p : m.vertices)
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3<double>> pts(n);
  for (auto& p : pts) p = {lo.x + u(rng) * (hi.x - lo.x), lo.y + u(rng) * (hi.y - lo.y), lo.z + u(rng) * (hi.z - lo.z)};
  return pts;
}

/// Best and worst Mpoints/s of `repeat` runs of contains.
std::pair<double, double> time_contains(const ClosedMesh& cm, const std::vector<Vec3<double>>& pts, std::vector<Side>& out, int repeat) {
  double best = 0, worst = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const double t0 = open_bench::now();
    cm.contains(pts, out, 1);
    const double rate = double(pts.size()) / (open_bench::now() - t0) * 1e-6;
    best = std::max(best, rate), worst = std::min(worst, rate);
  }
  return {worst, best};
}

}  // namespace open_bench
using open_bench::box_points;
using open_bench::time_contains;

std::size_t bench_open_meshes(const std::vector<std::string>& paths, const std::string& closed_reference, std::size_t points,
                              int repeat, std::vector<std::string>& verdicts) {
  std::mt19937_64 rng(30);
  double closed_rate = 0;
  std::string closed_name;
  if (!closed_reference.empty()) {
    try {
      const mesh::Mesh m = mesh::read_mesh(closed_reference);
      const ClosedMesh cm(VertexArray(&m.vertices[0].x, m.vertices.size()), IndexArray{m.triangles.front().data(), m.triangles.size()});
      const auto pts = box_points(m, points, rng);
      std::vector<Side> out(pts.size());
      const auto [lo, hi] = time_contains(cm, pts, out, repeat);
      closed_rate = hi;
      closed_name = std::filesystem::path(closed_reference).stem().string();
      fmt::print("\n== open meshes: the generalized winding number (contains, rule winding), one thread\n"
                 "  reference: contains on the closed {} ({} triangles, rule {}): {:.3f}-{:.3f} Mpoints/s\n",
                 closed_name, m.triangles.size(), to_string(cm.rule()), lo, hi);
    } catch (const std::exception& e) {
      fmt::print("  closed reference {}: skipped: {}\n", closed_reference, e.what());
    }
  }
  std::size_t wrong_total = 0;
  for (const auto& path : paths) {
    mesh::Mesh m;
    try {
      // "generated": the closed bumpy sphere of `rayproof bench` (1.31M triangles).
      m = path == "generated" ? scene::bumpy_sphere(std::size_t(1) << 20) : mesh::read_mesh(path);
    } catch (const std::exception& e) {
      fmt::print("  {}: skipped: {}\n", path, e.what());
      continue;
    }
    std::string name = path == "generated" ? "generated" : std::filesystem::path(path).stem().string();
    std::unique_ptr<ClosedMesh> cm;
    try {
      cm = std::make_unique<ClosedMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()),
                                        IndexArray{m.triangles.front().data(), m.triangles.size()});
      if (cm->closed()) {  // cut holes: 1% of the triangles removed
        std::vector<std::array<std::uint32_t, 3>> kept;
        for (const auto& t : m.triangles)
          if (rng() % 100 != 0) kept.push_back(t);
        m.triangles = kept;
        name += " minus 1% of its triangles";
        cm = std::make_unique<ClosedMesh>(VertexArray(&m.vertices[0].x, m.vertices.size()),
                                          IndexArray{m.triangles.front().data(), m.triangles.size()});
      }
    } catch (const std::exception& e) {
      fmt::print("  {}: skipped: {}\n", path, e.what());
      continue;
    }
    const auto pts = box_points(m, points, rng);
    std::vector<Side> out(pts.size());
    const auto [lo, hi] = time_contains(*cm, pts, out, repeat);
    // The brute force on a prefix sized to take about a second or two.
    const std::size_t nb = std::clamp<std::size_t>(std::size_t(4e7 / double(m.triangles.size())), 20, pts.size());
    std::vector<double> wb(nb);
    double bbest = 0;
    for (int r = 0; r < repeat; ++r) {
      const double t0 = open_bench::now();
      for (std::size_t i = 0; i < nb; ++i) wb[i] = winding_plain_double(m.vertices, m.triangles, pts[i]);
      bbest = std::max(bbest, double(nb) / (open_bench::now() - t0) * 1e-6);
    }
    std::size_t wrong = 0, compared = 0, inside = 0;
    for (std::size_t i = 0; i < nb; ++i) {
      if (!(std::fabs(wb[i] - 0.5) >= 1e-6) || out[i] == Side::surface) continue;
      ++compared;
      inside += wb[i] > 0.5;
      wrong += out[i] != (wb[i] > 0.5 ? Side::inside : Side::outside);
    }
    wrong_total += wrong;
    std::size_t tally[4] = {0, 0, 0, 0};
    for (Side s : out) ++tally[int(s)];
    fmt::print("\n{} ({} triangles, {}): {} random points in its box: {} inside, {} outside, {} surface\n", name, m.triangles.size(),
               cm->closed() ? "closed" : "not closed", pts.size(), tally[1], tally[0], tally[2]);
    fmt::print("  {:<28} {:>20} {:>12}\n", "method", "Mpoints/s (min-max)", "vs brute");
    fmt::print("  {:<28} {:>9.4f}-{:<10.4f} {:>11.1f}x\n", "contains (rule winding)", lo, hi, hi / bbest);
    fmt::print("  {:<28} {:>9.4f}{:<11} {:>11.1f}x   ({} points)\n", "brute-force double winding", bbest, "", 1.0, nb);
    fmt::print("  contains against the brute force where |w - 1/2| >= 1e-6: {} wrong of {} ({} inside)\n", wrong, compared, inside);
    verdicts.push_back(fmt::format("{}: winding contains / brute-force double = {:.1f} (target >= 20 on a large mesh)", name, hi / bbest));
    if (closed_rate > 0)
      verdicts.push_back(fmt::format("{}: winding contains / contains on the closed {} = {:.2f} (target >= 0.5): {}", name,
                                     closed_name, hi / closed_rate, hi >= 0.5 * closed_rate ? "met" : "missed"));
  }
  return wrong_total;
}

}  // namespace rayproof::cli
