#pragma once
// Shared body of the mesh-reader harnesses: arbitrary bytes as a mesh file in memory. The reader
// must never crash, must either return a mesh whose every index is in range and every coordinate
// finite, or throw a MeshError that names the file and the place ("NAME:LINE: ..." or
// "NAME: byte N: ..."). Anything else escaping the reader is a bug.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "mesh/mesh.h"

namespace rayproof::fuzz {

/// True when `msg` is "NAME:DIGITS: ..." or "NAME: byte DIGITS: ...".
inline bool names_a_place(const std::string& msg, const std::string& name) {
  if (msg.rfind(name, 0) != 0) return false;
  std::size_t i = name.size();
  if (msg.compare(i, 7, ": byte ") == 0) i += 7;
  else if (msg.compare(i, 1, ":") == 0) i += 1;
  else return false;
  const std::size_t digits = i;
  while (i < msg.size() && msg[i] >= '0' && msg[i] <= '9') ++i;
  return i > digits && msg.compare(i, 2, ": ") == 0 && msg.size() > i + 2;
}

inline int check_mesh_reader(const std::uint8_t* data, std::size_t size, mesh::MeshFormat f, const std::string& name) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size), std::ios::in | std::ios::binary);
  try {
    const mesh::Mesh m = mesh::read_mesh(in, f, name);
    for (const auto& t : m.triangles)
      for (const std::uint32_t i : t)
        if (i >= m.vertices.size()) {
          std::fprintf(stderr, "index %u out of range (%zu vertices)\n", i, m.vertices.size());
          std::abort();
        }
    for (const auto& v : m.vertices)
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
        std::fprintf(stderr, "non-finite vertex accepted\n");
        std::abort();
      }
  } catch (const mesh::MeshError& e) {
    if (!names_a_place(e.what(), name)) {
      std::fprintf(stderr, "error does not name a place: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}

}  // namespace rayproof::fuzz
