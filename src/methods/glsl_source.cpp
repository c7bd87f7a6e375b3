#include "methods/glsl_source.h"

#include "methods/source_scan.h"

#include <fmt/core.h>

#include <cctype>
#include <utility>

namespace rayproof::glsl {

namespace {

/// The named inputs of a kind after o and d, each a vec3 (3) or a real (1), in docs/cases.md order.
std::vector<std::pair<const char*, int>> fields(io::Kind k) {
  switch (k) {
    case io::Kind::plane: return {{"point", 3}, {"normal", 3}};
    case io::Kind::sphere: return {{"center", 3}, {"radius", 1}};
    case io::Kind::ellipsoid: return {{"center", 3}, {"semi_axes", 3}};
    case io::Kind::triangle: return {{"p0", 3}, {"p1", 3}, {"p2", 3}};
    case io::Kind::box: return {{"lo", 3}, {"hi", 3}};
    case io::Kind::disk: return {{"center", 3}, {"normal", 3}, {"radius", 1}};
  }
  return {};
}

}  // namespace

std::string function_name(io::Kind k) { return "rp_" + std::string(io::to_string(k)); }

std::string signature(io::Kind k, Precision p) {
  const bool dbl = p == Precision::float64;
  const std::string real = dbl ? "double" : "float", vec3 = dbl ? "dvec3" : "vec3", vec2 = dbl ? "dvec2" : "vec2";
  std::string s = "int " + function_name(k) + "(" + vec3 + " o, " + vec3 + " d";
  for (const auto& [name, n] : fields(k)) s += ", " + (n == 3 ? vec3 : real) + " " + name;
  s += ", out " + real + " t";
  if (k == io::Kind::triangle) s += ", out " + vec2 + " b";
  return s + ")";
}

std::vector<io::Kind> defined_kinds(std::string_view user_text) { return kinds_defined(user_text, function_name); }

std::string prepare_user_text(std::string_view user_text) {
  std::string out;
  std::size_t pos = 0;
  while (pos <= user_text.size()) {
    std::size_t end = user_text.find('\n', pos);
    if (end == std::string_view::npos) end = user_text.size();
    std::string_view line = user_text.substr(pos, end - pos);
    std::size_t i = 0;
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    const bool version = line.substr(i, 1) == "#" && [&] {
      std::size_t j = i + 1;
      while (j < line.size() && (line[j] == ' ' || line[j] == '\t')) ++j;
      return line.substr(j, 7) == "version";
    }();
    if (!version) out.append(line);
    if (end < user_text.size()) out += '\n';
    pos = end + 1;
  }
  return out;
}

std::string wrap(std::string_view user_text, std::string_view label, io::Kind k, Precision p) {
  const bool dbl = p == Precision::float64;
  std::string safe_label;
  for (char c : label) safe_label += (c == '"' || c == '\\' || c == '\n') ? '_' : c;
  std::string s = fmt::format(
      "#version 450\n"
      "#extension GL_GOOGLE_cpp_style_line_directive : require\n"
      "layout(local_size_x = {}) in;\n"
      "#define RP_MISS 0\n#define RP_HIT 1\n#define RP_HIT_T 2\n#define RP_HIT_T_B 3\n"
      "#define rp_real {}\n#define rp_vec2 {}\n#define rp_vec3 {}\n{}",
      kWorkgroup, dbl ? "double" : "float", dbl ? "dvec2" : "vec2", dbl ? "dvec3" : "vec3",
      dbl ? "#define RP_DOUBLE 1\n" : "");
  s += "#line 1 \"" + safe_label + "\"\n";
  s += prepare_user_text(user_text);
  s += "\n#line 1 \"rayproof wrapper calling " + function_name(k) + "\"\n";
  s += fmt::format(
      "layout(std430, binding = 0) readonly buffer RpIn {{ rp_real rp_in[]; }};\n"
      "layout(std430, binding = 1) writeonly buffer RpOut {{ rp_real rp_out[]; }};\n"
      "layout(push_constant) uniform RpCount {{ uint rp_n; }};\n"
      "void main() {{\n"
      "  uint i = gl_GlobalInvocationID.x;\n"
      "  if (i >= rp_n) return;\n"
      "  uint b = i * {}u;\n",
      kInReals);
  int at = 0;
  auto vec = [&](const char* name) {
    s += fmt::format("  rp_vec3 {0} = rp_vec3(rp_in[b + {1}u], rp_in[b + {2}u], rp_in[b + {3}u]);\n", name, at, at + 1,
                     at + 2);
    at += 3;
  };
  vec("o");
  vec("d");
  std::string args = "o, d";
  for (const auto& [name, n] : fields(k)) {
    const std::string local = std::string("rp_") + name;
    if (n == 3) {
      vec(local.c_str());
    } else {
      s += fmt::format("  rp_real {} = rp_in[b + {}u];\n", local, at);
      at += 1;
    }
    args += ", " + local;
  }
  s += "  rp_real t = rp_real(0);\n  rp_vec2 bc = rp_vec2(0);\n";
  s += fmt::format("  int code = {}({}, t{});\n", function_name(k), args, k == io::Kind::triangle ? ", bc" : "");
  s += fmt::format(
      "  uint r = i * {}u;\n"
      "  rp_out[r] = rp_real(code);\n  rp_out[r + 1u] = t;\n  rp_out[r + 2u] = bc.x;\n  rp_out[r + 3u] = bc.y;\n"
      "}}\n",
      kOutReals);
  return s;
}

std::string explain_compile_error(const std::string& message, io::Kind k, Precision p) {
  if (message.find("rayproof wrapper calling") == std::string::npos) return message;
  std::string out = message;
  if (!out.empty() && out.back() != '\n') out += '\n';
  out += "rayproof calls " + signature(k, p) + " (docs/shaders.md): does your " + function_name(k) +
         " have this signature and return int?";
  return out;
}

std::vector<std::uint32_t> decorate_no_contraction(const std::vector<std::uint32_t>& spirv) {
  constexpr std::uint32_t kMagic = 0x07230203;
  if (spirv.size() < 5 || spirv[0] != kMagic) return {};
  // Opcodes (SPIR-V 1.x): float arithmetic whose result the driver may contract or reorder.
  auto arithmetic = [](std::uint32_t op) {
    switch (op) {
      case 127: case 129: case 131: case 133: case 136: case 140: case 141:  // FNegate FAdd FSub FMul FDiv FRem FMod
      case 142: case 143: case 144: case 145: case 146: case 147: case 148:  // *TimesScalar .. OuterProduct, Dot
      case 12:                                                              // ExtInst (GLSL.std.450: cross, fma, ...)
        return true;
      default: return false;
    }
  };
  auto annotation = [](std::uint32_t op) { return (op >= 71 && op <= 75) || op == 332 || op == 5632 || op == 5633; };
  std::vector<std::uint32_t> ids;
  std::size_t insert_at = 0;
  for (std::size_t i = 5; i < spirv.size();) {
    const std::uint32_t count = spirv[i] >> 16, op = spirv[i] & 0xffff;
    if (count == 0 || i + count > spirv.size()) return {};
    if (insert_at == 0 && annotation(op)) insert_at = i;
    if (arithmetic(op) && count >= 3) ids.push_back(spirv[i + 2]);
    i += count;
  }
  if (insert_at == 0) return {};
  std::vector<std::uint32_t> out(spirv.begin(), spirv.begin() + static_cast<std::ptrdiff_t>(insert_at));
  for (std::uint32_t id : ids) {
    out.push_back((3u << 16) | 71u);  // OpDecorate
    out.push_back(id);
    out.push_back(42u);  // NoContraction
  }
  out.insert(out.end(), spirv.begin() + static_cast<std::ptrdiff_t>(insert_at), spirv.end());
  return out;
}

}  // namespace rayproof::glsl
