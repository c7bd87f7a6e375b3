// Ray file reader (see ray_file.h), sharing the mesh readers' bounded line reader.
#include "scene/ray_file.h"

#include <istream>

#include "mesh/reader_util.h"
#include "scene/scene.h"

namespace rayproof::scene {

std::vector<RayLine> read_rays(std::istream& in, const std::string& name) {
  std::vector<RayLine> out;
  try {
    mesh::detail::LineReader lines(in, name, '#');
    std::vector<std::string_view> t;
    while (lines.next(t)) {
      if (t.empty()) continue;
      RayLine r;
      r.line = lines.line();
      double v[6] = {};
      std::string err;
      if (t.size() != 6) err = "expected 6 numbers (ox oy oz dx dy dz), got " + std::to_string(t.size()) + " fields";
      for (std::size_t k = 0; k < t.size() && k < 6 && err.empty(); ++k)
        if (!mesh::detail::parse_double(t[k], v[k])) err = mesh::detail::quote(t[k]) + " is not a number";
      if (!err.empty()) r.error = name + ":" + std::to_string(r.line) + ": " + err;
      r.ray = {{v[0], v[1], v[2]}, {v[3], v[4], v[5]}};
      out.push_back(std::move(r));
    }
  } catch (const mesh::MeshError& e) {
    throw SceneError(e.what());
  }
  return out;
}

}  // namespace rayproof::scene
