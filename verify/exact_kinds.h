#pragma once
/// The exact method per kind (internal to rayproof_verify). Each takes a case that exact_classify
/// has already screened: every field finite, d != 0, no negative size, no inverted box, no zero
/// normal / radius / semi-axis. Only the triangle's degeneracy (collinear vertices) needs exact
/// arithmetic and is decided by exact_triangle itself.
#include "io/case_file.h"

namespace rayproof::verify {

[[nodiscard]] io::CaseResult exact_plane(const io::Case& c);
[[nodiscard]] io::CaseResult exact_disk(const io::Case& c);
[[nodiscard]] io::CaseResult exact_sphere(const io::Case& c);
[[nodiscard]] io::CaseResult exact_ellipsoid(const io::Case& c);
[[nodiscard]] io::CaseResult exact_triangle(const io::Case& c);
[[nodiscard]] io::CaseResult exact_box(const io::Case& c);

}  // namespace rayproof::verify
