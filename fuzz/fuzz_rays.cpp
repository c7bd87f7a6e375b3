// libFuzzer harness: arbitrary bytes as a ray file for `rayproof cast`. The reader must never
// crash; every line it keeps is a ray or an error "NAME:LINE: ..." with that line's number; line
// numbers increase; a read failure is a SceneError naming the line.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "fuzz/mesh_reader_check.h"
#include "scene/ray_file.h"
#include "scene/scene.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string name = "fuzz.rays";
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size), std::ios::in | std::ios::binary);
  try {
    std::size_t last = 0;
    for (const auto& r : rayproof::scene::read_rays(in, name)) {
      if (r.line <= last) std::abort();
      last = r.line;
      if (!r.error.empty() && r.error.rfind(name + ":" + std::to_string(r.line) + ": ", 0) != 0) {
        std::fprintf(stderr, "bad error message: %s\n", r.error.c_str());
        std::abort();
      }
      if (r.error.size() > 256) {
        std::fprintf(stderr, "unbounded error message (%zu bytes)\n", r.error.size());
        std::abort();
      }
    }
  } catch (const rayproof::scene::SceneError& e) {
    if (!rayproof::fuzz::names_a_place(e.what(), name)) {
      std::fprintf(stderr, "error does not name a place: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
