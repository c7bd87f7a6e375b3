#pragma once
/// Internals of the generator (not installed): the integer lattice on which exact contacts are
/// built, its exact placement into doubles, and the per-kind family generators.
///
/// Exact families build a case with small integers (a contact point at a dyadic fraction along an
/// edge becomes an integer after scaling the whole lattice by 2^m), check every exactness
/// condition in integer arithmetic, then place it: an axis permutation with sign flips (an
/// isometry of the lattice), an integer offset, and power-of-two scales 2^e for positions and
/// lengths, 2^f for the direction, 2^g for a normal. Each of those maps the case to one of the same
/// class, and each value is emitted only if it converts to a double (or, for float precision, a
/// float) exactly; otherwise the case is drawn again.
#include <array>
#include <cstdint>
#include <optional>

#include "gen/families.h"
#include "gen/rng.h"
#include "rayproof/vec3.h"

namespace rayproof::gen::detail {

inline bool is_float(Precision p) { return p == Precision::float32; }

using i64 = std::int64_t;
__extension__ using i128 = __int128;
using I3 = std::array<i64, 3>;
using D3 = Vec3<double>;

constexpr I3 add(I3 a, I3 b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
constexpr I3 sub(I3 a, I3 b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
constexpr I3 mul(I3 a, i64 k) { return {a[0] * k, a[1] * k, a[2] * k}; }
constexpr bool is_zero(I3 a) { return a[0] == 0 && a[1] == 0 && a[2] == 0; }
/// Cross product; the caller keeps |components| < 2^31 so it cannot overflow.
constexpr I3 cross(I3 a, I3 b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
constexpr i128 dot(I3 a, I3 b) {
  return static_cast<i128>(a[0]) * b[0] + static_cast<i128>(a[1]) * b[1] + static_cast<i128>(a[2]) * b[2];
}
/// (b - a) x (c - a) is zero, in 128-bit arithmetic (components below 2^62).
bool collinear(I3 a, I3 b, I3 c);
/// Number of bits of |x| (0 for 0).
int bit_length(i64 x);
/// Largest |component| over the vectors.
i64 max_abs(std::initializer_list<I3> vs);

/// A random integer vector with components in [-2^bits, 2^bits], not zero.
I3 rand_ivec(Rng& r, int bits);
/// A Pythagorean quadruple: an integer vector whose length is the integer `len` (> 0), with
/// |components| <= 2^bits roughly; sometimes axis-aligned or a planar Pythagorean triple.
I3 pythagorean(Rng& r, int bits, i64& len);

/// Mantissa bits of the emitted numbers: 24 (float) or 53 (double).
constexpr int mant_bits(Precision p) { return p == Precision::float32 ? 24 : 53; }

/// A case on the integer lattice. Which members are used depends on the kind:
/// triangle p[0..2]; sphere centre p[0], radius r; ellipsoid centre p[0], semi-axes s;
/// box lo p[0], hi p[1]; plane point p[0], normal n; disk centre p[0], normal n, radius r.
struct LCase {
  io::Kind kind = io::Kind::plane;
  I3 o{}, d{};
  std::array<I3, 3> p{};
  I3 n{}, s{};
  i64 r = 0;
  /// Exponent of the direction's tilt (near-parallel families): the emitted direction is
  /// d + tilt * 2^-tilt_shift along axis tilt_axis of the lattice frame, and o gets o_tilt * 2^-tilt_shift.
  int tilt_shift = 0;
  int tilt_axis = 2;
  i64 tilt = 0, o_tilt = 0;
};

/// How a lattice case is placed: output axis i = sign[i] * lattice axis perm[i]; positions get
/// `off` (in lattice units) and the scale 2^e; the direction 2^f; the normal 2^g.
struct Place {
  std::array<int, 3> perm{0, 1, 2};
  std::array<int, 3> sign{1, 1, 1};
  int e = 0, f = 0, g = 0;
  I3 off{};
  std::array<bool, 3> neg_zero{};  ///< a zero direction or normal component is emitted as -0.0
};

struct PlaceOpts {
  int e_lo = 0, e_hi = 0;  ///< position scale exponent range
  int f_lo = 0, f_hi = 0;  ///< direction scale exponent range
  int g_lo = 0, g_hi = 0;  ///< normal scale exponent range
  int off_lo = -1, off_hi = -1;  ///< offset magnitude bits; -1: no offset
  bool always_offset = false;  ///< else an offset two times in three
  bool permute = true;
  std::array<bool, 3> offset_axis{true, true, true};  ///< lattice axes that may be offset
};

/// The usual placement ranges for a precision (moderate scales, offsets sometimes).
PlaceOpts default_opts(Precision p);
/// A random placement within the options (offset bits capped so that positions stay exact).
Place random_place(Rng& r, Precision p, const LCase& c, const PlaceOpts& o);
/// The case as doubles, or nothing when some value would not be exact in the precision.
std::optional<io::Case> emit(const LCase& c, const Place& pl, Precision p);
/// m * 2^e when exactly representable in the precision.
std::optional<double> put(i64 m, int e, Precision p);

/// x rounded to the nearest float, as a double. Through a volatile float: g++ 12 at -O3 (SLP
/// vectorizer) was seen to drop a double -> float -> double round trip built in a lambda, emitting
/// the unrounded double; the volatile store cannot be elided.
double to_float(double x);
/// Rounds every field to float when the precision is float32 (random families).
void finish(io::Case& c, Precision p);
/// A random direction (uniform on the sphere, by rejection from the cube; not exactly unit).
D3 rand_unit(Rng& r);
/// Uniform in the cube [-h, h]^3.
D3 rand_box(Rng& r, double h);
D3 normalize(D3 v);
void set3(io::Case& c, std::size_t at, D3 v);

/// Generates one case of a family; `p` decides the bit budget. Never fails (draws again inside).
using CaseFn = io::Case (*)(Rng& r, Precision p);

/// Draws with `make` until the case converts exactly (a bounded number of tries; the budgets are
/// chosen so that a try almost always succeeds).
template <class Make>
io::Case retry(Rng& r, Precision p, Make&& make) {
  for (int attempt = 0;; ++attempt) {
    if (std::optional<io::Case> c = make(r, p)) return *c;
    if (attempt > 100000) return {};  // unreachable with the budgets used; keeps the loop finite
  }
}

// Family generators, by kind group (families_*.cpp).
io::Case tri_generic(Rng&, Precision);
io::Case tri_interior_exact(Rng&, Precision);
io::Case tri_edge(Rng&, Precision);
io::Case tri_vertex(Rng&, Precision);
io::Case tri_offset_big(Rng&, Precision);
io::Case tri_coplanar(Rng&, Precision);
io::Case tri_parallel(Rng&, Precision);
io::Case tri_near_parallel(Rng&, Precision);
io::Case tri_degenerate(Rng&, Precision);
io::Case tri_sliver(Rng&, Precision);
io::Case tri_behind(Rng&, Precision);
io::Case tri_far_small(Rng&, Precision);
io::Case tri_extreme_scale(Rng&, Precision);
io::Case tri_vertex_aimed_float(Rng&, Precision);

io::Case sph_generic(Rng&, Precision);
io::Case sph_tangent_exact(Rng&, Precision);
io::Case sph_on_surface(Rng&, Precision);
io::Case sph_inside_behind(Rng&, Precision);
io::Case ell_generic(Rng&, Precision);
io::Case ell_tangent_exact(Rng&, Precision);
io::Case ell_on_surface(Rng&, Precision);
io::Case ell_stiff(Rng&, Precision);

io::Case box_generic(Rng&, Precision);
io::Case box_graze(Rng&, Precision);
io::Case box_axis_parallel(Rng&, Precision);
io::Case box_flat(Rng&, Precision);
io::Case plane_generic(Rng&, Precision);
io::Case plane_exact(Rng&, Precision);
io::Case plane_near_parallel(Rng&, Precision);
io::Case disk_generic(Rng&, Precision);
io::Case disk_rim(Rng&, Precision);
io::Case invalid_mix(Rng&, Precision);

}  // namespace rayproof::gen::detail
