#pragma once
/// The classes of a triangle/triangle query (docs/tritri.md): what exact arithmetic on the two
/// closed triangles' doubles says about their intersection. Each class is defined there by the
/// signs of orient3d and orient2d on the six vertices, so the exact class is unique.
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

#include "rayproof/contact.h"

namespace rayproof {

enum class TriTri : std::uint8_t {
  disjoint,           ///< the closed triangles share no point
  crossing,           ///< not coplanar; some point lies in the relative interiors of both
  touching,           ///< not coplanar; they meet, but no point is interior to both
  coplanar_overlap,   ///< coplanar; the intersection has positive area
  coplanar_touching,  ///< coplanar; they meet in a segment or a point only
  degenerate,         ///< a triangle has zero area (collinear or coincident vertices)
  invalid,            ///< a coordinate is NaN or infinite
};

inline constexpr std::array<std::string_view, 7> kTriTriNames = {
    "disjoint", "crossing", "touching", "coplanar_overlap", "coplanar_touching", "degenerate", "invalid"};

[[nodiscard]] constexpr std::string_view to_string(TriTri c) { return kTriTriNames[static_cast<std::size_t>(c)]; }

[[nodiscard]] constexpr std::optional<TriTri> tritri_from_string(std::string_view s) {
  for (std::size_t i = 0; i < kTriTriNames.size(); ++i)
    if (kTriTriNames[i] == s) return static_cast<TriTri>(i);
  return std::nullopt;
}

/// True for the classes in which two non-degenerate triangles share at least one point; the
/// answer an intersect-or-not test (Möller, Guigue–Devillers) must give. False for degenerate and
/// invalid (their contact is not decided by the class).
[[nodiscard]] constexpr bool meets(TriTri c) {
  return c == TriTri::crossing || c == TriTri::touching || c == TriTri::coplanar_overlap ||
         c == TriTri::coplanar_touching;
}

/// The class as a case-file contact (docs/cases.md: a `tritri` case answers with these).
[[nodiscard]] constexpr Contact to_contact(TriTri c) {
  switch (c) {
    case TriTri::disjoint: return Contact::disjoint;
    case TriTri::crossing: return Contact::crossing;
    case TriTri::touching: return Contact::touching;
    case TriTri::coplanar_overlap: return Contact::coplanar_overlap;
    case TriTri::coplanar_touching: return Contact::coplanar_touching;
    case TriTri::degenerate: return Contact::degenerate;
    case TriTri::invalid: break;
  }
  return Contact::invalid;
}

/// The TriTri class of a contact, nothing for a contact no pair has (a ray class, `error`).
[[nodiscard]] constexpr std::optional<TriTri> tritri_of(Contact c) {
  switch (c) {
    case Contact::disjoint: return TriTri::disjoint;
    case Contact::crossing: return TriTri::crossing;
    case Contact::touching: return TriTri::touching;
    case Contact::coplanar_overlap: return TriTri::coplanar_overlap;
    case Contact::coplanar_touching: return TriTri::coplanar_touching;
    case Contact::degenerate: return TriTri::degenerate;
    case Contact::invalid: return TriTri::invalid;
    default: return std::nullopt;
  }
}

}  // namespace rayproof
