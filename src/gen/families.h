#pragma once
/// The deterministic adversarial case generator behind `rayproof gen`.
///
/// A family is one kind of primitive and one situation that stresses a kernel (an exact edge hit,
/// a tangent, a ray nearly parallel to a plane, huge offsets, ...). Families that claim a contact
/// build it exactly: every emitted case is in the claimed class under exact arithmetic on the
/// emitted doubles (docs/cases.md), which the tests check against the exact method.
///
/// Determinism: the same (family, count, seed, precision) gives the same cases, bit for bit, on any
/// machine and compiler (own PRNG and mappings, see rng.h; no FMA contraction). Each family draws
/// from its own stream, seeded from (seed, family name), so a family's cases do not depend on
/// which other families are generated, and the first N cases of a run with count M >= N are the
/// cases of a run with count N.
///
/// Precision::float32: every emitted number is exactly a float, so the float-rounded case
/// (io::round_to_float) is the same case and keeps its class.
///
/// The triangle-pair families (kind tritri, named tritri_NAME) are tritri_families.h's pair
/// families as case lines; in float their coordinates are rounded to float (the class may then
/// differ from the construction's; `classes` lists what either precision gives).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "io/case_file.h"
#include "rayproof/contact.h"

namespace rayproof::gen {

enum class Precision { float32, float64 };

struct Family {
  std::string name;
  io::Kind kind;
  std::string stresses;  ///< one line: what it stresses
  /// Every case of the family is in one of these classes under exact arithmetic. For the families
  /// built around an exact contact this is a guarantee of the construction; for the random ones it
  /// lists what they produce.
  std::vector<Contact> classes;
  /// The family mixes every kind (`invalid`); `kind` is then only its first case's kind.
  bool every_kind = false;
};

/// Every family, in a stable order.
[[nodiscard]] const std::vector<Family>& families();
/// The family of that name, or nullptr.
[[nodiscard]] const Family* find_family(std::string_view name);
/// Comma-separated names of every family (for messages).
[[nodiscard]] std::string family_names();

/// A triangle pair as a `tritri` case (a's vertices, then b's).
struct TriPair;
[[nodiscard]] io::Case tritri_case(const TriPair& p);

/// `count` cases of the family; each has `.family` = the family's name and `.line` = 0.
[[nodiscard]] std::vector<io::Case> generate(const Family& f, std::size_t count, std::uint64_t seed, Precision p);

/// The same cases, one at a time (for outputs too large to hold).
void generate_each(const Family& f, std::size_t count, std::uint64_t seed, Precision p,
                   const std::function<void(const io::Case&)>& sink);

}  // namespace rayproof::gen
