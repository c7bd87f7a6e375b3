#pragma once
// The judges' line protocol (docs/check.md, "Inside/outside", "Distances" and "All hits") for the
// C++ engine examples: read the mesh once, then answer batches of points or rays until `end`. Only the standard
// library and fmt: each example links its own engine (CGAL, Embree) and nothing of rayproof.
#include <fmt/core.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

namespace engine_example {

struct Mesh {
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
};

[[noreturn]] inline void fail(const std::string& why) {
  fmt::print(stderr, "{}\n", why);
  std::exit(1);
}

inline std::string next_line() {
  std::string line;
  if (!std::getline(std::cin, line)) std::exit(0);  // rayproof closed the pipe: nothing more to answer
  return line;
}

/// "WORD N": the count after the expected word.
inline std::size_t count_after(const std::string& word) {
  std::istringstream in(next_line());
  std::string w;
  std::size_t n = 0;
  if (!(in >> w >> n) || w != word) fail("expected '" + word + " N'");
  return n;
}

/// N doubles on a line (strtod reads inf, -inf and nan too, and shortest decimals exactly).
template <std::size_t N>
std::array<double, N> doubles() {
  const std::string line = next_line();
  std::array<double, N> p{};
  const char* s = line.c_str();
  for (double& x : p) {
    char* end = nullptr;
    x = std::strtod(s, &end);
    if (end == s) fail(fmt::format("not {} numbers: {}", N, line));
    s = end;
  }
  return p;
}

inline std::array<double, 3> three_doubles() { return doubles<3>(); }

/// The header line `HEAD 1` and the mesh after it.
inline Mesh read_mesh(const std::string& head) {
  if (next_line() != head + " 1") fail("not the rayproof " + head + " protocol");
  Mesh m;
  m.vertices.resize(count_after("vertices"));
  for (auto& v : m.vertices) v = three_doubles();
  m.triangles.resize(count_after("triangles"));
  for (auto& t : m.triangles) {
    std::istringstream in(next_line());
    if (!(in >> t[0] >> t[1] >> t[2])) fail("not a triangle line");
  }
  return m;
}

/// Answers every batch `WORD n` of n lines of N numbers with `answer(items)` (one string per item,
/// without the newline) until `end`.
template <std::size_t N, class Answer>
void serve(const std::string& word_expected, Answer&& answer) {
  for (;;) {
    std::istringstream in(next_line());
    std::string word;
    std::size_t n = 0;
    in >> word;
    if (word == "end") return;
    if (word != word_expected || !(in >> n)) fail("expected '" + word_expected + " N' or 'end'");
    std::vector<std::array<double, N>> items(n);
    for (auto& p : items) p = doubles<N>();
    std::string out;
    for (const std::string& a : answer(items)) out += a + "\n";
    std::fwrite(out.data(), 1, out.size(), stdout);
    std::fflush(stdout);
  }
}

/// Batches of points (`points n`, one point `x y z` a line): the containment and distance judges.
template <class Answer>
void serve_batches(Answer&& answer) {
  serve<3>("points", answer);
}

/// Batches of rays (`rays n`, one ray `ox oy oz dx dy dz` a line): the crossings judge.
template <class Answer>
void serve_ray_batches(Answer&& answer) {
  serve<6>("rays", answer);
}

}  // namespace engine_example
