// Wavefront OBJ reader: `v x y z [w]` and `f` polygons (`i`, `i/t`, `i//n`, `i/t/n`, negative
// indices relative to the vertices read so far); every other statement is ignored. Hand-written
// rather than tinyobjloader so that a bad index or number is reported with its line and the
// reader never keeps more than one line of text.
#include "mesh/mesh.h"
#include "mesh/reader_util.h"

namespace rayproof::mesh {

Mesh read_obj(std::istream& in, const std::string& name) {
  detail::LineReader lines(in, name, '#');
  std::vector<std::string_view> toks;
  std::vector<std::uint32_t> idx;
  Mesh m;
  while (lines.next(toks)) {
    if (toks.empty()) continue;
    if (toks[0] == "v") {
      if (toks.size() < 4 || toks.size() > 5) lines.fail("'v' needs 3 coordinates (and an optional w)");
      double c[3];
      for (int k = 0; k < 3; ++k) {
        if (!detail::parse_double(toks[1 + k], c[k])) lines.fail("bad vertex coordinate " + detail::quote(toks[1 + k]));
        if (!std::isfinite(c[k])) lines.fail("vertex coordinate is not finite: " + detail::quote(toks[1 + k]));
      }
      if (m.vertices.size() == 0xffffffffu) lines.fail("more than 2^32 - 1 vertices");
      m.vertices.push_back({c[0], c[1], c[2]});
    } else if (toks[0] == "f") {
      if (toks.size() < 4) lines.fail("'f' needs at least 3 vertices");
      idx.clear();
      const auto nv = static_cast<std::int64_t>(m.vertices.size());
      for (std::size_t k = 1; k < toks.size(); ++k) {
        const std::string_view ref = toks[k].substr(0, toks[k].find('/'));
        std::int64_t i;
        if (!detail::parse_int(ref, i) || i == 0)
          lines.fail("bad face vertex " + detail::quote(toks[k]) + " (expected a non-zero integer index)");
        const std::int64_t zero_based = i > 0 ? i - 1 : nv + i;
        if (zero_based < 0 || zero_based >= nv)
          lines.fail("face vertex index " + std::to_string(i) + " out of range (" + std::to_string(nv) + " vertices so far)");
        idx.push_back(static_cast<std::uint32_t>(zero_based));
      }
      detail::add_fan(m, idx.data(), idx.size());
    }
  }
  if (in.bad()) throw MeshError(name + ": read error");
  return m;
}

}  // namespace rayproof::mesh
