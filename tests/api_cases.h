#pragma once
/// Shared by the typed-API tests: the shared sample (data/sample.txt and .expected) as typed rays and
/// primitives, and a dispatch from a case to the typed call.
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include <gmpxx.h>
#include <gtest/gtest.h>

#include <cmath>

#include "gen/families.h"
#include "io/case_file.h"
#include "methods/primitive_of.h"

#ifndef RAYPROOF_DATA_DIR
#error "RAYPROOF_DATA_DIR must name the directory holding sample.txt and sample.expected"
#endif

namespace rayproof::api_test {

struct Sample {
  std::vector<io::Case> cases;
  std::vector<io::CaseResult> expected;
};

/// The sample and its expected answers, line by line; fails the test when they cannot be read.
inline Sample load_sample() {
  const std::string dir = RAYPROOF_DATA_DIR;
  std::ifstream cases(dir + "/sample.txt"), expected(dir + "/sample.expected");
  Sample s;
  EXPECT_TRUE(cases && expected) << dir << "/sample.*";
  for (const auto& e : io::read_cases(cases)) {
    const auto* c = std::get_if<io::Case>(&e);
    EXPECT_NE(c, nullptr) << "sample.txt: a line that is not a case";
    if (c) s.cases.push_back(*c);
  }
  for (std::string line; std::getline(expected, line);) {
    if (line.empty()) continue;
    const auto r = io::parse_result(line);
    EXPECT_TRUE(r.has_value()) << "sample.expected: " << line;
    if (r) s.expected.push_back(*r);
  }
  EXPECT_EQ(s.cases.size(), s.expected.size());
  EXPECT_GT(s.cases.size(), 100U);
  return s;
}

/// f(ray, primitive) with the case's typed inputs (double).
template <class F>
void visit(const io::Case& c, F&& f) {
  const Ray<double> ray = ray_of<double>(c);
  switch (c.kind) {
    case io::Kind::plane: f(ray, plane_of<double>(c)); return;
    case io::Kind::sphere: f(ray, sphere_of<double>(c)); return;
    case io::Kind::ellipsoid: f(ray, ellipsoid_of<double>(c)); return;
    case io::Kind::triangle: f(ray, triangle_of<double>(c)); return;
    case io::Kind::box: f(ray, box_of<double>(c)); return;
    case io::Kind::disk: f(ray, disk_of<double>(c)); return;
    case io::Kind::tritri: ADD_FAILURE() << "a triangle pair has no ray: " << io::format_case(c); return;
  }
}

/// Exact barycentrics (b1, b2) of the plane point, computed here independently of the library:
/// u_i / den with u_1 = d . ((p2 - o) x (p0 - o)), u_2 = d . ((p0 - o) x (p1 - o)),
/// den = d . ((p1 - p0) x (p2 - p0)) (must be nonzero).
inline std::pair<mpq_class, mpq_class> exact_barycentrics(const Ray<double>& ray, const Triangle<double>& tri) {
  struct V {
    mpq_class x, y, z;
  };
  auto q = [](const Vec3<double>& v) { return V{v.x, v.y, v.z}; };
  auto sub = [](const V& a, const V& b) { return V{a.x - b.x, a.y - b.y, a.z - b.z}; };
  auto crs = [](const V& a, const V& b) {
    return V{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  };
  auto dt = [](const V& a, const V& b) { return mpq_class(a.x * b.x + a.y * b.y + a.z * b.z); };
  const V o = q(ray.o), d = q(ray.d), p0 = q(tri.p0), p1 = q(tri.p1), p2 = q(tri.p2);
  const V a = sub(p0, o), b = sub(p1, o), c = sub(p2, o);
  const mpq_class den = dt(d, crs(sub(p1, p0), sub(p2, p0)));
  return {dt(d, crs(c, a)) / den, dt(d, crs(a, b)) / den};
}

/// True when x is the double nearest to the rational b (b within half an ulp on either side).
inline bool rounded_to_nearest(double x, const mpq_class& b) {
  const double lo = std::nextafter(x, -INFINITY), hi = std::nextafter(x, INFINITY);
  const mpq_class mid_lo = (mpq_class(lo) + mpq_class(x)) / 2, mid_hi = (mpq_class(x) + mpq_class(hi)) / 2;
  return mid_lo <= b && b <= mid_hi;
}

/// The triangle families of the generator (every case a triangle).
inline std::vector<const gen::Family*> triangle_families() {
  std::vector<const gen::Family*> out;
  for (const auto& f : gen::families())
    if (f.kind == io::Kind::triangle && !f.every_kind) out.push_back(&f);
  return out;
}

/// Equal doubles, NaN equal to NaN, and +0.0 distinguished from -0.0.
inline bool same(double a, double b) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return a == b && std::signbit(a) == std::signbit(b);
}

}  // namespace rayproof::api_test
