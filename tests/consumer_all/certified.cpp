// rayproof::certified: exact classes on a contact of every kind that only exact signs decide
// (an edge, a tangent, a graze, a rim), each answer constructed so that its t is an exact double.
#include <verify/certified.h>

#include <cstdio>

#include "checks.h"

namespace {

struct Expected {
  rayproof::io::Case c;
  rayproof::Contact contact;
  double t;
};

}  // namespace

int check_certified() {
  using rayproof::Contact;
  using rayproof::io::Kind;
  const Expected cases[] = {
      {{Kind::plane, {0, 0, 0, 0, 0, 1, 0, 0, 3, 0, 0, 1}}, Contact::hit, 3},
      {{Kind::sphere, {-3, 1, 0, 1, 0, 0, 0, 0, 0, 1}}, Contact::tangent, 3},
      {{Kind::ellipsoid, {-4, 0, 2, 1, 0, 0, 0, 0, 0, 2, 3, 2}}, Contact::tangent, 4},
      {{Kind::triangle, {2, 0, 5, 0, 0, -1, 0, 0, 0, 4, 0, 0, 0, 4, 0}}, Contact::edge, 5},
      {{Kind::box, {-1, 0, 0.5, 1, 1, 0, 0, 0, 0, 1, 1, 1}}, Contact::graze, 1},
      {{Kind::disk, {3, 4, 2, 0, 0, -1, 0, 0, 0, 0, 0, 1, 5}}, Contact::rim, 2},
  };
  int failures = 0;
  for (const auto& e : cases) {
    const auto r = rayproof::verify::certified_classify(e.c);
    if (r.contact != e.contact || !r.t || *r.t != e.t) {
      std::printf("certified: %s gave %s, want %s %g\n", rayproof::io::format_case(e.c).c_str(),
                  rayproof::io::format_result(r).c_str(), to_string(e.contact).data(), e.t);
      ++failures;
    }
  }
  std::printf("certified: %zu kinds checked, %d failures\n", std::size(cases), failures);
  return failures;
}
