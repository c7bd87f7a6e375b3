// glTF 2.0 through tinygltf (src/mesh/gltf.cpp): a tetrahedron written here as .gltf with an
// embedded (data: URI) and an external buffer and as .glb, read back exactly, node transforms
// applied; non-triangle primitives, bad accessors and malformed JSON refused with the file and the
// object named; every truncation of the .glb refused without a crash; the commands name the reader.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.h"
#include "mesh/mesh.h"

using namespace rayproof;
using rayproof::testing::run_rayproof;
using rayproof::testing::scratch_dir;
using rayproof::testing::write_file;

namespace {

const float kVerts[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
const std::uint16_t kIndex[12] = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};

/// The buffer: 48 bytes of positions, then 24 of uint16 indices.
std::string buffer() {
  std::string b(72, '\0');
  std::memcpy(b.data(), kVerts, 48);
  std::memcpy(b.data() + 48, kIndex, 24);
  return b;
}

std::string base64(const std::string& in) {
  static const char* k = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 2 < in.size(); i += 3) {
    const unsigned v = unsigned(std::uint8_t(in[i])) << 16 | unsigned(std::uint8_t(in[i + 1])) << 8 | std::uint8_t(in[i + 2]);
    out += k[v >> 18], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += k[v & 63];
  }
  if (i + 1 == in.size()) {
    const unsigned v = unsigned(std::uint8_t(in[i])) << 16;
    out += k[v >> 18], out += k[(v >> 12) & 63], out += "==";
  } else if (i + 2 == in.size()) {
    const unsigned v = unsigned(std::uint8_t(in[i])) << 16 | unsigned(std::uint8_t(in[i + 1])) << 8;
    out += k[v >> 18], out += k[(v >> 12) & 63], out += k[(v >> 6) & 63], out += '=';
  }
  return out;
}

/// The JSON of the tetrahedron; `uri` empty for a .glb's own buffer. `mode`, `node` and the index
/// accessor's count let a test break one thing at a time.
std::string json(const std::string& uri, int mode = 4, const std::string& node = R"({"mesh": 0})",
                 int index_count = 12) {
  return std::string(R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [)") + node +
         R"(], "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": )" + std::to_string(mode) +
         R"(}]}], "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",)"
         R"( "min": [0, 0, 0], "max": [1, 1, 1]}, {"bufferView": 1, "componentType": 5123, "count": )" +
         std::to_string(index_count) +
         R"(, "type": "SCALAR"}], "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48},)"
         R"( {"buffer": 0, "byteOffset": 48, "byteLength": 24}], "buffers": [{"byteLength": 72)" +
         (uri.empty() ? std::string() : R"(, "uri": ")" + uri + "\"") + "}]}";
}

std::string glb(std::string js) {
  while (js.size() % 4) js += ' ';
  const std::string bin = buffer();  // 72 bytes, already a multiple of 4
  std::string out = "glTF";
  auto u32 = [&](std::uint32_t v) {
    for (int k = 0; k < 4; ++k) out += char((v >> (8 * k)) & 255);
  };
  u32(2), u32(std::uint32_t(12 + 8 + js.size() + 8 + bin.size()));
  u32(std::uint32_t(js.size())), out += "JSON", out += js;
  u32(std::uint32_t(bin.size())), out += std::string("BIN\0", 4), out += bin;
  return out;
}

std::string error_of(const std::string& path) {
  try {
    (void)mesh::read_mesh(path);
  } catch (const mesh::MeshError& e) {
    return e.what();
  }
  return "(no error)";
}

void expect_tetrahedron(const mesh::Mesh& m, double dx = 0) {
  ASSERT_EQ(m.vertices.size(), 4u);
  ASSERT_EQ(m.triangles.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(m.vertices[std::size_t(i)].x, kVerts[i][0] + dx) << i;
    EXPECT_EQ(m.vertices[std::size_t(i)].y, kVerts[i][1]) << i;
    EXPECT_EQ(m.vertices[std::size_t(i)].z, kVerts[i][2]) << i;
  }
  for (int t = 0; t < 4; ++t)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(m.triangles[std::size_t(t)][std::size_t(c)], kIndex[t * 3 + c]);
}

}  // namespace

TEST(Gltf, EmbeddedExternalAndBinaryBuffersGiveTheSameMesh) {
  if (mesh::reader_name(mesh::MeshFormat::gltf).rfind("tinygltf", 0) != 0)
    GTEST_SKIP() << "built without tinygltf (Debian: libtinygltf-dev): " << mesh::reader_name(mesh::MeshFormat::gltf);
  const auto embedded = write_file("tet_embedded.gltf", json("data:application/octet-stream;base64," + base64(buffer())));
  expect_tetrahedron(mesh::read_mesh(embedded.string()));
  write_file("tet.bin", buffer());
  const auto external = write_file("tet_external.gltf", json("tet.bin"));
  expect_tetrahedron(mesh::read_mesh(external.string()));
  const auto binary = write_file("tet.glb", glb(json("")));
  expect_tetrahedron(mesh::read_mesh(binary.string()));
  // A node's translation moves the vertices into world space.
  const auto moved = write_file("tet_moved.gltf", json("tet.bin", 4, R"({"mesh": 0, "translation": [2, 0, 0]})"));
  expect_tetrahedron(mesh::read_mesh(moved.string()), 2);
  EXPECT_EQ(mesh::reader_name(mesh::format_of("x.GLB")).rfind("tinygltf ", 0), 0u);
}

TEST(Gltf, BadFilesAreRefusedWithTheFileAndTheObjectNamed) {
  if (mesh::reader_name(mesh::MeshFormat::gltf).rfind("tinygltf", 0) != 0) GTEST_SKIP() << "built without tinygltf";
  write_file("tet.bin", buffer());
  const auto lines = write_file("tet_lines.gltf", json("tet.bin", 1));
  EXPECT_EQ(error_of(lines.string()),
            lines.string() + ": meshes[0].primitives[0]: mode 1 (lines) is not a triangle list; rayproof reads triangle "
                             "primitives (mode 4) only");
  const auto strip = write_file("tet_strip.gltf", json("tet.bin", 5));
  EXPECT_NE(error_of(strip.string()).find("mode 5 (triangle strip) is not a triangle list"), std::string::npos);
  const auto short_indices = write_file("tet_count.gltf", json("tet.bin", 4, R"({"mesh": 0})", 14));
  EXPECT_EQ(error_of(short_indices.string()), short_indices.string() + ": accessors[1]: 14 indices: not a multiple of 3");
  const auto long_indices = write_file("tet_long.gltf", json("tet.bin", 4, R"({"mesh": 0})", 18));
  EXPECT_EQ(error_of(long_indices.string()),
            long_indices.string() + ": accessors[1]: 18 elements need 36 bytes of bufferViews[1], which has 24");
  const auto cycle = write_file("tet_cycle.gltf", json("tet.bin", 4, R"({"mesh": 0, "children": [0]})"));
  EXPECT_EQ(error_of(cycle.string()), cycle.string() + ": nodes[0]: reached twice (a cycle, or a node with two parents)");
  const auto missing = write_file("tet_missing.gltf", json("no_such.bin"));
  const std::string m = error_of(missing.string());
  EXPECT_EQ(m.rfind(missing.string() + ": glTF (tinygltf): ", 0), 0u) << m;
  const auto broken = write_file("broken.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"meshes\": [");
  const std::string b = error_of(broken.string());
  EXPECT_EQ(b.rfind(broken.string() + ": glTF (tinygltf): ", 0), 0u) << b;
  EXPECT_EQ(error_of((scratch_dir() / "absent.glb").string()), (scratch_dir() / "absent.glb").string() + ": no such file");
}

TEST(Gltf, EveryTruncationOfAGlbIsAnErrorNotACrash) {
  if (mesh::reader_name(mesh::MeshFormat::gltf).rfind("tinygltf", 0) != 0) GTEST_SKIP() << "built without tinygltf";
  const std::string whole = glb(json(""));
  std::size_t errors = 0;
  for (std::size_t n = 0; n < whole.size(); ++n) {
    std::istringstream in(whole.substr(0, n), std::ios::binary);
    try {
      (void)mesh::read_mesh(in, mesh::MeshFormat::gltf, "cut.glb");
      ADD_FAILURE() << "a .glb cut to " << n << " of " << whole.size() << " bytes was read";
    } catch (const mesh::MeshError& e) {
      ++errors;
      EXPECT_EQ(std::string(e.what()).rfind("cut.glb: ", 0), 0u) << e.what();
    }
  }
  EXPECT_EQ(errors, whole.size());
  // Bytes flipped one at a time: read or refused, never a crash, never an index out of range.
  for (std::size_t at = 0; at < whole.size(); at += 3) {
    std::string bad = whole;
    bad[at] = char(bad[at] ^ 0x5A);
    std::istringstream in(bad, std::ios::binary);
    try {
      const mesh::Mesh m = mesh::read_mesh(in, mesh::MeshFormat::gltf, "flip.glb");
      for (const auto& t : m.triangles)
        for (const auto i : t) ASSERT_LT(i, m.vertices.size()) << at;
    } catch (const mesh::MeshError&) {
    }
  }
}

TEST(Gltf, CommandsReadGltfAndNameTheReader) {
  if (mesh::reader_name(mesh::MeshFormat::gltf).rfind("tinygltf", 0) != 0) GTEST_SKIP() << "built without tinygltf";
  const auto file = write_file("tet_cli.glb", glb(json("")));
  // From outside along -x through the face x + y + z = 1 (at x = 0.6), and one ray that passes by.
  const auto rays = write_file("tet_rays.txt", "2 0.2 0.2 -1 0 0\n0.2 0.2 5 0 0 1\n");
  const auto r = run_rayproof("cast -v " + file.string() + " " + rays.string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.err.find("4 triangles"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("(read by tinygltf "), std::string::npos) << r.err;
  std::istringstream out(r.out);
  std::string first, second;
  std::getline(out, first), std::getline(out, second);
  ASSERT_EQ(first.rfind("interior ", 0), 0u) << r.out;
  EXPECT_NEAR(std::stod(first.substr(9)), 1.4, 1e-12) << r.out;
  EXPECT_EQ(second.rfind("miss", 0), 0u) << r.out;
  const auto off = write_file("tet_cli.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
  const auto o = run_rayproof("cast -v " + off.string() + " " + rays.string());
  ASSERT_EQ(o.status, 0) << o.err;
  EXPECT_NE(o.err.find("(read by rayproof's OFF reader)"), std::string::npos) << o.err;
  EXPECT_EQ(o.out, r.out);  // the same mesh, the same answers
  write_file("tet.bin", buffer());
  const auto lines = write_file("tet_cli_lines.gltf", json("tet.bin", 1));
  const auto bad = run_rayproof("cast " + lines.string() + " " + rays.string());
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("mode 1 (lines) is not a triangle list"), std::string::npos) << bad.err;
}
