// Scene utilities: primitive numbering and bounds, mesh placement, cameras, the built-in scene.
#include "scene/scene.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>

namespace rayproof::scene {

int Camera::width() const { return std::visit([](const auto& c) { return c.width; }, cam); }
int Camera::height() const { return std::visit([](const auto& c) { return c.height; }, cam); }
Ray<double> Camera::generate(int i, int j) const {
  return std::visit([&](const auto& c) { return c.generate(i, j); }, cam);
}

PrimKind Scene::kind_of(std::uint32_t id, std::uint32_t& local) const {
  std::size_t i = id;
  if (i < mesh.triangles.size()) return local = std::uint32_t(i), PrimKind::triangle;
  i -= mesh.triangles.size();
  if (i < spheres.size()) return local = std::uint32_t(i), PrimKind::sphere;
  i -= spheres.size();
  if (i < ellipsoids.size()) return local = std::uint32_t(i), PrimKind::ellipsoid;
  i -= ellipsoids.size();
  if (i < disks.size()) return local = std::uint32_t(i), PrimKind::disk;
  i -= disks.size();
  return local = std::uint32_t(i), PrimKind::box;
}

namespace {
BvhBox box_around(Vec3<double> c, Vec3<double> half) {
  BvhBox b;
  b.extend(c - half), b.extend(c + half);
  return b;
}
Vec3<float> center_of(const BvhBox& b) {
  return {(b.lo[0] + b.hi[0]) / 2, (b.lo[1] + b.hi[1]) / 2, (b.lo[2] + b.hi[2]) / 2};
}
}  // namespace

namespace {
/// x rounded to float towards -inf (`up` false) or +inf: the nearest float, stepped one
/// ulp outward when it fell on the wrong side; the same as bvh_float_down / bvh_float_up, without
/// branches (the side is a coin flip per coordinate, which branches mispredict).
float float_outward(double x, bool up) {
  if (x != x) return up ? -std::numeric_limits<float>::infinity() : std::numeric_limits<float>::infinity();  // NaN: no bound
  float f = static_cast<float>(x);
  const double back = f;
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  // One step outward: away from zero on the outward side (|f| grows), towards zero otherwise. A
  // zero here is -0 going down or +0 going up (the sign of x survives the rounding), whose steps
  // are to -denorm_min / +denorm_min: +1 on the bits, as the rule gives.
  const std::uint32_t negative = u >> 31;
  const std::uint32_t wrong = up ? std::uint32_t(back < x) : std::uint32_t(back > x);
  const std::uint32_t away = up ? 1u - negative : negative;  // growing |f| moves outward
  u += wrong * (away ? 1u : ~0u);
  std::memcpy(&f, &u, 4);
  return f;
}
}  // namespace

void triangle_bounds(const Triangle<double>& t, BvhBox& box, Vec3<float>& center) {
  // Bounds in double, then rounded outward once: the same box as extending by each vertex
  // (rounding down / up is monotonic), with 6 roundings instead of 18.
  for (int k = 0; k < 3; ++k) {
    const double a = t.p0[k], b = t.p1[k], c = t.p2[k];
    const double l = a < b ? a : b, h = a > b ? a : b;
    box.lo[k] = float_outward(c < l ? c : l, false), box.hi[k] = float_outward(c > h ? c : h, true);
  }
  center = ((t.p0 + t.p1 + t.p2) / 3.0).cast<float>();
}

void Scene::primitive_bounds(std::vector<BvhBox>& out, std::vector<Vec3<float>>& centers) const {
  out.clear(), centers.clear();
  out.reserve(size()), centers.reserve(size());
  out.resize(mesh.triangles.size()), centers.resize(mesh.triangles.size());
  for (std::uint32_t i = 0; i < mesh.triangles.size(); ++i) triangle_bounds(triangle(i), out[i], centers[i]);
  auto add = [&](const BvhBox& b) { out.push_back(b), centers.push_back(center_of(b)); };
  for (const auto& s : spheres) add(box_around(s.center, {s.radius, s.radius, s.radius}));
  for (const auto& e : ellipsoids) add(box_around(e.center, e.semi_axes));
  for (const auto& d : disks) {
    // Half extent of a disk along axis k: r sqrt(1 - n_k^2 / |n|^2).
    const double nn = length_squared(d.normal);
    Vec3<double> h;
    for (int k = 0; k < 3; ++k) h[k] = d.radius * std::sqrt(std::max(0.0, 1.0 - d.normal[k] * d.normal[k] / nn)) * (1 + 1e-12);
    add(box_around(d.center, h));
  }
  for (const auto& b : boxes) {
    BvhBox bb;
    bb.extend(b.lo), bb.extend(b.hi);
    add(bb);
  }
}

BvhBox Scene::bounds() const {
  std::vector<BvhBox> b;
  std::vector<Vec3<float>> c;
  primitive_bounds(b, c);
  BvhBox all;
  for (const auto& x : b) all.extend(x);
  return all;
}

std::size_t Scene::triangle_bytes() const {
  return mesh.vertices.size() * sizeof(Vec3<double>) + mesh.triangles.size() * sizeof(mesh.triangles[0]);
}

void add_mesh(Scene& s, const mesh::Mesh& m, const Transform<double>& world_from_object) {
  const auto base = static_cast<std::uint32_t>(s.mesh.vertices.size());
  for (const auto& v : m.vertices) s.mesh.vertices.push_back(world_from_object.point(v));
  for (const auto& t : m.triangles) s.mesh.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

mesh::Mesh icosphere(int subdivisions, Vec3<double> c, double r) {
  const double p = (1 + std::sqrt(5.0)) / 2;
  mesh::Mesh m;
  m.vertices = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  m.triangles = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (auto& v : m.vertices) v = normalize(v);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto midpoint = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::minmax(a, b);
      auto [it, fresh] = mid.try_emplace(key, std::uint32_t(m.vertices.size()));
      if (fresh) m.vertices.push_back(normalize(m.vertices[a] + m.vertices[b]));
      return it->second;
    };
    std::vector<std::array<std::uint32_t, 3>> next;
    next.reserve(m.triangles.size() * 4);
    for (const auto& t : m.triangles) {
      const std::uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), d = midpoint(t[2], t[0]);
      next.push_back({t[0], a, d}), next.push_back({t[1], b, a}), next.push_back({t[2], d, b}), next.push_back({a, b, d});
    }
    m.triangles = std::move(next);
  }
  for (auto& v : m.vertices) v = c + r * v;
  return m;
}

Camera default_camera(const Scene& s, int width, int height) {
  const BvhBox b = s.bounds();
  Vec3<double> c{0, 0, 0};
  double radius = 1;
  if (!b.empty()) {
    c = Vec3<double>{double(b.lo[0]) + b.hi[0], double(b.lo[1]) + b.hi[1], double(b.lo[2]) + b.hi[2]} / 2.0;
    radius = std::max(1e-30, length(Vec3<double>{double(b.hi[0]) - b.lo[0], double(b.hi[1]) - b.lo[1], double(b.hi[2]) - b.lo[2]}) / 2);
  }
  const double fov = std::numbers::pi / 4;
  const double dist = radius / std::sin(fov / 2) * 1.05;
  const Vec3<double> eye = c + dist * normalize(Vec3<double>{0.3, 0.35, 1});
  return {PerspectiveCamera<double>::look_at(width, height, fov, eye, c, {0, 1, 0})};
}

Scene default_scene(int subdivisions, int width, int height) {
  Scene s;
  add_mesh(s, icosphere(subdivisions, {-0.9, 1, 0}, 1));
  s.spheres.push_back({{1.3, 0.6, 0.8}, 0.6});
  s.ellipsoids.push_back({{0.2, 0.35, 1.8}, {0.5, 0.35, 0.3}});
  s.boxes.push_back({{0.6, 0, -1.4}, {1.8, 1.2, -0.2}});
  s.disks.push_back({{0, 0, 0}, {0, 1, 0}, 4});
  s.camera = Camera{PerspectiveCamera<double>::look_at(width, height, 0.8, {0.5, 2.6, 6.5}, {0.1, 0.7, 0}, {0, 1, 0})};
  s.lights.push_back({{{0, 5, 2}, {0, -1, 0}, 1}, {8, 8, 8}});
  return s;
}

}  // namespace rayproof::scene
