/// Mesh leak check: on closed triangle meshes, rays from an interior point towards every vertex and
/// every edge midpoint must hit some triangle (brute force over all triangles). Under `robust`
/// (watertight, float inputs) and `certified` (exact classes) none may leak; `float`
/// (Möller–Trumbore in float) is counted and printed, not asserted.
/// Meshes: CGAL's sphere966.off and cube.off (extracted from libcgal-dev's data.tar.gz at configure
/// time, skipped when absent) and a generated icosphere.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "rayproof/triangle_moller_trumbore.h"
#include "rayproof/triangle_watertight.h"
#include "verify/certified_method.h"

using namespace rayproof;

namespace {

struct Mesh {
  std::vector<Vec3<double>> v;
  std::vector<std::array<int, 3>> f;
};

/// Tiny OFF reader: "OFF", counts, vertices, faces (polygons fan-triangulated). Comments skipped.
bool read_off(const std::string& path, Mesh& m) {
  std::ifstream in(path);
  std::string word;
  auto skip = [&] {
    while (in >> std::ws && in.peek() == '#') std::getline(in, word);
  };
  skip();
  if (!(in >> word) || word.rfind("OFF", 0) != 0) return false;
  skip();
  std::size_t nv = 0, nf = 0, ne = 0;
  if (!(in >> nv >> nf >> ne)) return false;
  m.v.resize(nv);
  for (auto& p : m.v) {
    skip();
    if (!(in >> p.x >> p.y >> p.z)) return false;
  }
  for (std::size_t i = 0; i < nf; ++i) {
    skip();
    int k = 0;
    if (!(in >> k) || k < 3) return false;
    std::vector<int> idx(static_cast<std::size_t>(k));
    for (int& j : idx) in >> j;
    std::getline(in, word);  // optional colour
    for (int j = 1; j + 1 < k; ++j) m.f.push_back({idx[0], idx[static_cast<std::size_t>(j)], idx[static_cast<std::size_t>(j) + 1]});
  }
  return static_cast<bool>(in);
}

/// Icosahedron subdivided `levels` times, vertices pushed onto the unit sphere (closed, 2-manifold).
Mesh icosphere(int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  Mesh m;
  m.v = {{-1, g, 0}, {1, g, 0}, {-1, -g, 0}, {1, -g, 0}, {0, -1, g}, {0, 1, g},
         {0, -1, -g}, {0, 1, -g}, {g, 0, -1}, {g, 0, 1}, {-g, 0, -1}, {-g, 0, 1}};
  m.f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
         {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (auto& p : m.v) p = normalize(p);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      if (auto it = mid.find(key); it != mid.end()) return it->second;
      m.v.push_back(normalize(m.v[static_cast<std::size_t>(a)] + m.v[static_cast<std::size_t>(b)]));
      return mid[key] = static_cast<int>(m.v.size()) - 1;
    };
    std::vector<std::array<int, 3>> f;
    for (const auto& t : m.f) {
      const int a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      f.insert(f.end(), {{t[0], a, c}, {t[1], b, a}, {t[2], c, b}, {a, b, c}});
    }
    m.f = std::move(f);
  }
  return m;
}

/// Every vertex and every edge midpoint (the midpoint computed in double, then rounded like the mesh).
std::vector<Vec3<double>> targets(const Mesh& m) {
  std::vector<Vec3<double>> out(m.v.begin(), m.v.end());
  std::set<std::pair<int, int>> edges;
  for (const auto& t : m.f)
    for (int i = 0; i < 3; ++i) edges.insert(std::minmax(t[static_cast<std::size_t>(i)], t[static_cast<std::size_t>((i + 1) % 3)]));
  for (const auto& [a, b] : edges) out.push_back((m.v[static_cast<std::size_t>(a)] + m.v[static_cast<std::size_t>(b)]) / 2.0);
  return out;
}

struct Leaks {
  std::size_t rays = 0, robust = 0, certified = 0, flt = 0;
};

/// Rays from an interior point (the vertex centroid, nudged off symmetry axes) to every target, with
/// d = target - o and with d normalized in float; all coordinates rounded to float first.
Leaks check(const Mesh& mesh) {
  Mesh m = mesh;
  for (auto& p : m.v) p = p.cast<float>().cast<double>();
  Vec3<double> c{};
  for (const auto& p : m.v) c = c + p;
  c = c / double(m.v.size());
  double extent = 0;
  for (const auto& p : m.v) extent = std::max(extent, length(p - c));
  const Vec3<float> o = (c + Vec3<double>{0.013, 0.021, 0.034} * extent).cast<float>();
  std::vector<Triangle<float>> tf;
  for (const auto& t : m.f)
    tf.push_back({m.v[static_cast<std::size_t>(t[0])].cast<float>(), m.v[static_cast<std::size_t>(t[1])].cast<float>(),
                  m.v[static_cast<std::size_t>(t[2])].cast<float>()});
  Leaks leaks;
  for (const auto& target : targets(m)) {
    const Vec3<float> tgt = target.cast<float>();
    for (const Vec3<float> d : {tgt - o, normalize(tgt - o)}) {
      const Ray<float> ray{o, d};
      ++leaks.rays;
      const WatertightRay<float, double> wr(ray);
      bool robust = false, flt = false, cert = false;
      for (const auto& tri : tf) robust = robust || is_hit(intersect_watertight(wr, tri).contact);
      for (const auto& tri : tf) flt = flt || is_hit(intersect_moller_trumbore(ray, tri).contact);
      io::Case cs{io::Kind::triangle, {}, {}, 0};
      for (int i = 0; i < 3; ++i) cs.v[static_cast<std::size_t>(i)] = o[static_cast<std::size_t>(i)],
                                  cs.v[static_cast<std::size_t>(3 + i)] = d[static_cast<std::size_t>(i)];
      for (const auto& tri : tf) {
        for (int i = 0; i < 3; ++i) {
          cs.v[static_cast<std::size_t>(6 + i)] = tri.p0[static_cast<std::size_t>(i)];
          cs.v[static_cast<std::size_t>(9 + i)] = tri.p1[static_cast<std::size_t>(i)];
          cs.v[static_cast<std::size_t>(12 + i)] = tri.p2[static_cast<std::size_t>(i)];
        }
        if (is_hit(verify::certified_classify(cs).contact)) {
          cert = true;
          break;
        }
      }
      leaks.robust += !robust;
      leaks.flt += !flt;
      leaks.certified += !cert;
    }
  }
  return leaks;
}

void run(const std::string& name, const Mesh& m) {
  ASSERT_FALSE(m.f.empty()) << name;
  const Leaks l = check(m);
  std::printf("%-14s %6zu triangles %7zu rays: leaks robust %zu, certified %zu, float %zu\n", name.c_str(), m.f.size(),
              l.rays, l.robust, l.certified, l.flt);
  EXPECT_EQ(l.robust, 0u) << name;
  EXPECT_EQ(l.certified, 0u) << name;
}

}  // namespace

TEST(MeshLeak, Icosphere) { run("icosphere(3)", icosphere(3)); }

TEST(MeshLeak, CgalSphere966) {
  Mesh m;
  if (!read_off(std::string(RAYPROOF_CGAL_MESHES) + "/sphere966.off", m)) GTEST_SKIP() << "sphere966.off not available";
  run("sphere966.off", m);
}

TEST(MeshLeak, CgalCube) {
  Mesh m;
  if (!read_off(std::string(RAYPROOF_CGAL_MESHES) + "/cube.off", m)) GTEST_SKIP() << "cube.off not available";
  run("cube.off", m);
}
