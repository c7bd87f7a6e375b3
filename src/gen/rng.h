#pragma once
/// The generator's pseudo-random numbers, bit-for-bit the same on every machine and compiler.
///
/// The standard <random> engines are portable but its distributions (uniform_real_distribution,
/// normal_distribution, ...) are implementation-defined, so the generator never uses them. Instead:
/// - xoshiro256** 1.0 (D. Blackman, S. Vigna, "Scrambled linear pseudorandom number generators",
///   ACM TOMS 47(4), 2021; reference code https://prng.di.unimi.it/xoshiro256starstar.c),
///   seeded by
/// - splitmix64 (G. Steele, D. Lea, C. Flood, "Fast splittable pseudorandom number generators",
///   OOPSLA 2014; reference code https://prng.di.unimi.it/splitmix64.c), as its authors advise;
/// - doubles from the top 53 bits times 2^-53 (exact: no rounding anywhere);
/// - integers in a range by Lemire's multiply-shift with rejection ("Fast random integer generation
///   in an interval", ACM TOMACS 29(1), 2019), which is exactly uniform.
/// All of it is integer arithmetic or exact floating-point scaling.
///
/// Callers must never put two draws in one expression whose evaluation order C++ leaves open
/// (two arguments of one call, two operands of `*`): compilers differ there. Braced initializer
/// lists and separate declarations are evaluated in order.
#include <array>
#include <cmath>
#include <cstdint>
#include <string_view>

namespace rayproof::gen {

/// splitmix64 step: advances `state` and returns the next output.
[[nodiscard]] constexpr std::uint64_t splitmix64(std::uint64_t& state) {
  std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

/// 64-bit FNV-1a hash of a name (http://www.isthe.com/chongo/tech/comp/fnv/).
[[nodiscard]] constexpr std::uint64_t fnv1a64(std::string_view s) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  for (char c : s) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ULL;
  }
  return h;
}

class Rng {
 public:
  /// Four splitmix64 outputs of `seed` fill the state (never all zero: splitmix64 is a bijection
  /// of a counter, so four consecutive outputs cannot all be 0).
  explicit constexpr Rng(std::uint64_t seed) {
    std::uint64_t sm = seed;
    for (auto& w : s_) w = splitmix64(sm);
  }

  /// The stream of one family: independent of every other family's stream and of counts.
  [[nodiscard]] static constexpr Rng for_family(std::uint64_t seed, std::string_view family) {
    std::uint64_t sm = seed;
    const std::uint64_t a = splitmix64(sm);
    return Rng(a ^ fnv1a64(family));
  }

  /// xoshiro256** next().
  constexpr std::uint64_t next() {
    const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
    const std::uint64_t t = s_[1] << 17;
    s_[2] ^= s_[0];
    s_[3] ^= s_[1];
    s_[1] ^= s_[2];
    s_[0] ^= s_[3];
    s_[2] ^= t;
    s_[3] = rotl(s_[3], 45);
    return result;
  }

  /// Uniform in [0, n), n > 0 (Lemire's method; exact, no modulo bias).
  std::uint64_t below(std::uint64_t n) {
    __extension__ using u128 = unsigned __int128;
    u128 m = static_cast<u128>(next()) * n;
    auto low = static_cast<std::uint64_t>(m);
    if (low < n) {
      const std::uint64_t threshold = (0 - n) % n;
      while (low < threshold) {
        m = static_cast<u128>(next()) * n;
        low = static_cast<std::uint64_t>(m);
      }
    }
    return static_cast<std::uint64_t>(m >> 64);
  }

  /// Uniform integer in [lo, hi] (inclusive; hi - lo < 2^63).
  std::int64_t range(std::int64_t lo, std::int64_t hi) {
    return lo + static_cast<std::int64_t>(below(static_cast<std::uint64_t>(hi - lo) + 1));
  }
  int irange(int lo, int hi) { return static_cast<int>(range(lo, hi)); }
  /// range(lo, hi) with a random sign (the magnitude is drawn first).
  std::int64_t signed_range(std::int64_t lo, std::int64_t hi) {
    const std::int64_t v = range(lo, hi);
    return coin() ? v : -v;
  }

  /// Uniform in [-2^bits, 2^bits] (bits in 0..61).
  std::int64_t sym_int(int bits) {
    const std::int64_t m = std::int64_t{1} << bits;
    return range(-m, m);
  }

  /// True with probability num/den.
  bool chance(std::uint64_t num, std::uint64_t den) { return below(den) < num; }
  bool coin() { return (next() >> 63) != 0; }
  int sign() { return coin() ? 1 : -1; }

  /// Uniform in [0, 1): the top 53 bits times 2^-53 (exact).
  double unit() { return std::ldexp(static_cast<double>(next() >> 11), -53); }
  /// Uniform in [-1, 1): 54 random bits, offset, times 2^-53 (exact).
  double sym() {
    const auto k = static_cast<std::int64_t>(next() >> 10) - (std::int64_t{1} << 53);
    return std::ldexp(static_cast<double>(k), -53);
  }
  /// a + (b - a) * unit(): two IEEE roundings, the same everywhere (no FMA: see families.cpp).
  double uniform(double a, double b) {
    const double w = b - a;
    const double x = w * unit();
    return a + x;
  }
  /// 2^k with k uniform in [lo, hi].
  double pow2(int lo, int hi) { return std::ldexp(1.0, irange(lo, hi)); }

 private:
  static constexpr std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
  std::array<std::uint64_t, 4> s_{};
};

}  // namespace rayproof::gen
