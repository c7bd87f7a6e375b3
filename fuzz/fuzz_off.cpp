// libFuzzer harness: arbitrary bytes as a .off file (see mesh_reader_check.h for the properties).
#include "fuzz/mesh_reader_check.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return rayproof::fuzz::check_mesh_reader(data, size, rayproof::mesh::MeshFormat::off, "fuzz.off");
}
