// The point sets of the containment judge (rayproof/verify/contains_check.h): points exactly on
// the surface and one ulp off it, through thin parts, far away and invalid.
#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <span>
#include <stdexcept>
#include <tuple>
#include <utility>

#include "rayproof/ray.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/contains_check.h"

namespace rayproof::verify {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr const char* kSets[] = {"vertex", "edge", "face", "nudged", "medial", "thin", "far", "random", "invalid"};

/// Adds named sets, each point once, evenly subsampled to the cap.
struct SetBuilder {
  ContainsPoints& out;
  std::size_t cap;
  bool float32 = false;  ///< round every point to float
  void add(const char* name, std::vector<Vec3<double>> points) {
    if (float32)
      for (Vec3<double>& p : points) p = {double(float(p.x)), double(float(p.y)), double(float(p.z))};
    std::set<std::array<std::uint64_t, 3>> seen;
    std::erase_if(points, [&](const Vec3<double>& p) {
      return !seen.insert({std::bit_cast<std::uint64_t>(p.x), std::bit_cast<std::uint64_t>(p.y),
                           std::bit_cast<std::uint64_t>(p.z)})
                  .second;
    });
    const auto id = static_cast<std::uint8_t>(out.names.size());
    out.names.push_back(name);
    const std::size_t n = points.size(), keep = std::min(n, cap);
    for (std::size_t k = 0; k < keep; ++k) {
      out.points.push_back(points[keep == n ? k : k * n / keep]);
      out.set.push_back(id);
    }
  }
};

bool wanted(const ContainsCheckOptions& opt, const char* name) {
  return opt.sets.empty() || std::find(opt.sets.begin(), opt.sets.end(), name) != opt.sets.end();
}

Vec3<double> random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  for (;;) {
    const Vec3<double> v{g(rng), g(rng), g(rng)};
    const double l = length(v);
    if (l > 1e-6) return v / l;
  }
}

double& component(Vec3<double>& p, int axis) { return axis == 0 ? p.x : (axis == 1 ? p.y : p.z); }

}  // namespace

ContainsPoints contains_points(const ContainsMesh& mesh, const ContainsCheckOptions& opt) {
  for (const std::string& s : opt.sets)
    if (std::find_if(std::begin(kSets), std::end(kSets), [&](const char* k) { return s == k; }) == std::end(kSets))
      throw std::invalid_argument("unknown point set '" + s + "' (vertex, edge, face, nudged, medial, thin, far, random, invalid)");
  const auto& V = mesh.vertices;
  const auto& F = mesh.triangles;
  for (const auto& f : F)
    for (auto i : f)
      if (i >= V.size()) throw MeshInputError(fmt::format("triangle index {} out of range ({} vertices)", i, V.size()));
  ContainsPoints out;
  const bool float32 = opt.precision == ContainsPrecision::float32;
  SetBuilder b{out, std::max<std::size_t>(opt.max_points_per_set, 1), float32};
  // One ulp of the function's precision from x towards `to`.
  auto nudge = [float32](double x, double to) {
    return float32 ? double(std::nextafter(float(x), float(to))) : std::nextafter(x, to);
  };
  std::mt19937_64 rng(opt.seed);
  Vec3<double> lo{kInf, kInf, kInf}, hi = -lo;
  for (const auto& f : F)
    for (auto i : f)
      lo = {std::min(lo.x, V[i].x), std::min(lo.y, V[i].y), std::min(lo.z, V[i].z)},
      hi = {std::max(hi.x, V[i].x), std::max(hi.y, V[i].y), std::max(hi.z, V[i].z)};
  if (F.empty()) lo = {-1, -1, -1}, hi = {1, 1, 1};
  const Vec3<double> centre = 0.5 * lo + 0.5 * hi;
  // Shapes (normals, lengths, casts through thin parts) are measured on W, the mesh times 2^-E where
  // its largest coordinate is beyond 2^±200 (E that coordinate's exponent; else E = 0 and W is the
  // mesh), and their points scaled back: the sets of a mesh times 2^K are its sets times 2^K, no
  // cross product or squared length overflowing or underflowing on the way.
  int E = 0;
  {
    double big = 0;
    for (const auto& f : F)
      for (auto i : f)
        for (double c : {V[i].x, V[i].y, V[i].z})
          if (std::isfinite(c)) big = std::max(big, std::fabs(c));
    if (big > 0 && (big > 0x1p200 || big < 0x1p-200)) E = std::ilogb(big);
  }
  auto scaled = [](const Vec3<double>& p, int e) {
    return Vec3<double>{std::ldexp(p.x, e), std::ldexp(p.y, e), std::ldexp(p.z, e)};
  };
  std::vector<Vec3<double>> W_own;
  if (E != 0)
    for (const Vec3<double>& v : V) W_own.push_back(scaled(v, -E));
  const std::span<const Vec3<double>> W = E != 0 ? std::span<const Vec3<double>>(W_own) : V;
  const double size_w = E != 0 ? length(scaled(hi, -E) - scaled(lo, -E)) : std::max(length(hi - lo), 1e-300);
  const double size = E != 0 ? std::max(std::ldexp(size_w, E), 1e-300) : size_w;
  auto normal = [&](std::size_t k) { return cross(W[F[k][1]] - W[F[k][0]], W[F[k][2]] - W[F[k][0]]); };

  // Points on the surface, each with the sum of the unit normals of the triangles it lies on (for
  // the nudged set).
  auto unit_normal = [&](std::size_t k) {
    const Vec3<double> n = normal(k);
    const double l = length(n);
    return l > 0 && std::isfinite(l) ? n / l : Vec3<double>{0, 0, 0};
  };
  std::vector<Vec3<double>> vertex, edge, face, vertex_n, edge_n, face_n;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> edge_ends;  // per edge point
  std::vector<int> edge_uses;                                      // triangles on it
  {
    std::vector<Vec3<double>> around(V.size(), Vec3<double>{0, 0, 0});
    std::vector<bool> used(V.size(), false);
    for (std::size_t k = 0; k < F.size(); ++k)
      for (auto i : F[k]) used[i] = true, around[i] = around[i] + unit_normal(k);
    for (std::size_t i = 0; i < V.size(); ++i)
      if (used[i]) vertex.push_back(V[i]), vertex_n.push_back(around[i]);
    std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> es;
    for (std::size_t k = 0; k < F.size(); ++k)
      for (int j = 0; j < 3; ++j)
        es.emplace_back(std::min(F[k][j], F[k][(j + 1) % 3]), std::max(F[k][j], F[k][(j + 1) % 3]),
                        static_cast<std::uint32_t>(k));
    std::sort(es.begin(), es.end());
    for (std::size_t i = 0; i < es.size(); ++i) {
      const auto [a, c, k] = es[i];
      if (i > 0 && std::get<0>(es[i - 1]) == a && std::get<1>(es[i - 1]) == c) {
        edge_n.back() = edge_n.back() + unit_normal(k);
        ++edge_uses.back();
        continue;
      }
      edge.push_back(0.5 * V[a] + 0.5 * V[c]);  // halves first: no overflow at huge coordinates
      edge_n.push_back(unit_normal(k));
      edge_ends.emplace_back(a, c);
      edge_uses.push_back(1);
    }
    for (std::size_t k = 0; k < F.size(); ++k) {
      face.push_back(V[F[k][0]] / 3.0 + V[F[k][1]] / 3.0 + V[F[k][2]] / 3.0);
      face_n.push_back(unit_normal(k));
    }
  }
  if (wanted(opt, "vertex")) b.add("vertex", vertex);
  if (wanted(opt, "edge")) b.add("edge", edge);
  if (wanted(opt, "face")) b.add("face", face);
  if (wanted(opt, "nudged")) {
    // Each point one ulp both ways along its normal, roughly: every coordinate whose component of
    // the summed normal is at least a tenth of the largest moves one ulp (so a point on a cube's
    // edge leaves both faces). As many of each kind: the cap's sixth each way.
    std::vector<Vec3<double>> nudged;
    const std::size_t per_kind = std::max<std::size_t>(1, b.cap / 6);
    for (auto [pts, ns] : {std::pair{&vertex, &vertex_n}, std::pair{&edge, &edge_n}, std::pair{&face, &face_n}}) {
      const std::size_t n = pts->size(), keep = std::min(n, per_kind);
      for (std::size_t k = 0; k < keep; ++k) {
        const std::size_t i = keep == n ? k : k * n / keep;
        Vec3<double> dir = (*ns)[i];
        if (!(length(dir) > 0)) dir = face_n.empty() ? Vec3<double>{1, 0, 0} : Vec3<double>{0, 0, 1};
        const double big = std::max({std::fabs(dir.x), std::fabs(dir.y), std::fabs(dir.z)});
        for (double way : {1.0, -1.0}) {
          Vec3<double> p = (*pts)[i];
          for (int axis = 0; axis < 3; ++axis) {
            const double c = component(dir, axis);
            if (std::fabs(c) >= 0.1 * big) component(p, axis) = nudge(component(p, axis), way * c * kInf);
          }
          nudged.push_back(p);
        }
      }
    }
    b.add("nudged", std::move(nudged));
  }
  if (wanted(opt, "medial")) {
    // Near the medial axis, where two triangles (or more) are equally near: from the midpoint of
    // each edge shared by triangles, along the bisector of their normals (the sum of their unit
    // normals), both ways, 2^-20, 2^-4 and 2^-1 of the edge's length away. Where the two triangles
    // mirror each other about the bisector's plane (a cube's edges and diagonals) the points are
    // exact ties.
    std::vector<Vec3<double>> medial;
    for (std::size_t e = 0; e < edge.size(); ++e) {
      if (edge_uses[e] < 2) continue;
      const Vec3<double> dir = edge_n[e];
      const double l = length(dir);
      if (!(l > 1e-6) || !std::isfinite(l)) continue;  // opposite normals: a fold, no bisector
      const auto [a, c] = edge_ends[e];
      const double len = 2 * length(0.5 * W[c] - 0.5 * W[a]);
      for (double f : {0x1p-20, 0x1p-4, 0x1p-1})
        for (double way : {1.0, -1.0}) {
          // The offset's coordinates rounded to 11 bits below its largest one's leading bit: added
          // to the midpoint without rounding (unless the edge is tiny beside its coordinates), so
          // that a bisector with coordinates of equal size (a cube's) gives exact ties.
          Vec3<double> o = (way * f * len / l) * dir;
          const int q = std::ilogb(std::max({std::fabs(o.x), std::fabs(o.y), std::fabs(o.z)})) - 10;
          for (int axis = 0; axis < 3; ++axis)
            component(o, axis) = std::ldexp(std::nearbyint(std::ldexp(component(o, axis), -q)), q + E);
          medial.push_back(edge[e] + o);
        }
    }
    b.add("medial", std::move(medial));
  }
  if (wanted(opt, "thin")) {
    // The thinnest parts: from sampled triangles' centroids along the normal both ways to the next
    // surface; through the thinnest, points near both sides and across.
    std::vector<Vec3<double>> thin;
    if (!F.empty()) {
      const MeshCaster<cast::Robust> caster(VertexArray(reinterpret_cast<const double*>(W.data()), W.size()),
                                            IndexArray{F.data()->data(), F.size()});
      struct Through {
        double t;
        Vec3<double> from, dir;
      };
      std::vector<Through> through;
      const std::size_t step = std::max<std::size_t>(1, F.size() / 2000);
      for (std::size_t k = 0; k < F.size(); k += step) {
        const Vec3<double> n = face_n[k];
        const double l = length(n);
        if (!(l > 0) || !std::isfinite(l)) continue;
        for (double s : {-1.0, 1.0}) {
          const Vec3<double> d = (s / l) * n;
          const Vec3<double> from = scaled(face[k], -E);
          const MeshHit h = caster.closest(Ray<double>{from, d}, TRange{size_w * 0x1p-40, kInf});
          if (h.hit() && std::isfinite(h.t)) through.push_back({h.t, from, d});
        }
      }
      std::sort(through.begin(), through.end(), [](const Through& a, const Through& c) { return a.t < c.t; });
      const std::size_t parts = std::min<std::size_t>(through.size(), std::max<std::size_t>(1, b.cap / 8));
      for (std::size_t k = 0; k < parts; ++k)
        for (double f : {-0x1p-20, 0x1p-40, 0x1p-20, 0.5, 1 - 0x1p-20, 1 - 0x1p-40, 1 + 0x1p-20, 1 + 0x1p-40})
          thin.push_back(scaled(through[k].from + (f * through[k].t) * through[k].dir, E));
    }
    if (F.empty()) out.notes.push_back("thin: no triangles");
    b.add("thin", std::move(thin));
  }
  if (wanted(opt, "far")) {
    std::vector<Vec3<double>> far;
    constexpr double kScales[] = {10, 1e3, 1e8, 1e15, 1e30, 1e100, 1e300};
    const std::size_t n = std::max<std::size_t>(std::size(kScales), std::min<std::size_t>(b.cap, 200));
    for (std::size_t i = 0; i < n; ++i) {
      const double s = kScales[i % std::size(kScales)];
      const Vec3<double> u = random_unit(rng);
      const double r = std::min(size * s, 1e300);
      far.push_back(std::isfinite(centre.x + r) ? centre + r * u : r * u);
    }
    const double big = std::numeric_limits<double>::max();
    for (const Vec3<double> p : {Vec3<double>{big, big, big}, Vec3<double>{-big, centre.y, centre.z},
                                 Vec3<double>{centre.x, big, -big}})
      far.push_back(p);
    b.add("far", std::move(far));
  }
  if (wanted(opt, "random")) {
    std::vector<Vec3<double>> random;
    const Vec3<double> pad = 0.05 * (hi - lo);
    std::uniform_real_distribution<double> u01(0, 1);
    for (std::size_t i = 0; i < opt.random_points; ++i) {
      const Vec3<double> t{u01(rng), u01(rng), u01(rng)};
      random.push_back({lo.x - pad.x + t.x * (hi.x - lo.x + 2 * pad.x), lo.y - pad.y + t.y * (hi.y - lo.y + 2 * pad.y),
                        lo.z - pad.z + t.z * (hi.z - lo.z + 2 * pad.z)});
    }
    b.add("random", std::move(random));
  }
  if (wanted(opt, "invalid"))
    b.add("invalid", {{kNaN, centre.y, centre.z}, {centre.x, kNaN, centre.z}, {centre.x, centre.y, kNaN},
                      {kInf, centre.y, centre.z}, {-kInf, centre.y, centre.z}, {centre.x, kInf, centre.z},
                      {centre.x, centre.y, -kInf}, {kNaN, kNaN, kNaN}, {kInf, -kInf, kNaN}, {kInf, kInf, kInf}});
  for (std::size_t k = 0; k < out.names.size(); ++k)
    if (std::find(out.set.begin(), out.set.end(), k) == out.set.end() && out.names[k] != "thin")
      out.notes.push_back(out.names[k] + (out.names[k] == "medial" && !F.empty()
                                              ? ": empty (no edge is shared by triangles that are not folded flat)"
                                              : ": empty (the mesh has no triangles)"));
  return out;
}

}  // namespace rayproof::verify
