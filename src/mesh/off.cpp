// OFF reader (Geomview Object File Format): "OFF", counts "nv nf ne", nv vertex lines, nf faces
// "n i0 .. in-1 [colour]". Hand-written rather than CGAL's IO (CGAL belongs in the verify layer)
// so that every error names the line and counts from the header never size an allocation.
#include "mesh/mesh.h"
#include "mesh/reader_util.h"

namespace rayproof::mesh {

Mesh read_off(std::istream& in, const std::string& name) {
  detail::LineReader lines(in, name, '#');
  std::vector<std::string_view> toks;
  if (!lines.next_nonblank(toks)) lines.fail("empty file, expected 'OFF'");
  // The keyword may share its line with the counts ("OFF 8 12 0"); COFF/NOFF variants carry
  // extra per-vertex fields we do not support.
  std::string_view kw = toks[0];
  if (kw != "OFF") lines.fail("expected 'OFF', got " + detail::quote(kw) + " (only plain OFF is supported)");
  detail::TokenReader tr(lines);
  std::vector<std::string_view> rest(toks.begin() + 1, toks.end());
  std::size_t ri = 0;
  auto count = [&](const char* what) -> std::uint64_t {
    if (ri < rest.size()) {
      std::uint64_t v;
      if (!detail::parse_uint(rest[ri], v)) lines.fail(std::string("expected ") + what + ", got " + detail::quote(rest[ri]));
      ++ri;
      return v;
    }
    return tr.need_uint(what);
  };
  const std::uint64_t nv = count("vertex count");
  const std::uint64_t nf = count("face count");
  (void)count("edge count");
  if (nv > 0xffffffffull) lines.fail("vertex count " + std::to_string(nv) + " exceeds 2^32 - 1");
  Mesh m;
  m.vertices.reserve(std::min<std::uint64_t>(nv, detail::kMaxReserve));
  for (std::uint64_t i = 0; i < nv; ++i) {
    const double x = tr.need_double("vertex x"), y = tr.need_double("vertex y"), z = tr.need_double("vertex z");
    m.vertices.push_back({x, y, z});
  }
  std::vector<std::uint32_t> idx;
  m.triangles.reserve(std::min<std::uint64_t>(nf, detail::kMaxReserve));
  for (std::uint64_t f = 0; f < nf; ++f) {
    const std::uint64_t n = tr.need_uint("face corner count");
    if (n < 3) lines.fail("face " + std::to_string(f) + " has " + std::to_string(n) + " corners (need at least 3)");
    if (n > nv) lines.fail("face " + std::to_string(f) + " has " + std::to_string(n) + " corners, more than the " + std::to_string(nv) + " vertices");
    idx.clear();
    for (std::uint64_t k = 0; k < n; ++k) {
      const std::uint64_t v = tr.need_uint("vertex index");
      if (v >= nv) lines.fail("vertex index " + std::to_string(v) + " out of range (" + std::to_string(nv) + " vertices)");
      idx.push_back(static_cast<std::uint32_t>(v));
    }
    detail::add_fan(m, idx.data(), idx.size());
    // Optional colour values follow on the same line: skip the rest of this line's tokens.
    tr.skip_line();
  }
  return m;
}

}  // namespace rayproof::mesh
