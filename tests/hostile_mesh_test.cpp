// Hostile input for the scene commands (cast, render, bench): empty, truncated and garbage mesh
// and scene files, a line of a million characters, counts claiming billions of elements, NaN and
// infinities, directories and unreadable paths, bad ray lines next to good ones. Each gets a
// one-line error naming the input and the place, a non-zero exit, no crash, no hang (every run is
// under `timeout`) and bounded memory (every run is under `ulimit -v`).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <random>

#include "cli_support.h"

using rayproof::testing::scratch_dir;
using rayproof::testing::run_rayproof;
using rayproof::testing::write_file;
using rayproof::testing::RunResult;

namespace {

/// Like run_rayproof, with 2 GiB of address space and 60 s at most (exit 124 on timeout).
RunResult run_limited(const std::string& args) {
  // AddressSanitizer reserves terabytes of shadow address space, so the address-space limit that
  // bounds memory in the normal build would stop a sanitized binary before main: skip it there
  // (ASan itself reports any allocation it cannot make).
#if defined(__SANITIZE_ADDRESS__)
  const std::string limit = "";
#else
  const std::string limit = "ulimit -v 2097152; ";
#endif
  return run_rayproof(args, "", limit + "timeout 60 ");
}

std::string garbage(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::string s(n, '\0');
  for (auto& c : s) c = static_cast<char>(rng() & 0xff);
  return s;
}

void put32(std::string& s, std::uint32_t v) {
  for (int k = 0; k < 4; ++k) s.push_back(static_cast<char>((v >> (8 * k)) & 0xff));
}
void putf(std::string& s, float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, 4);
  put32(s, u);
}
/// Binary STL: `claim` in the header, `tris` triangles present (all corners at `x`).
std::string stl_binary(std::uint32_t claim, int tris, float x = 0) {
  std::string s(80, ' ');
  put32(s, claim);
  for (int t = 0; t < tris; ++t) {
    for (int k = 0; k < 3; ++k) putf(s, 0);
    const float v[9] = {x, 0, 0, 1, 0, 0, 0, 1, 0};
    for (float f : v) putf(s, f);
    s += std::string(2, '\0');
  }
  return s;
}
std::string ply_header(const char* format, const char* count) {
  return std::string("ply\nformat ") + format + " 1.0\nelement vertex " + count +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n";
}

const std::string kTetraOff = "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

struct Hostile {
  std::string name, path, place;  ///< place: text the message must hold besides the path
};

/// Scene inputs (mesh files and scene JSON) that every scene command must refuse.
std::vector<Hostile> hostile_scenes() {
  const auto dir = scratch_dir();
  std::filesystem::create_directories(dir / "adir.off");
  write_file("regular.txt", "x");
  std::vector<Hostile> h;
  auto add = [&](const std::string& name, const std::string& file, const std::string& text, const std::string& place) {
    h.push_back({name, write_file(file, text).string(), place});
  };
  add("empty OFF", "empty.off", "", ": empty file");
  add("empty OBJ", "empty.obj", "", ": no triangles");
  add("empty PLY", "empty.ply", "", ": not a PLY file");
  add("empty STL", "empty.stl", "", ": byte 0: truncated binary STL header");
  add("empty JSON", "empty.json", "", ": byte ");
  add("truncated OFF", "trunc.off", "OFF\n8 12 0\n0 0 0\n1 0 0\n", ":4: unexpected end of file");
  add("truncated binary STL", "trunc.stl", stl_binary(4, 4).substr(0, 84 + 150), ": byte 80: binary STL header claims 4");
  add("truncated binary PLY", "trunc.ply", ply_header("binary_little_endian", "4") + std::string(20, '\0'), ":3: element 'vertex' claims 4");
  add("truncated ASCII PLY", "trunc_ascii.ply", ply_header("ascii", "3") + "0 0 0\n1 0", ":11: unexpected end of file");
  add("truncated JSON", "trunc.json", "{\"spheres\": [{\"center\": [0, 0", ": byte ");
  add("garbage OFF", "garbage.off", garbage(4096, 1), ":1: expected 'OFF'");
  add("garbage OBJ", "garbage.obj", garbage(4096, 2), ":");
  add("garbage PLY", "garbage.ply", garbage(4096, 3), ":1: not a PLY file");
  add("garbage STL", "garbage.stl", garbage(4096, 4), ": byte 80: ");
  add("garbage JSON", "garbage.json", garbage(4096, 5), ": byte ");
  add("million-char line OFF", "long.off", "OFF\n" + std::string(1000000, '7') + " 1 0\n", ":2: expected vertex count");
  add("million-char line OBJ", "long.obj", "v " + std::string(1000000, '1') + " 0 0\n", ":1: bad vertex coordinate");
  add("million-char line PLY", "long.ply", "ply\n" + std::string(1000000, 'x') + "\n", ":2: unexpected");
  add("2-million-char line OFF", "longer.off", "OFF\n" + std::string(2000000, '7') + "\n", ":2: line longer than");
  add("STL claiming 4e9 triangles", "huge.stl", stl_binary(4000000000u, 1), ": byte 80: binary STL header claims 4000000000");
  add("OFF claiming 2e9 vertices", "huge.off", "OFF\n2000000000 1 0\n0 0 0\n", ":3: unexpected end of file");
  add("OFF claiming 2^40 vertices", "huger.off", "OFF\n1099511627776 1 0\n", ":2: vertex count 1099511627776 exceeds");
  add("PLY claiming 3e9 vertices (binary)", "huge.ply", ply_header("binary_little_endian", "3000000000") + std::string(12, '\0'),
      ":3: element 'vertex' claims 3000000000");
  add("PLY claiming 3e9 vertices (ASCII)", "huge_ascii.ply", ply_header("ascii", "3000000000") + "0 0 0\n", ":10: unexpected end of file");
  add("NaN in OFF", "nan.off", "OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", ":4: vertex y is not finite");
  add("inf in OBJ", "inf.obj", "v 0 0 0\nv 1 0 0\nv 0 1 -inf\nf 1 2 3\n", ":3: vertex coordinate is not finite");
  add("1e999 in ASCII STL", "inf_ascii.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1e999 0 0\n", ":5: bad vertex coordinate");
  add("NaN in binary STL", "nan.stl", stl_binary(1, 1, std::nanf("")), ": byte 96: coordinate is not finite");
  add("NaN in ASCII PLY", "nan.ply", ply_header("ascii", "3") + "0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n", ":11: property value is not finite");
  add("inf in JSON", "inf.json", "{\"spheres\": [{\"center\": [0, 0, 0], \"radius\": 1e999}]}", ": byte 46: number out of range");
  add("JSON camera type not a string", "type.json", "{\"camera\": {\"type\": 3, \"eye\": [0, 0, 5], \"target\": [0, 0, 0]}}",
      "camera.type: expected a string");
  add("JSON mesh missing", "mesh.json", "{\"meshes\": [{\"file\": \"missing.off\"}]}", "meshes[0].file: ");
  h.push_back({"directory as a mesh", (dir / "adir.off").string(), ": is a directory"});
  h.push_back({"directory as a scene", dir.string(), ": is a directory"});
  h.push_back({"path through a file (mesh)", (dir / "regular.txt" / "x.off").string(), ": no such file"});
  h.push_back({"path through a file (scene)", (dir / "regular.txt" / "x").string(), ": no such file"});
  return h;
}

void expect_refused(RunResult r, const Hostile& h, const std::string& cmd) {
  const std::string what = cmd + " / " + h.name;
  // cast answers a bad ray line in place and ends with a count: the message itself is one line.
  const std::string summary = "rayproof cast: 1 line(s) could not be read\n";
  if (r.err.size() > summary.size() && r.err.compare(r.err.size() - summary.size(), summary.size(), summary) == 0)
    r.err.resize(r.err.size() - summary.size());
  EXPECT_NE(r.status, 0) << what;
  EXPECT_LT(r.status, 124) << what << ": crashed or hung (status " << r.status << ")";
  EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << what << ": not one line: " << r.err.substr(0, 300);
  EXPECT_LT(r.err.size(), 400u) << what << ": " << r.err.substr(0, 300);
  EXPECT_NE(r.err.find("rayproof " + cmd + ": " + h.path), std::string::npos) << what << ": " << r.err.substr(0, 300);
  EXPECT_NE(r.err.find(h.place), std::string::npos) << what << ": " << r.err.substr(0, 300);
}

}  // namespace

TEST(HostileMesh, CastRefusesEveryBadScene) {
  const auto rays = write_file("ok.rays", "0 0 5 0 0 -1\n");
  for (const auto& h : hostile_scenes()) expect_refused(run_limited("cast " + h.path + " " + rays.string()), h, "cast");
}

TEST(HostileMesh, RenderRefusesEveryBadScene) {
  const auto png = (scratch_dir() / "never.png").string();
  for (const auto& h : hostile_scenes()) {
    expect_refused(run_limited("render " + h.path + " --out " + png), h, "render");
    EXPECT_FALSE(std::filesystem::exists(png)) << h.name;
  }
}

TEST(HostileMesh, BenchRefusesEveryBadScene) {
  for (const auto& h : hostile_scenes())
    expect_refused(run_limited("bench " + h.path + " --rays 100 --slow-rays 10 --leak-rays 10 --methods float"), h, "bench");
}

TEST(HostileMesh, CastRefusesBadRayFiles) {
  const auto scene = write_file("tetra.off", kTetraOff).string();
  const auto dir = scratch_dir();
  std::filesystem::create_directories(dir / "adir.rays");
  std::vector<Hostile> h;
  auto add = [&](const std::string& name, const std::string& file, const std::string& text, const std::string& place) {
    h.push_back({name, write_file(file, text).string(), place});
  };
  add("empty", "empty.rays", "", ": no rays");
  add("comments only", "comments.rays", "# nothing\n\n", ": no rays");
  add("truncated", "trunc.rays", "0 0 5 0 0", ":1: expected 6 numbers (ox oy oz dx dy dz), got 5 fields");
  add("truncated number", "trunc2.rays", "0 0 5 0 0 -1e", ":1: '-1e' is not a number");
  add("million-char line", "long.rays", "0 0 5 0 0 " + std::string(1000000, '9') + "x\n", ":1: '99999");
  add("2-million-char line", "longer.rays", std::string(2000000, '9') + "\n", ":1: line longer than");
  h.push_back({"directory", (dir / "adir.rays").string(), ": is a directory"});
  h.push_back({"missing", (dir / "missing.rays").string(), ": no such file"});
  h.push_back({"path through a file", (dir / "tetra.off" / "x").string(), ": no such file"});
  for (const auto& x : h) {
    const auto r = run_limited("cast " + scene + " " + x.path);
    expect_refused(r, x, "cast");
  }
  // Garbage: every line that is not a ray is named, in order; nothing crashes.
  const auto g = write_file("garbage.rays", garbage(4096, 9)).string();
  const auto r = run_limited("cast " + scene + " " + g);
  EXPECT_NE(r.status, 0);
  EXPECT_LT(r.status, 124);
  EXPECT_NE(r.err.find("rayproof cast: " + g + ":1: "), std::string::npos) << r.err.substr(0, 300);
  EXPECT_LT(r.err.size(), 64u * 1024u);  // messages quote at most 40 bytes of a token
}

TEST(HostileMesh, GoodRaysNextToBadLinesAreAnswered) {
  const auto scene = write_file("tetra.off", kTetraOff).string();
  const auto rays = write_file("mixed.rays",
                               "# good, bad, NaN, infinite, zero direction, good\n"
                               "0.1 0.1 5 0 0 -1\n"
                               "0.1 0.1 5 0 0 -1 7\n"
                               "nan 0.1 5 0 0 -1\n"
                               "0.1 0.1 5 0 0 -inf\n"
                               "0.1 0.1 5 0 0 0\n"
                               "0.1 0.1 -5 0 0 1\n")
                        .string();
  const auto r = run_limited("cast " + scene + " " + rays);
  EXPECT_EQ(r.status, 1);
  // NaN and infinite components and d = 0 make a ray `invalid` (docs/cases.md), not an input error.
  EXPECT_EQ(r.out, "interior 4.2 3\nerror - -\ninvalid - -\ninvalid - -\ninvalid - -\ninterior 5.0 0\n");
  EXPECT_NE(r.err.find(rays + ":3: expected 6 numbers"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("1 line(s) could not be read"), std::string::npos) << r.err;
}
