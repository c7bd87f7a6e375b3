#pragma once
// The judges' line protocol (docs/check.md, "Inside/outside" and "Distances") for the C++ engine
// examples: read the mesh once, then answer batches of points until `end`. Only the standard
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

/// Three doubles on a line (strtod reads inf, -inf and nan too, and shortest decimals exactly).
inline std::array<double, 3> three_doubles() {
  const std::string line = next_line();
  std::array<double, 3> p{};
  const char* s = line.c_str();
  for (double& x : p) {
    char* end = nullptr;
    x = std::strtod(s, &end);
    if (end == s) fail("not three numbers: " + line);
    s = end;
  }
  return p;
}

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

/// Answers every batch with `answer(points)` (one string per point, without the newline) until
/// `end`.
template <class Answer>
void serve_batches(Answer&& answer) {
  for (;;) {
    std::istringstream in(next_line());
    std::string word;
    std::size_t n = 0;
    in >> word;
    if (word == "end") return;
    if (word != "points" || !(in >> n)) fail("expected 'points N' or 'end'");
    std::vector<std::array<double, 3>> points(n);
    for (auto& p : points) p = three_doubles();
    std::string out;
    for (const std::string& a : answer(points)) out += a + "\n";
    std::fwrite(out.data(), 1, out.size(), stdout);
    std::fflush(stdout);
  }
}

}  // namespace engine_example
