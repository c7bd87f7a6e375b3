// rayproof::certified: certified::intersect on a contact of every kind that only exact signs decide
// (an edge, a tangent, a graze, a rim), each built so that its t is an exact double.
#include <rayproof/certified/intersect.h>
#include <rayproof/certified/tritri.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "checks.h"

namespace {

int expect(const char* what, rayproof::Contact got, double t, rayproof::Contact want, double want_t) {
  if (got == want && t == want_t) return 0;
  std::printf("certified: %s gave %s %g, want %s %g\n", what, to_string(got).data(), t, to_string(want).data(), want_t);
  return 1;
}

}  // namespace

int check_certified() {
  using namespace rayproof;
  using V = Vec3<double>;
  int failures = 0;
  failures += expect("plane", certified::intersect(Ray<double>{V{0, 0, 0}, V{0, 0, 1}}, Plane<double>{V{0, 0, 3}, V{0, 0, 1}}).contact,
                     3, Contact::hit, 3);
  const auto sphere = certified::intersect(Ray<double>{V{-3, 1, 0}, V{1, 0, 0}}, Sphere<double>{V{0, 0, 0}, 1});
  failures += expect("sphere", sphere.contact, sphere.t, Contact::tangent, 3);
  const auto ell = certified::intersect(Ray<double>{V{-4, 0, 2}, V{1, 0, 0}}, Ellipsoid<double>{V{0, 0, 0}, V{2, 3, 2}});
  failures += expect("ellipsoid", ell.contact, ell.t, Contact::tangent, 4);
  const auto tri = certified::intersect(Ray<double>{V{2, 0, 5}, V{0, 0, -1}}, Triangle<double>{V{0, 0, 0}, V{4, 0, 0}, V{0, 4, 0}});
  failures += expect("triangle", tri.contact, tri.t, Contact::edge, 5);
  if (tri.b1 != 0.5 || tri.b2 != 0) {
    std::printf("certified: triangle barycentrics %g %g, want 0.5 0\n", tri.b1, tri.b2);
    ++failures;
  }
  const auto box = certified::intersect(Ray<double>{V{-1, 0, 0.5}, V{1, 1, 0}}, Box<double>{V{0, 0, 0}, V{1, 1, 1}});
  failures += expect("box", box.contact, box.t, Contact::graze, 1);
  const auto disk = certified::intersect(Ray<double>{V{3, 4, 2}, V{0, 0, -1}}, Disk<double>{V{0, 0, 0}, V{0, 0, 1}, 5});
  failures += expect("disk", disk.contact, disk.t, Contact::rim, 2);
  // Triangle/triangle: a vertex exactly on the other's face, at 2^600 (GMP decides the signs).
  const double s = std::ldexp(1.0, 600);
  const Triangle<double> ta{V{0, 0, 0}, V{4 * s, 0, 0}, V{0, 4 * s, 0}}, tb{V{s, s, 0}, V{s, s, s}, V{2 * s, s, s}};
  if (certified::tritri(ta, tb) != TriTri::touching) {
    std::printf("certified: tritri gave %s, want touching\n", to_string(certified::tritri(ta, tb)).data());
    ++failures;
  }
  std::printf("certified: 6 kinds and a triangle pair checked, %d failures\n", failures);
  return failures + check_certified_sample();
}

namespace {

bool within_one_ulp(double got, const std::string& want_text) {
  if (want_text == "-") return true;  // the class carries no such value
  const double want = std::strtod(want_text.c_str(), nullptr);
  return got == want || got == std::nextafter(want, INFINITY) || got == std::nextafter(want, -INFINITY);
}

}  // namespace

// The shared sample (the tree's data/sample.txt, a copy of shared/cases/sample.txt, with its
// independently computed sample.expected) through certified::intersect, read by this program's own
// few lines of parsing: the expected class on every case, t and t2 within one ulp.
int check_certified_sample() {
  using namespace rayproof;
  using V = Vec3<double>;
  const char* dir = std::getenv("RAYPROOF_SAMPLE_DIR");
  if (!dir) {
    std::printf("certified sample: RAYPROOF_SAMPLE_DIR is not set\n");
    return 1;
  }
  std::ifstream cases(std::string(dir) + "/sample.txt"), expected(std::string(dir) + "/sample.expected");
  if (!cases || !expected) {
    std::printf("certified sample: cannot read %s/sample.txt and sample.expected\n", dir);
    return 1;
  }
  int n = 0, failures = 0;
  std::string line, want_line;
  while (std::getline(cases, line)) {
    std::istringstream in(line.substr(0, line.find('#')));
    std::string kind, tok;
    if (!(in >> kind)) continue;
    std::vector<double> v;
    while (in >> tok) v.push_back(std::strtod(tok.c_str(), nullptr));
    if (!std::getline(expected, want_line)) {
      std::printf("certified sample: sample.expected ends before case %d\n", n + 1);
      return failures + 1;
    }
    ++n;
    v.resize(15, 0.0);
    auto at = [&](int i) { return V{v[i], v[i + 1], v[i + 2]}; };
    const Ray<double> ray{at(0), at(3)};
    Hit<double> h;
    if (kind == "plane") h = certified::intersect(ray, Plane<double>{at(6), at(9)});
    else if (kind == "sphere") h = certified::intersect(ray, Sphere<double>{at(6), v[9]});
    else if (kind == "ellipsoid") h = certified::intersect(ray, Ellipsoid<double>{at(6), at(9)});
    else if (kind == "box") h = certified::intersect(ray, Box<double>{at(6), at(9)});
    else if (kind == "disk") h = certified::intersect(ray, Disk<double>{at(6), at(9), v[12]});
    else if (kind == "triangle") {
      const auto th = certified::intersect(ray, Triangle<double>{at(6), at(9), at(12)});
      h = {th.contact, th.t, th.t2};
    } else {
      std::printf("certified sample: case %d: unknown kind '%s'\n", n, kind.c_str());
      ++failures;
      continue;
    }
    std::istringstream w(want_line);
    std::string cls, t, t2;
    w >> cls >> t >> t2;
    if (to_string(h.contact) != cls || !within_one_ulp(h.t, t) || !within_one_ulp(h.t2, t2)) {
      std::printf("certified sample: case %d (%s): got %s %.17g %.17g, expected %s\n", n, kind.c_str(),
                  to_string(h.contact).data(), h.t, h.t2, want_line.c_str());
      ++failures;
    }
  }
  if (n < 100) {
    std::printf("certified sample: only %d cases read\n", n);
    ++failures;
  }
  std::printf("certified sample: %d cases, %d failures\n", n, failures);
  return failures;
}
