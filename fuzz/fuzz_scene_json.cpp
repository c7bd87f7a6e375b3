// libFuzzer harness: arbitrary bytes as a scene JSON. The parser must never crash and never let
// anything but a SceneError escape; the error names the file and a place (a byte offset for bad
// JSON, a JSON path such as "spheres[1].radius" otherwise). A parsed scene has every triangle
// index in range. Mesh paths resolve against a directory that does not exist.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string name = "fuzz.json";
  try {
    const auto s = rayproof::scene::parse_scene_json(std::string(reinterpret_cast<const char*>(data), size),
                                                     "/nonexistent-rayproof-fuzz", name);
    for (const auto& t : s.mesh.triangles)
      for (const std::uint32_t i : t)
        if (i >= s.mesh.vertices.size()) std::abort();
  } catch (const rayproof::scene::SceneError& e) {
    const std::string msg = e.what();
    // "fuzz.json: PLACE: what" with a non-empty place.
    const std::string head = name + ": ";
    const std::size_t colon = msg.find(": ", head.size());
    if (msg.rfind(head, 0) != 0 || colon == std::string::npos || colon == head.size()) {
      std::fprintf(stderr, "error does not name a place: %s\n", msg.c_str());
      std::abort();
    }
  }
  return 0;
}
