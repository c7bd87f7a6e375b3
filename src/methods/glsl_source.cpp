#include "methods/glsl_source.h"

#include "methods/source_scan.h"

#include <fmt/core.h>

#include <algorithm>
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
    case io::Kind::tritri: break;  // two triangles, no ray: shader kernels answer the ray kinds only
  }
  return {};
}

}  // namespace

std::string function_name(io::Kind k) { return "rayproof_" + std::string(io::to_string(k)); }

std::string legacy_function_name(io::Kind k) { return "rp_" + std::string(io::to_string(k)); }

std::string signature(io::Kind k, Precision p) {
  const bool dbl = p == Precision::float64;
  const std::string real = dbl ? "double" : "float", vec3 = dbl ? "dvec3" : "vec3", vec2 = dbl ? "dvec2" : "vec2";
  std::string s = "int " + function_name(k) + "(" + vec3 + " o, " + vec3 + " d";
  for (const auto& [name, n] : fields(k)) s += ", " + (n == 3 ? vec3 : real) + " " + name;
  s += ", out " + real + " t";
  if (k == io::Kind::triangle) s += ", out " + vec2 + " b";
  return s + ")";
}

std::vector<io::Kind> defined_kinds(std::string_view user_text) {
  const auto now = kinds_defined(user_text, function_name), old = kinds_defined(user_text, legacy_function_name);
  std::vector<io::Kind> out;
  for (io::Kind k : io::kAllKinds)
    if (std::find(now.begin(), now.end(), k) != now.end() || std::find(old.begin(), old.end(), k) != old.end())
      out.push_back(k);
  return out;
}

std::vector<io::Kind> legacy_kinds(std::string_view user_text) {
  const auto now = kinds_defined(user_text, function_name), old = kinds_defined(user_text, legacy_function_name);
  std::vector<io::Kind> out;
  for (io::Kind k : old)
    if (std::find(now.begin(), now.end(), k) == now.end()) out.push_back(k);
  return out;
}

std::string legacy_names_warning(std::string_view file, std::string_view user_text) {
  const auto old = legacy_kinds(user_text);
  if (old.empty()) return {};
  std::string names, renamed;
  for (io::Kind k : old) {
    names += (names.empty() ? "" : ", ") + legacy_function_name(k);
    renamed += (renamed.empty() ? "" : ", ") + function_name(k);
  }
  return fmt::format("rayproof --glsl {}: {} {} the old GLSL spelling; rename {} {} (and RP_*, rp_real, rp_vec* to "
                     "RAYPROOF_*, rayproof_real, rayproof_real*), the names OpenCL kernels use too. The old names "
                     "work in this release and are removed in the next (docs/shaders.md).",
                     file, names, old.size() == 1 ? "is" : "are", old.size() == 1 ? "it" : "them", renamed);
}

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
      "#define RAYPROOF_MISS 0\n#define RAYPROOF_HIT 1\n#define RAYPROOF_HIT_T 2\n#define RAYPROOF_HIT_TB 3\n"
      "#define RAYPROOF_REAL_IS_DOUBLE {}\n"
      "#define rayproof_real {}\n#define rayproof_real2 {}\n#define rayproof_real3 {}\n"
      "// The old spellings, for one release (legacy_names_warning says so):\n"
      "#define RP_MISS 0\n#define RP_HIT 1\n#define RP_HIT_T 2\n#define RP_HIT_T_B 3\n"
      "#define rp_real rayproof_real\n#define rp_vec2 rayproof_real2\n#define rp_vec3 rayproof_real3\n{}",
      kWorkgroup, dbl ? 1 : 0, dbl ? "double" : "float", dbl ? "dvec2" : "vec2", dbl ? "dvec3" : "vec3",
      dbl ? "#define RP_DOUBLE 1\n" : "");
  s += "#line 1 \"" + safe_label + "\"\n";
  s += prepare_user_text(user_text);
  const auto old = legacy_kinds(user_text);
  const std::string callee = std::find(old.begin(), old.end(), k) != old.end() ? legacy_function_name(k) : function_name(k);
  s += "\n#line 1 \"rayproof wrapper calling " + callee + "\"\n";
  s += fmt::format(
      "layout(std430, binding = 0) readonly buffer RayproofIn {{ rayproof_real rayproof_in[]; }};\n"
      "layout(std430, binding = 1) writeonly buffer RayproofOut {{ rayproof_real rayproof_out[]; }};\n"
      "layout(push_constant) uniform RayproofCount {{ uint rayproof_n; }};\n"
      "void main() {{\n"
      "  uint i = gl_GlobalInvocationID.x;\n"
      "  if (i >= rayproof_n) return;\n"
      "  uint b = i * {}u;\n",
      kInReals);
  int at = 0;
  auto vec = [&](const char* name) {
    s += fmt::format("  rayproof_real3 {0} = rayproof_real3(rayproof_in[b + {1}u], rayproof_in[b + {2}u], "
                     "rayproof_in[b + {3}u]);\n", name, at, at + 1, at + 2);
    at += 3;
  };
  vec("o");
  vec("d");
  std::string args = "o, d";
  for (const auto& [name, n] : fields(k)) {
    const std::string local = std::string("rayproof_") + name;
    if (n == 3) {
      vec(local.c_str());
    } else {
      s += fmt::format("  rayproof_real {} = rayproof_in[b + {}u];\n", local, at);
      at += 1;
    }
    args += ", " + local;
  }
  s += "  rayproof_real t = rayproof_real(0);\n  rayproof_real2 bc = rayproof_real2(0);\n";
  s += fmt::format("  int code = {}({}, t{});\n", callee, args, k == io::Kind::triangle ? ", bc" : "");
  s += fmt::format(
      "  uint r = i * {}u;\n"
      "  rayproof_out[r] = rayproof_real(code);\n  rayproof_out[r + 1u] = t;\n  rayproof_out[r + 2u] = bc.x;\n"
      "  rayproof_out[r + 3u] = bc.y;\n"
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
