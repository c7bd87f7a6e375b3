// fuzz --winding (verify/winding_fuzz.h).
#include "verify/winding_fuzz.h"

#include <fmt/core.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <exception>
#include <memory>
#include <random>

#include "rayproof/float_util.h"
#include "verify/mesh_fuzz.h"

namespace rayproof::verify {

namespace {

using Tri = std::array<std::uint32_t, 3>;

struct Soup {
  std::vector<Vec3<double>> v;
  std::vector<Tri> t;
};

std::string off_text(const Soup& s) {
  std::string out = fmt::format("OFF\n{} {} 0\n", s.v.size(), s.t.size());
  for (const auto& p : s.v) out += fmt::format("{:a} {:a} {:a}\n", p.x, p.y, p.z);
  for (const auto& f : s.t) out += fmt::format("3 {} {} {}\n", f[0], f[1], f[2]);
  return out;
}

double u01(std::mt19937_64& rng) { return std::uniform_real_distribution<double>(0, 1)(rng); }
std::size_t pick(std::mt19937_64& rng, std::size_t n) { return std::size_t(rng() % n); }

/// A closed mesh of fuzz --mesh: a perturbed icosphere (20 or 80 triangles) or a convex hull of 8 to 24 points.
Soup closed_mesh(std::mt19937_64& rng) {
  std::vector<Vec3<double>> interior;
  mesh::Mesh m = rng() % 2 ? random_star_mesh(rng, int(rng() % 2), 0, interior)
                           : random_hull_mesh(rng, 8 + int(rng() % 17), 0, interior);
  return {std::move(m.vertices), std::move(m.triangles)};
}

void bounds(const std::vector<Vec3<double>>& v, Vec3<double>& lo, Vec3<double>& hi) {
  lo = hi = v.front();
  for (const auto& p : v) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
}

double& coord(Vec3<double>& p, int a) { return a == 0 ? p.x : a == 1 ? p.y : p.z; }


/// Removes 1 to a quarter of the triangles (at least one triangle stays).
void cut_holes(std::mt19937_64& rng, Soup& s) {
  const std::size_t n = 1 + pick(rng, std::max<std::size_t>(1, s.t.size() / 4));
  for (std::size_t k = 0; k < n && s.t.size() > 1; ++k) s.t.erase(s.t.begin() + std::ptrdiff_t(pick(rng, s.t.size())));
}

/// Cuts along the plane x_a = (a vertex's coordinate): the triangles whose centroid lies above it
/// get their own copies of the vertices they share with the others, moved by one ulp, by 2^-30 or
/// by 2^-8 of the mesh's size: the edges along the cut no longer match.
void crack(std::mt19937_64& rng, Soup& s) {
  const int a = int(rng() % 3);
  const double cut = coord(s.v[pick(rng, s.v.size())], a);
  auto above = [&](const Tri& f) { return coord(s.v[f[0]], a) + coord(s.v[f[1]], a) + coord(s.v[f[2]], a) > 3 * cut; };
  std::vector<char> below_uses(s.v.size(), 0);
  for (const auto& f : s.t)
    if (!above(f))
      for (auto i : f) below_uses[i] = 1;
  Vec3<double> lo, hi;
  bounds(s.v, lo, hi);
  const double size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  const int style = int(rng() % 3);
  const Vec3<double> dir{u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5};
  std::vector<std::uint32_t> copy(s.v.size(), UINT32_MAX);
  for (auto& f : s.t) {
    if (!above(f)) continue;
    for (auto& i : f) {
      if (!below_uses[i]) continue;
      if (copy[i] == UINT32_MAX) {
        Vec3<double> q = s.v[i];
        if (style == 0) {
          double& c = coord(q, int(rng() % 3));
          c = rng() % 2 ? next_up(c) : next_down(c);
        } else {
          q = q + dir * (size * (style == 1 ? 0x1p-30 : 0x1p-8));
        }
        copy[i] = std::uint32_t(s.v.size());
        s.v.push_back(q);
      }
      i = copy[i];
    }
  }
}

/// Reverses 1 to a third of the triangles.
void flip(std::mt19937_64& rng, Soup& s) {
  const std::size_t n = 1 + pick(rng, std::max<std::size_t>(1, s.t.size() / 3));
  for (std::size_t k = 0; k < n; ++k) {
    Tri& f = s.t[pick(rng, s.t.size())];
    std::swap(f[1], f[2]);
  }
}

/// Appends a copy shifted by up to half the mesh's size in each direction (sometimes with holes):
/// where the copies overlap the winding number is 2.
void overlap(std::mt19937_64& rng, Soup& s) {
  Vec3<double> lo, hi;
  bounds(s.v, lo, hi);
  const Vec3<double> shift{(u01(rng) - 0.5) * (hi.x - lo.x), (u01(rng) - 0.5) * (hi.y - lo.y),
                           (u01(rng) - 0.5) * (hi.z - lo.z)};
  Soup c = s;
  for (auto& p : c.v) p = p + shift;
  if (rng() % 3 == 0) cut_holes(rng, c);
  const auto base = std::uint32_t(s.v.size());
  s.v.insert(s.v.end(), c.v.begin(), c.v.end());
  for (const auto& f : c.t) s.t.push_back({f[0] + base, f[1] + base, f[2] + base});
}

/// Random triangles over 4 to 15 vertices: small integers (coplanar and repeated triangles) or
/// random reals; repeated indices give zero-area triangles.
Soup soup(std::mt19937_64& rng) {
  Soup s;
  const int nv = 4 + int(rng() % 12), nt = 2 + int(rng() % 20);
  const bool grid = rng() % 2;
  for (int i = 0; i < nv; ++i)
    s.v.push_back(grid ? Vec3<double>{double(int(rng() % 7) - 3), double(int(rng() % 7) - 3), double(int(rng() % 7) - 3)}
                       : Vec3<double>{u01(rng) * 6 - 3, u01(rng) * 6 - 3, u01(rng) * 6 - 3});
  for (int i = 0; i < nt; ++i) s.t.push_back({std::uint32_t(pick(rng, nv)), std::uint32_t(pick(rng, nv)), std::uint32_t(pick(rng, nv))});
  return s;
}

Soup random_mesh(std::mt19937_64& rng, WindingMeshKind kind) {
  if (kind == WindingMeshKind::soup) return soup(rng);
  Soup s = closed_mesh(rng);
  switch (kind) {
    case WindingMeshKind::holes: cut_holes(rng, s); break;
    case WindingMeshKind::crack: crack(rng, s); break;
    case WindingMeshKind::flipped: flip(rng, s); break;
    case WindingMeshKind::overlap: overlap(rng, s); break;
    default: break;
  }
  return s;
}

/// Point k of a mesh: by k % 7 random in the box grown by 10%, a vertex, an edge midpoint, a point
/// on a face, a one-ulp neighbour of a vertex, a far point, a one-ulp neighbour of an edge midpoint.
Vec3<double> random_point(std::mt19937_64& rng, const Soup& s, int k, const Vec3<double>& lo, const Vec3<double>& hi) {
  const Tri& f = s.t[pick(rng, s.t.size())];
  const Vec3<double> size = hi - lo;
  switch (k % 7) {
    case 0: return {lo.x + size.x * (1.2 * u01(rng) - 0.1), lo.y + size.y * (1.2 * u01(rng) - 0.1), lo.z + size.z * (1.2 * u01(rng) - 0.1)};
    case 1: return s.v[f[pick(rng, 3)]];
    case 2: {
      const std::size_t e = pick(rng, 3);
      return (s.v[f[e]] + s.v[f[(e + 1) % 3]]) * 0.5;
    }
    case 3: {
      double a = u01(rng), b = u01(rng);
      if (rng() % 2) a = double(rng() % 9) / 8, b = double(rng() % 9) / 8;  // dyadic: often exactly on the triangle
      if (a + b > 1) a = 1 - a, b = 1 - b;
      return s.v[f[0]] * (1 - a - b) + s.v[f[1]] * a + s.v[f[2]] * b;
    }
    case 4:
    case 6: {
      // k % 7 == 6: beside an edge's midpoint (a hole's rim, a crack), else beside a vertex.
      const std::size_t e = pick(rng, 3);
      Vec3<double> p = k % 7 == 6 ? (s.v[f[e]] + s.v[f[(e + 1) % 3]]) * 0.5 : s.v[f[e]];
      const int moved = 1 + int(rng() % 7);  // which coordinates move: a nonempty subset
      for (int a = 0; a < 3; ++a)
        if (moved >> a & 1) coord(p, a) = rng() % 2 ? next_up(coord(p, a)) : next_down(coord(p, a));
      return p;
    }
    default: {
      const double d = std::max({size.x, size.y, size.z, 0x1p-1000});
      const Vec3<double> dir{u01(rng) - 0.5, u01(rng) - 0.5, u01(rng) - 0.5};
      return (lo + hi) * 0.5 + dir * std::ldexp(d, 4 + int(rng() % 37));
    }
  }
}

}  // namespace

const char* to_string(WindingMeshKind k) {
  switch (k) {
    case WindingMeshKind::closed: return "closed";
    case WindingMeshKind::holes: return "holes";
    case WindingMeshKind::crack: return "crack";
    case WindingMeshKind::flipped: return "flipped";
    case WindingMeshKind::overlap: return "overlap";
    case WindingMeshKind::soup: return "soup";
  }
  return "?";
}

WindingPointVerdict judge_winding_point(const WindingValue& ref, const WindingValue& value, Side side) {
  WindingPointVerdict v;
  if (ref.surface) {
    if (!value.surface || side != Side::surface) {
      v.wrong_surface = true;
      v.what = fmt::format("on a triangle, but winding_value says {} and contains says {}",
                           value.surface ? "surface" : fmt::format("w = {} +- {}", value.w, value.bound), to_string(side));
    }
    return v;
  }
  if (value.surface || side == Side::surface) {
    v.wrong_surface = true;
    v.what = fmt::format("off every triangle (w = {}), but winding_value says {} and contains says {}", ref.w,
                         value.surface ? "surface" : "not surface", to_string(side));
    return v;
  }
  // (a) The two intervals meet; the slack covers the rounding of the difference and the sum.
  if (!(std::abs(value.w - ref.w) <= (value.bound + ref.bound) * (1 + 0x1p-50))) {
    v.bound_miss = true;
    v.what = fmt::format("w = {} +- {}, but the reference gives {} +- {}", value.w, value.bound, ref.w, ref.bound);
  }
  // (b) The side, where the reference is at least 1e-6 from 1/2.
  if (!(std::abs(ref.w - 0.5) - ref.bound >= 1e-6)) {
    v.near_half = true;
  } else {
    const Side want = ref.w > 0.5 ? Side::inside : Side::outside;
    if (side != want) {
      v.wrong_side = true;
      if (v.what.empty()) v.what = fmt::format("contains says {}, but the reference gives w = {} ({})", to_string(side), ref.w, to_string(want));
    }
  }
  return v;
}

WindingFuzzResult run_winding_fuzz(const WindingFuzzOptions& opt) {
  WindingFuzzResult res;
  std::mt19937_64 rng(opt.seed);
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
  const int exponents[] = {0, 0, 0, 0, 20, -20, 100, -100, 300, -300};
  auto record = [&](const Soup& s, const Vec3<double>& p, std::string what) {
    if (res.findings.size() < 5) res.findings.push_back({std::move(what), off_text(s), p});
  };
  for (;;) {
    if (opt.max_meshes ? res.meshes >= opt.max_meshes : elapsed() >= opt.seconds) break;
    const auto kind = WindingMeshKind(rng() % kWindingMeshKinds);
    Soup s = random_mesh(rng, kind);
    const int e = exponents[pick(rng, std::size(exponents))];
    for (auto& p : s.v) p = {std::ldexp(p.x, e), std::ldexp(p.y, e), std::ldexp(p.z, e)};
    ++res.meshes, ++res.kind_meshes[std::size_t(kind)], res.triangles += s.t.size();
    std::unique_ptr<ExactMesh> m;
    try {
      m = std::make_unique<ExactMesh>(VertexArray(&s.v[0].x, s.v.size()), IndexArray{s.t.front().data(), s.t.size()},
                                       ContainsRule::winding);
    } catch (const std::exception& ex) {
      ++res.errors;
      record(s, s.v.front(), fmt::format("ExactMesh with the winding rule threw: {}", ex.what()));
      continue;
    }
    Vec3<double> lo, hi;
    bounds(s.v, lo, hi);
    for (int k = 0; k < 28; ++k) {
      const Vec3<double> p = random_point(rng, s, k, lo, hi);
      ++res.points;
      const WindingValue ref = winding_brute_force_mpfr(s.v, s.t, p, opt.bits);
      res.surface_points += ref.surface;
      WindingPointVerdict v;
      try {
        const WindingValue value = opt.value ? opt.value(*m, p) : m->winding_value(p);
        const Side side = opt.contains ? opt.contains(*m, p) : m->contains(p);
        v = judge_winding_point(ref, value, side);
      } catch (const std::exception& ex) {
        ++res.errors;
        record(s, p, fmt::format("threw: {}", ex.what()));
        continue;
      }
      res.near_half += v.near_half;
      res.bound_misses += v.bound_miss, res.wrong_sides += v.wrong_side, res.wrong_surfaces += v.wrong_surface;
      if (!v.what.empty()) record(s, p, fmt::format("{} mesh: {}", to_string(kind), v.what));
    }
    // (d) Every fourth open mesh: a batch large enough to tabulate the caps' field, against the
    // same points asked alone before it was built.
    if (kind != WindingMeshKind::closed && res.meshes % 4 == 0) {
      std::vector<Vec3<double>> pts(kWindingBatch);
      std::vector<Side> alone(kWindingBatchCompared), batch(kWindingBatch);
      for (std::size_t k = 0; k < kWindingBatch; ++k) pts[k] = random_point(rng, s, int(k), lo, hi);
      try {
        for (std::size_t k = 0; k < kWindingBatchCompared; ++k) alone[k] = m->contains(pts[k]);
        if (opt.batch) opt.batch(*m, pts, batch);
        else m->contains(pts, batch, 1);
      } catch (const std::exception& ex) {
        ++res.errors;
        record(s, pts.front(), fmt::format("the batch threw: {}", ex.what()));
        continue;
      }
      ++res.batch_meshes, res.batch_points += kWindingBatchCompared;
      for (std::size_t k = 0; k < kWindingBatchCompared; ++k)
        if (batch[k] != alone[k]) {
          ++res.batch_differ;
          record(s, pts[k], fmt::format("{} mesh: the batch says {}, the point alone {}", to_string(kind), to_string(batch[k]),
                                        to_string(alone[k])));
        }
    }
  }
  res.seconds = elapsed();
  return res;
}

}  // namespace rayproof::verify
