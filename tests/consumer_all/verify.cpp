// rayproof::verify: exact answers agree with the certified ones on seeded random cases of every kind.
#include <verify/certified.h>
#include <verify/exact.h>

#include <cmath>
#include <cstdint>
#include <cstdio>

#include "checks.h"

namespace {

// A fixed-seed generator (splitmix64): the same cases on every machine.
struct Rng {
  std::uint64_t s;
  double next() {
    std::uint64_t z = (s += 0x9e3779b97f4a7c15u);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    return static_cast<double>((z ^ (z >> 31)) >> 11) * 0x1p-53 * 8 - 4;  // [-4, 4)
  }
};

}  // namespace

int check_verify() {
  using namespace rayproof;
  Rng rng{12};
  int failures = 0, compared = 0;
  for (const auto kind : io::kAllKinds) {
    for (int i = 0; i < 50; ++i) {
      io::Case c{kind, {}};
      for (int k = 0; k < io::field_count(kind); ++k) c.v[k] = rng.next();
      if (kind == io::Kind::sphere) c.v[9] = std::fabs(c.v[9]);
      if (kind == io::Kind::ellipsoid)
        for (int k = 9; k < 12; ++k) c.v[k] = std::fabs(c.v[k]);
      if (kind == io::Kind::disk) c.v[12] = std::fabs(c.v[12]);
      if (kind == io::Kind::box)
        for (int k = 6; k < 9; ++k)
          if (c.v[k] > c.v[k + 3]) std::swap(c.v[k], c.v[k + 3]);
      const auto exact = verify::exact_classify(c);
      const auto cert = verify::certified_classify(c);
      ++compared;
      const auto ulps = [](std::optional<double> a, std::optional<double> b) {
        if (!a || !b) return a.has_value() == b.has_value() ? 0.0 : 1e9;
        return std::fabs(*a - *b) / std::fabs(std::nextafter(*b, INFINITY) - *b);
      };
      if (exact.contact != cert.contact || ulps(cert.t, exact.t) > 1 || ulps(cert.t2, exact.t2) > 1) {
        std::printf("verify: %s exact %s certified %s\n", io::format_case(c).c_str(),
                    io::format_result(exact).c_str(), io::format_result(cert).c_str());
        ++failures;
      }
    }
  }
  std::printf("verify: %d cases compared with exact, %d failures\n", compared, failures);
  return failures;
}
