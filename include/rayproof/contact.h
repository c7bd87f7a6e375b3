#pragma once
/// The contact classes of docs/cases.md: the contract between fast and exact methods.
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
};

inline constexpr std::array<std::string_view, 15> kContactNames = {
    "invalid", "degenerate", "parallel", "coplanar", "miss",   "behind", "interior", "edge",
    "vertex",  "hit",        "tangent",  "inside",   "graze",  "rim",    "error"};

[[nodiscard]] constexpr std::string_view to_string(Contact c) { return kContactNames[static_cast<std::size_t>(c)]; }

[[nodiscard]] constexpr std::optional<Contact> contact_from_string(std::string_view s) {
  for (std::size_t i = 0; i < kContactNames.size(); ++i)
    if (kContactNames[i] == s) return static_cast<Contact>(i);
  return std::nullopt;
}

/// True for the classes in which the ray touches the primitive at some t >= 0.
[[nodiscard]] constexpr bool is_hit(Contact c) {
  switch (c) {
    case Contact::interior: case Contact::edge: case Contact::vertex: case Contact::hit:
    case Contact::tangent: case Contact::inside: case Contact::graze: case Contact::rim:
      return true;
    default:
      return false;
  }
}

}  // namespace rayproof
