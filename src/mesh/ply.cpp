// PLY reader (Turk's polygon file format): ASCII, binary_little_endian and binary_big_endian.
// Reads x, y, z of `vertex` and the `vertex_indices` (or `vertex_index`) list of `face`; every
// other element and property is read past. Hand-written rather than a library so that errors name
// the line (header, ASCII) or byte (binary), and a binary element count is checked against the
// bytes left in the file before anything is reserved.
#include <algorithm>
#include <limits>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "mesh/mesh.h"
#include "mesh/reader_util.h"

namespace rayproof::mesh {
namespace {

enum class Type { i8, u8, i16, u16, i32, u32, f32, f64 };
struct Prop {
  std::string name;
  Type type = Type::f32;
  bool list = false;
  Type count_type = Type::u8;
};
struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Prop> props;
  std::size_t line = 0;
};

bool type_of(std::string_view s, Type& t) {
  static const std::pair<const char*, Type> names[] = {
      {"char", Type::i8},   {"int8", Type::i8},    {"uchar", Type::u8},  {"uint8", Type::u8},    {"short", Type::i16},
      {"int16", Type::i16}, {"ushort", Type::u16}, {"uint16", Type::u16}, {"int", Type::i32},     {"int32", Type::i32},
      {"uint", Type::u32},  {"uint32", Type::u32}, {"float", Type::f32}, {"float32", Type::f32}, {"double", Type::f64},
      {"float64", Type::f64}};
  for (const auto& [n, ty] : names)
    if (s == n) return t = ty, true;
  return false;
}
int size_of(Type t) {
  switch (t) {
    case Type::i8: case Type::u8: return 1;
    case Type::i16: case Type::u16: return 2;
    case Type::i32: case Type::u32: case Type::f32: return 4;
    case Type::f64: break;
  }
  return 8;
}
std::string fmt_index(double v) {
  char b[64];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
bool is_integer(Type t) { return t != Type::f32 && t != Type::f64; }
/// The range of an integer type (for ASCII values, which a binary file cannot exceed); `name` for
/// messages. Float types: the whole line.
struct Range {
  double lo, hi;
  const char* name;
};
Range range_of(Type t) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  switch (t) {
    case Type::i8: return {-128.0, 127.0, "char"};
    case Type::u8: return {0.0, 255.0, "uchar"};
    case Type::i16: return {-32768.0, 32767.0, "short"};
    case Type::u16: return {0.0, 65535.0, "ushort"};
    case Type::i32: return {-2147483648.0, 2147483647.0, "int"};
    case Type::u32: return {0.0, 4294967295.0, "uint"};
    case Type::f32: return {-inf, inf, "float"};
    case Type::f64: break;
  }
  return {-inf, inf, "double"};
}

/// Reads binary values, tracking the byte offset for messages.
struct BinaryReader {
  std::istream& in;
  const std::string& name;
  bool big;
  std::uint64_t offset;
  double read(Type t) {
    unsigned char b[8];
    const int n = size_of(t);
    if (in.rdbuf()->sgetn(reinterpret_cast<char*>(b), n) != n) detail::fail_byte(name, offset, "unexpected end of file");
    offset += n;
    if (big != (std::endian::native == std::endian::big)) std::reverse(b, b + n);
    switch (t) {
      case Type::i8: return static_cast<std::int8_t>(b[0]);
      case Type::u8: return b[0];
      case Type::i16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::u16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case Type::i32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::u32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case Type::f32: { float v; std::memcpy(&v, b, 4); return v; }
      case Type::f64: break;
    }
    double v;
    std::memcpy(&v, b, 8);
    return v;
  }
};

}  // namespace

Mesh read_ply(std::istream& in, const std::string& name) {
  detail::LineReader lines(in, name, 0);
  std::vector<std::string_view> t;
  if (!lines.next(t) || t.size() != 1 || t[0] != "ply") lines.fail("not a PLY file (first line must be 'ply')");
  int format = -1;  // 0 ascii, 1 little endian, 2 big endian
  std::vector<Element> elems;
  for (;;) {
    if (!lines.next(t)) lines.fail("unexpected end of file in the header (no 'end_header')");
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") break;
    if (t[0] == "format") {
      if (t.size() != 3) lines.fail("'format' needs a format and a version");
      if (t[1] == "ascii") format = 0;
      else if (t[1] == "binary_little_endian") format = 1;
      else if (t[1] == "binary_big_endian") format = 2;
      else lines.fail("unknown PLY format " + detail::quote(t[1]));
    } else if (t[0] == "element") {
      std::uint64_t n;
      if (t.size() != 3 || !detail::parse_uint(t[2], n)) lines.fail("'element' needs a name and a count");
      elems.push_back({std::string(t[1]), n, {}, lines.line()});
    } else if (t[0] == "property") {
      if (elems.empty()) lines.fail("'property' before any 'element'");
      Prop p;
      if (t.size() == 5 && t[1] == "list") {
        if (!type_of(t[2], p.count_type) || !type_of(t[3], p.type) || !is_integer(p.count_type))
          lines.fail("bad list property types");
        p.list = true;
        p.name = t[4];
      } else if (t.size() == 3) {
        if (!type_of(t[1], p.type)) lines.fail("unknown property type " + detail::quote(t[1]));
        p.name = t[2];
      } else {
        lines.fail("malformed 'property' line");
      }
      elems.back().props.push_back(p);
    } else {
      lines.fail("unexpected " + detail::quote(t[0]) + " in the header");
    }
  }
  if (format < 0) lines.fail("no 'format' line in the header");

  Mesh m;
  std::uint64_t nv = 0;
  bool have_vertices = false;
  const std::int64_t left = format == 0 ? -1 : detail::remaining_bytes(in);
  std::uint64_t need = 0;  // minimum bytes the binary body must hold
  for (const auto& e : elems) {
    std::uint64_t min_item = 0;
    for (const auto& p : e.props) min_item += size_of(p.list ? p.count_type : p.type);
    if (left >= 0 && min_item > 0 && e.count > (static_cast<std::uint64_t>(left) - std::min<std::uint64_t>(need, left)) / min_item)
      detail::fail_line(name, e.line, "element " + detail::quote(e.name) + " claims " + std::to_string(e.count) +
                                          " items, more than the " + std::to_string(left) + " bytes after the header can hold");
    need += e.count * min_item;
  }
  detail::TokenReader tokens(lines);
  BinaryReader bin{in, name, format == 2, 0};
  if (format != 0) {
    const auto here = in.tellg();
    bin.offset = here < 0 ? 0 : static_cast<std::uint64_t>(here);
  }
  auto fail_here = [&](const std::string& what) {
    if (format == 0) lines.fail(what);
    detail::fail_byte(name, bin.offset, what);
  };
  // An ASCII value of an integer type must lie in that type's range, as a binary one does: a count
  // of 1e90 for a `uchar` is refused here rather than cast to an integer later.
  auto value = [&](Type ty, const char* what) -> double {
    if (format != 0) return bin.read(ty);
    const double v = tokens.need_double(what);
    const Range r = range_of(ty);
    if (v < r.lo || v > r.hi) fail_here(std::string(what) + " " + fmt_index(v) + " is outside the range of " + r.name);
    return v;
  };
  std::vector<std::uint32_t> idx;
  for (const auto& e : elems) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int xyz[3] = {-1, -1, -1};
    int list_prop = -1;
    for (std::size_t k = 0; k < e.props.size(); ++k) {
      const auto& p = e.props[k];
      if (is_vertex && !p.list && (p.name == "x" || p.name == "y" || p.name == "z")) xyz[p.name[0] - 'x'] = int(k);
      if (is_face && p.list && (p.name == "vertex_indices" || p.name == "vertex_index")) list_prop = int(k);
    }
    if (is_vertex) {
      if (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0) detail::fail_line(name, e.line, "element 'vertex' lacks x, y or z");
      if (e.count > 0xffffffffull) detail::fail_line(name, e.line, "more than 2^32 - 1 vertices");
      nv = e.count;
      have_vertices = true;
      m.vertices.reserve(std::min<std::uint64_t>(nv, detail::kMaxReserve));
    }
    if (is_face) {
      if (list_prop < 0) detail::fail_line(name, e.line, "element 'face' has no 'vertex_indices' list");
      if (!have_vertices) detail::fail_line(name, e.line, "element 'face' comes before element 'vertex'");
    }
    // An element without properties holds no data: its count (possibly 2^64 - 1) is not looped over.
    const std::uint64_t items = e.props.empty() ? 0 : e.count;
    for (std::uint64_t i = 0; i < items; ++i) {
      double c[3] = {0, 0, 0};
      for (std::size_t k = 0; k < e.props.size(); ++k) {
        const auto& p = e.props[k];
        if (!p.list) {
          const double v = value(p.type, "property value");
          if (is_vertex)
            for (int a = 0; a < 3; ++a)
              if (xyz[a] == int(k)) {
                if (!std::isfinite(v)) fail_here("vertex coordinate is not finite");
                c[a] = v;
              }
          continue;
        }
        const double n = value(p.count_type, "list count");
        if (!(n >= 0) || n != std::floor(n)) fail_here("bad list count");
        const bool faces = is_face && int(k) == list_prop;
        if (faces && n < 3) fail_here("face " + std::to_string(i) + " has " + std::to_string(std::uint64_t(n)) + " corners (need at least 3)");
        idx.clear();
        for (std::uint64_t j = 0; j < static_cast<std::uint64_t>(n); ++j) {
          const double v = value(p.type, "list value");
          if (!faces) continue;
          if (!(v >= 0 && v < double(nv)) || v != std::floor(v))
            fail_here("vertex index " + fmt_index(v) + " out of range (" + std::to_string(nv) + " vertices)");
          idx.push_back(static_cast<std::uint32_t>(v));
        }
        if (faces) detail::add_fan(m, idx.data(), idx.size());
      }
      if (is_vertex) m.vertices.push_back({c[0], c[1], c[2]});
    }
  }
  return m;
}

}  // namespace rayproof::mesh
