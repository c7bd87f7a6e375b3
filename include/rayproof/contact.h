#pragma once
/// The contact classes of docs/cases.md: the contract between fast and exact methods. A ray case
/// answers with the classes up to `error`; a triangle/triangle case (kind `tritri`) with the five
/// after it or `invalid` / `degenerate` (docs/tritri.md; rayproof::TriTri, tritri_class.h).
#include <array>
#include <cstdint>
#include <optional>
#include <string_view>

namespace rayproof {

enum class Contact : std::uint8_t {
  invalid,     ///< NaN or infinite field, zero direction, negative size, inverted box
  degenerate,  ///< the primitive has no interior (zero normal, zero radius, collinear triangle)
  parallel,    ///< direction parallel to the plane, origin off it
  coplanar,    ///< the ray lies in the plane
  miss,        ///< the line misses the primitive
  behind,      ///< the line meets the primitive only at t < 0
  interior,    ///< triangle: hit with all barycentrics > 0
  edge,        ///< triangle: hit with exactly one barycentric = 0
  vertex,      ///< triangle: hit with two barycentrics = 0
  hit,         ///< plane, quadric, box, disk: an ordinary hit at t >= 0
  tangent,     ///< quadric: a double root at t >= 0
  inside,      ///< quadric, box: the origin is inside (T < 0 <= T2)
  graze,       ///< box: the ray touches the box at one point
  rim,         ///< disk: hit exactly on the circle
  error,       ///< not a class: the case line could not be read (CLI output only)
  // Triangle against triangle (TriTri; appended so that the values above keep their numbers):
  disjoint,           ///< the closed triangles share no point
  crossing,           ///< not coplanar; some point lies in the relative interiors of both
  touching,           ///< not coplanar; they meet, but no point is interior to both
  coplanar_overlap,   ///< coplanar; the intersection has positive area
  coplanar_touching,  ///< coplanar; they meet in a segment or a point only
};

inline constexpr std::array<std::string_view, 20> kContactNames = {
    "invalid", "degenerate", "parallel", "coplanar", "miss",   "behind", "interior", "edge",
    "vertex",  "hit",        "tangent",  "inside",   "graze",  "rim",    "error",
    "disjoint", "crossing", "touching", "coplanar_overlap", "coplanar_touching"};

[[nodiscard]] constexpr std::string_view to_string(Contact c) { return kContactNames[static_cast<std::size_t>(c)]; }

[[nodiscard]] constexpr std::optional<Contact> contact_from_string(std::string_view s) {
  for (std::size_t i = 0; i < kContactNames.size(); ++i)
    if (kContactNames[i] == s) return static_cast<Contact>(i);
  return std::nullopt;
}

/// True for the classes in which the ray touches the primitive at some t >= 0, and for the
/// triangle/triangle classes in which the two triangles meet (rayproof::meets).
[[nodiscard]] constexpr bool is_hit(Contact c) {
  switch (c) {
    case Contact::interior: case Contact::edge: case Contact::vertex: case Contact::hit:
    case Contact::tangent: case Contact::inside: case Contact::graze: case Contact::rim:
    case Contact::crossing: case Contact::touching: case Contact::coplanar_overlap: case Contact::coplanar_touching:
      return true;
    default:
      return false;
  }
}

/// True for the classes only a triangle/triangle case has (disjoint ... coplanar_touching).
[[nodiscard]] constexpr bool is_pair_class(Contact c) {
  return c == Contact::disjoint || c == Contact::crossing || c == Contact::touching || c == Contact::coplanar_overlap ||
         c == Contact::coplanar_touching;
}

}  // namespace rayproof
