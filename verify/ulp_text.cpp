#include "verify/ulp_text.h"

#include <fmt/core.h>

#include <cmath>

namespace rayproof::verify {

namespace {
int mantissa_bits(Precision p) { return p == Precision::float32 ? 23 : 52; }
}  // namespace

std::string ulp_note(std::uint64_t u, Precision p) {
  if (u == kNaNUlps || u < 1000000) return "";
  const int m = mantissa_bits(p);
  if ((u >> m) != 0) return "leading bits wrong";
  return fmt::format("rel. <= {:.0e}", std::ldexp(double(u), -m));
}

std::string ulp_number(std::uint64_t u) {
  if (u == kNaNUlps) return "NaN t";
  return u < 1000000 ? std::to_string(u) : fmt::format("{:.2g}", double(u));
}

std::string ulp_text(std::uint64_t u, Precision p) {
  const std::string note = ulp_note(u, p);
  return note.empty() ? ulp_number(u) : ulp_number(u) + " (" + note + ")";
}

}  // namespace rayproof::verify
