/// The exact method: ground truth of CASES.md. Screening (invalid, then degenerate) compares the
/// parsed doubles directly, which is exact; the per-kind geometry is in exact_*.cpp, in rationals.
#include "verify/exact.h"

#include <cmath>

#include "verify/exact_kinds.h"

namespace rayproof::verify {

namespace {

bool all_zero(const io::Case& c, std::size_t i) { return c.v[i] == 0 && c.v[i + 1] == 0 && c.v[i + 2] == 0; }

bool any_negative(const io::Case& c, std::size_t i, std::size_t count) {
  for (std::size_t k = i; k < i + count; ++k)
    if (c.v[k] < 0) return true;
  return false;
}

bool any_zero(const io::Case& c, std::size_t i, std::size_t count) {
  for (std::size_t k = i; k < i + count; ++k)
    if (c.v[k] == 0) return true;
  return false;
}

/// NaN or infinite field, d = 0, negative radius or semi-axis, box with lo > hi on an axis.
bool is_invalid(const io::Case& c) {
  const auto n = static_cast<std::size_t>(io::field_count(c.kind));
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(c.v[i])) return true;
  if (all_zero(c, 3)) return true;
  switch (c.kind) {
    case io::Kind::sphere: return any_negative(c, 9, 1);
    case io::Kind::ellipsoid: return any_negative(c, 9, 3);
    case io::Kind::disk: return any_negative(c, 12, 1);
    case io::Kind::box: return c.v[6] > c.v[9] || c.v[7] > c.v[10] || c.v[8] > c.v[11];
    case io::Kind::plane: case io::Kind::triangle: return false;
  }
  return false;
}

/// Zero normal, radius or semi-axis. (A collinear triangle is decided exactly by exact_triangle;
/// a box with lo = hi is flat, not degenerate.)
bool is_degenerate(const io::Case& c) {
  switch (c.kind) {
    case io::Kind::plane: return all_zero(c, 9);
    case io::Kind::sphere: return c.v[9] == 0;
    case io::Kind::ellipsoid: return any_zero(c, 9, 3);
    case io::Kind::disk: return all_zero(c, 9) || c.v[12] == 0;
    case io::Kind::triangle: case io::Kind::box: return false;
  }
  return false;
}

}  // namespace

io::CaseResult exact_classify(const io::Case& c) {
  if (is_invalid(c)) return {Contact::invalid, std::nullopt, std::nullopt};
  if (is_degenerate(c)) return {Contact::degenerate, std::nullopt, std::nullopt};
  switch (c.kind) {
    case io::Kind::plane: return exact_plane(c);
    case io::Kind::sphere: return exact_sphere(c);
    case io::Kind::ellipsoid: return exact_ellipsoid(c);
    case io::Kind::triangle: return exact_triangle(c);
    case io::Kind::box: return exact_box(c);
    case io::Kind::disk: return exact_disk(c);
  }
  return {Contact::error, std::nullopt, std::nullopt};
}

void register_exact_method(MethodRegistry& reg) {
  reg.add({"exact",
           "ground truth: exact rationals (CGAL Gmpq) decide the class; T, T2 rounded to nearest (MPFR, "
           "checked exactly)",
           Precision::float64, std::vector<io::Kind>(io::kAllKinds.begin(), io::kAllKinds.end()), exact_classify, {}});
}

}  // namespace rayproof::verify
