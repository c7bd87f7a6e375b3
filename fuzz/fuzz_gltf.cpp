// libFuzzer harness: arbitrary bytes as a .glb/.gltf file (tinygltf, then src/mesh/gltf.cpp's checks).
// The reader must never crash and must either return a mesh whose every index is in range and every
// coordinate finite, or throw a MeshError that starts with the file name (glTF errors name an object,
// not a line: "fuzz.glb: accessors[1]: ...", "fuzz.glb: glTF (tinygltf): ...").
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "mesh/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace rayproof;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size), std::ios::in | std::ios::binary);
  try {
    const mesh::Mesh m = mesh::read_mesh(in, mesh::MeshFormat::gltf, "fuzz.glb");
    for (const auto& t : m.triangles)
      for (const std::uint32_t i : t)
        if (i >= m.vertices.size()) std::fprintf(stderr, "index %u out of range\n", i), std::abort();
    for (const auto& v : m.vertices)
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        std::fprintf(stderr, "non-finite vertex accepted\n"), std::abort();
  } catch (const mesh::MeshError& e) {
    if (std::string(e.what()).rfind("fuzz.glb: ", 0) != 0)
      std::fprintf(stderr, "error does not name the file: %s\n", e.what()), std::abort();
  }
  return 0;
}
