#pragma once
/// Stiffness knobs: case generators with one stiffness parameter made explicit, for the stability
/// curves of `rayproof report` (docs/stability.md).
///
/// A knob is swept in powers of two: at exponent k its value is 2^k (an offset over size of 2^k, a
/// tilt of 2^k with k < 0, ...). `generate_knob(knob, k, count, seed)` gives `count` cases whose
/// knob value is 2^k, built in double precision; every case carries `.family` = step_name(knob, k).
/// Deterministic: the same (knob, k, count, seed) gives the same cases on any machine (own PRNG, no
/// FMA contraction), drawn from a stream seeded from (seed, knob name, k), so a step's cases do not
/// depend on which other steps are generated. The families of gen/families.h are untouched.
///
/// Where the knob allows it, the values are small integers times powers of two, exact in float as
/// well (so a float method sees the same case): the tilts, the magnitudes up to float's range, the
/// ellipsoid axes. Where the knob cannot be represented at the precision (an offset of 2^60 over a
/// triangle's size, a tangency gap of 2^-60), the emitted doubles are the nearest ones and the
/// expected answer is the exact one on them, as everywhere else.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/case_file.h"

namespace rayproof::gen {

struct Knob {
  std::string name;      ///< e.g. "offset"
  io::Kind kind;
  std::string quantity;  ///< what 2^k measures, e.g. "offset / size"
  std::string stresses;  ///< one line
  std::vector<int> exponents;  ///< the steps k swept by default, increasing stiffness order
};

/// Every knob, in a stable order.
[[nodiscard]] const std::vector<Knob>& knobs();
[[nodiscard]] const Knob* find_knob(std::string_view name);

/// The group name of a step's cases: "NAME@K" (e.g. "tilt_triangle@-24").
[[nodiscard]] std::string step_name(const Knob& k, int exponent);
/// Parses a step name back into (knob, exponent); nothing when it is not one.
[[nodiscard]] std::optional<std::pair<const Knob*, int>> parse_step_name(std::string_view group);

/// `count` cases of the knob at value 2^exponent (any exponent the knob's construction allows:
/// see knobs.cpp; the default exponents always work).
[[nodiscard]] std::vector<io::Case> generate_knob(const Knob& k, int exponent, std::size_t count, std::uint64_t seed);

}  // namespace rayproof::gen
