// Mesh readers: every format on small files, fan triangulation, and located errors on bad input.
#include <gtest/gtest.h>

#include <bit>
#include <cstring>
#include <sstream>

#include "mesh/mesh.h"

using namespace rayproof::mesh;

namespace {
Mesh read(const std::string& text, MeshFormat f) {
  std::istringstream in(text, std::ios::binary);
  return read_mesh(in, f, "m");
}
std::string error_of(const std::string& text, MeshFormat f) {
  try {
    (void)read(text, f);
  } catch (const MeshError& e) {
    return e.what();
  }
  return "(no error)";
}
template <class T>
void put(std::string& s, T v, bool big) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + sizeof(T));
  s.append(b, sizeof(T));
}
const char* kSquareOff = "OFF\n# a unit square as one quad\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n";
}  // namespace

TEST(Off, QuadIsFanTriangulated) {
  const Mesh m = read(kSquareOff, MeshFormat::off);
  ASSERT_EQ(m.vertices.size(), 4u);
  ASSERT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(m.triangles[0], (std::array<std::uint32_t, 3>{0, 1, 2}));
  EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(m.vertices[2].y, 1.0);
}

TEST(Off, CountsOnTheKeywordLineAndColoursAreAccepted) {
  const Mesh m = read("OFF 3 1 0\n0 0 0 1 0 0\n0 1 0\n3 0 1 2 255 0 0\n", MeshFormat::off);
  EXPECT_EQ(m.triangles.size(), 1u);
}

TEST(Off, ErrorsNameTheLine) {
  EXPECT_EQ(error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n", MeshFormat::off),
            "m:6: vertex index 7 out of range (3 vertices)");
  EXPECT_EQ(error_of("OFF\n3 1 0\n0 0 0\n1 zero 0\n", MeshFormat::off), "m:4: expected vertex y, got 'zero'");
  EXPECT_EQ(error_of("OFF\n3 1 0\n0 0 0\n1 0 0\n", MeshFormat::off), "m:4: unexpected end of file, expected vertex x");
  EXPECT_EQ(error_of("COFF\n", MeshFormat::off), "m:1: expected 'OFF', got 'COFF' (only plain OFF is supported)");
  EXPECT_EQ(error_of("", MeshFormat::off), "m:0: empty file, expected 'OFF'");
  // An absurd count fails at the end of the data, not at an allocation.
  EXPECT_EQ(error_of("OFF\n4000000000 4000000000 0\n0 0 0\n", MeshFormat::off),
            "m:3: unexpected end of file, expected vertex x");
  EXPECT_EQ(error_of("OFF\n99999999999 1 0\n", MeshFormat::off), "m:2: vertex count 99999999999 exceeds 2^32 - 1");
}

TEST(Obj, SlashesAndNegativeIndices) {
  const Mesh m = read("# square\nv 0 0 0\nv 1 0 0\nv 1 1 0\nvt 0 0\nvn 0 0 1\nv 0 1 0\ng sq\n"
                      "f 1/1/1 2//1 3/1 4\nf -4 -3 -1\n",
                      MeshFormat::obj);
  ASSERT_EQ(m.triangles.size(), 3u);
  EXPECT_EQ(m.triangles[1], (std::array<std::uint32_t, 3>{0, 2, 3}));
  EXPECT_EQ(m.triangles[2], (std::array<std::uint32_t, 3>{0, 1, 3}));
}

TEST(Obj, ErrorsNameTheLine) {
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nf 1 2 3\n", MeshFormat::obj), "m:3: face vertex index 3 out of range (2 vertices so far)");
  EXPECT_EQ(error_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 0 2\n", MeshFormat::obj),
            "m:4: bad face vertex '0' (expected a non-zero integer index)");
  EXPECT_EQ(error_of("v 0 0\n", MeshFormat::obj), "m:1: 'v' needs 3 coordinates (and an optional w)");
  EXPECT_EQ(error_of("v 0 0 nan\n", MeshFormat::obj), "m:1: vertex coordinate is not finite: 'nan'");
  EXPECT_EQ(error_of("v 0 0 0\nf 1 1\n", MeshFormat::obj), "m:2: 'f' needs at least 3 vertices");
}

namespace {
std::string ply_header(const char* format, std::uint64_t nv, std::uint64_t nf) {
  return std::string("ply\nformat ") + format + " 1.0\ncomment test\nelement vertex " + std::to_string(nv) +
         "\nproperty float x\nproperty float y\nproperty double z\nproperty uchar red\nelement face " +
         std::to_string(nf) + "\nproperty list uchar int vertex_indices\nend_header\n";
}
std::string ply_binary(bool big) {
  std::string s = ply_header(big ? "binary_big_endian" : "binary_little_endian", 4, 1);
  const float xy[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (auto& p : xy) put(s, p[0], big), put(s, p[1], big), put(s, 2.5, big), put(s, std::uint8_t(7), big);
  put(s, std::uint8_t(4), big);
  for (int i : {0, 1, 2, 3}) put(s, std::int32_t(i), big);
  return s;
}
}  // namespace

TEST(Ply, AsciiAndBothBinaryByteOrdersAgree) {
  const Mesh a = read(ply_header("ascii", 4, 1) + "0 0 2.5 7\n1 0 2.5 7\n1 1 2.5 7\n0 1 2.5 7\n4 0 1 2 3\n", MeshFormat::ply);
  for (bool big : {false, true}) {
    const Mesh b = read(ply_binary(big), MeshFormat::ply);
    ASSERT_EQ(b.vertices.size(), 4u) << big;
    ASSERT_EQ(b.triangles, a.triangles) << big;
    for (int i = 0; i < 4; ++i) EXPECT_EQ(b.vertices[i], a.vertices[i]) << big << i;
  }
  EXPECT_EQ(a.triangles.size(), 2u);
  EXPECT_EQ(a.vertices[3].z, 2.5);
}

TEST(Ply, ErrorsNameTheLineOrByte) {
  std::string trunc = ply_binary(false);
  trunc.resize(trunc.size() - 3);
  const std::size_t header = ply_header("binary_little_endian", 4, 1).size();
  // 4 vertices of 17 bytes, then the list count and 4 ints: 4 ints need 16 bytes, 13 remain.
  EXPECT_EQ(error_of(trunc, MeshFormat::ply),
            "m: byte " + std::to_string(header + 4 * 17 + 1 + 12) + ": unexpected end of file");
  EXPECT_EQ(error_of(ply_header("binary_little_endian", 4000000000ull, 1) + "abc", MeshFormat::ply),
            "m:4: element 'vertex' claims 4000000000 items, more than the 3 bytes after the header can hold");
  EXPECT_EQ(error_of(ply_header("ascii", 3, 1) + "0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 3\n", MeshFormat::ply),
            "m:15: vertex index 3 out of range (3 vertices)");
  EXPECT_EQ(error_of("ply\nformat ascii 1.0\nelement vertex 1\n", MeshFormat::ply),
            "m:3: unexpected end of file in the header (no 'end_header')");
  EXPECT_EQ(error_of("plx\n", MeshFormat::ply), "m:1: not a PLY file (first line must be 'ply')");
  // An ASCII value outside its declared integer type is refused where it is read (a fuzzer's
  // list count of 1.2e90 for a uchar used to reach a cast to an integer: undefined behaviour).
  EXPECT_EQ(error_of(ply_header("ascii", 3, 1) + "0 0 0 0\n1 0 0 0\n0 1 0 0\n5e20 0 1 2\n", MeshFormat::ply),
            "m:15: list count 5e+20 is outside the range of uchar");
  EXPECT_EQ(error_of(ply_header("ascii", 3, 1) + "0 0 0 256\n1 0 0 0\n0 1 0 0\n3 0 1 2\n", MeshFormat::ply),
            "m:12: property value 256 is outside the range of uchar");
  EXPECT_EQ(error_of(ply_header("ascii", 3, 1) + "0 0 0 0\n1 0 0 0\n0 1 0 0\n3 0 1 -2147483649\n", MeshFormat::ply),
            "m:15: list value -2147483649 is outside the range of int");
}

TEST(Stl, AsciiWeldsSharedVertices) {
  const Mesh m = read("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\nendloop\n"
                      "endfacet\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 1 0\n  vertex 0 1 0\n"
                      " endloop\nendfacet\nendsolid t\n",
                      MeshFormat::stl);
  EXPECT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 2u);
  EXPECT_EQ(error_of("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n", MeshFormat::stl),
            "m:4: 'vertex' needs 3 coordinates");
  EXPECT_EQ(error_of("solid t\nfacet normal 0 0 1\n", MeshFormat::stl), "m:2: unexpected end of file, expected 'endsolid'");
}

TEST(Stl, BinaryRoundTripAndAbsurdCount) {
  const Mesh sq = read(kSquareOff, MeshFormat::off);
  std::ostringstream out(std::ios::binary);
  write_stl_binary(out, sq);
  ASSERT_EQ(out.str().size(), 84u + 2 * 50);
  const Mesh back = read(out.str(), MeshFormat::stl);
  EXPECT_EQ(back.vertices.size(), 4u);
  EXPECT_EQ(back.triangles.size(), 2u);
  // 100 bytes claiming 4 billion triangles: an error at the count, before any allocation.
  std::string bad(80, 'x');
  put(bad, std::uint32_t(4000000000u), false);
  bad.resize(100, '\0');
  EXPECT_EQ(error_of(bad, MeshFormat::stl),
            "m: byte 80: binary STL header claims 4000000000 triangles (200000000084 bytes) but the file has 100 bytes");
  EXPECT_EQ(error_of(std::string(50, 'x'), MeshFormat::stl), "m: byte 50: truncated binary STL header (84 bytes needed)");
}

TEST(Mesh, OffRoundTripIsExact) {
  Mesh m;
  m.vertices = {{0.1, -1e-300, 3}, {1.0 / 3, 2, 0}, {0, 0x1.fffffffffffffp-1, 5}};
  m.triangles = {{0, 1, 2}};
  std::ostringstream out;
  write_off(out, m);
  const Mesh back = read(out.str(), MeshFormat::off);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(back.vertices[i], m.vertices[i]);
}

TEST(Mesh, FilesByExtension) {
  EXPECT_EQ(format_of("a/B.PLY"), MeshFormat::ply);
  EXPECT_THROW((void)format_of("x.txt"), MeshError);
  try {
    (void)read_mesh("/nonexistent/x.off");
    FAIL();
  } catch (const MeshError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/x.off: no such file");
  }
}
