#include "methods/opencl_wrapper.h"

#include "methods/source_scan.h"

#include <fmt/core.h>

#include <algorithm>
#include <cctype>
#include <vector>

namespace rayproof::opencl {

namespace {

/// The groups of a kind's fields after the ray: 3 = a rayproof_real3, 1 = a rayproof_real.
std::vector<int> groups(io::Kind k) {
  switch (k) {
    case io::Kind::plane: return {3, 3};
    case io::Kind::sphere: return {3, 1};
    case io::Kind::ellipsoid: return {3, 3};
    case io::Kind::triangle: return {3, 3, 3};
    case io::Kind::box: return {3, 3};
    case io::Kind::disk: return {3, 3, 1};
    case io::Kind::tritri: break;  // not a ray kind: no OpenCL kernel answers pairs
  }
  return {};
}

/// A C string literal of `s` for #line.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += (c == '\n' || c == '\r') ? '?' : c;
  }
  return out + "\"";
}

}  // namespace

int fields(io::Kind k) { return io::field_count(k); }

std::string function_name(io::Kind k) { return "rayproof_" + std::string(io::to_string(k)); }

std::vector<io::Kind> kinds_defined(const std::string& source) { return rayproof::kinds_defined(source, function_name); }

std::string wrapper_source(const std::string& user_text, const std::string& file_name,
                           const std::vector<io::Kind>& kinds, const WrapperOptions& opt) {
  const bool dbl = opt.precision == Precision::float64;
  std::string s;
  s += "/* rayproof --opencl wrapper (docs/opencl.md) */\n";
  if (dbl) s += "#pragma OPENCL EXTENSION cl_khr_fp64 : enable\n";
  if (opt.contract_off) s += "#pragma OPENCL FP_CONTRACT OFF\n";
  s += dbl ? "typedef double rayproof_real;\ntypedef double3 rayproof_real3;\n"
           : "typedef float rayproof_real;\ntypedef float3 rayproof_real3;\n";
  s += "#define RAYPROOF_REAL_IS_DOUBLE " + std::string(dbl ? "1" : "0") + "\n";
  s += "#define RAYPROOF_MISS 0\n#define RAYPROOF_HIT 1\n#define RAYPROOF_HIT_T 2\n#define RAYPROOF_HIT_TB 3\n";
  s += "#line 1 " + quoted(file_name) + "\n";
  s += user_text;
  if (!user_text.empty() && user_text.back() != '\n') s += '\n';
  s += "#line 1 \"<rayproof wrapper: the signatures of docs/opencl.md>\"\n";
  for (io::Kind k : kinds) {
    const int n = fields(k);
    const bool tri = k == io::Kind::triangle;
    s += fmt::format(
        "__kernel void rayproof_run_{0}(__global const rayproof_real* in, __global int* code, "
        "__global rayproof_real* out, const uint n) {{\n"
        "  const uint i = (uint)get_global_id(0);\n"
        "  if (i >= n) return;\n"
        "  __global const rayproof_real* v = in + (size_t)i * {1};\n"
        "  rayproof_real t = (rayproof_real)NAN, b1 = (rayproof_real)NAN, b2 = (rayproof_real)NAN;\n"
        "  const int c = {2}((rayproof_real3)(v[0], v[1], v[2]), (rayproof_real3)(v[3], v[4], v[5])",
        io::to_string(k), n, function_name(k));
    int at = 6;
    for (int g : groups(k)) {
      if (g == 3) s += fmt::format(", (rayproof_real3)(v[{}], v[{}], v[{}])", at, at + 1, at + 2);
      else s += fmt::format(", v[{}]", at);
      at += g;
    }
    s += tri ? ", &t, &b1, &b2);\n" : ", &t);\n";
    s += "  code[i] = c;\n  out[(size_t)i * 3] = t;\n  out[(size_t)i * 3 + 1] = b1;\n  out[(size_t)i * 3 + 2] = b2;\n}\n";
  }
  return s;
}

std::variant<io::CaseResult, std::string> to_result(io::Kind kind, const RawAnswer& a) {
  io::CaseResult r;
  r.form = io::AnswerForm::coarse;
  switch (a.code) {
    case kMiss: r.contact = Contact::miss; return r;
    case kHit: r.contact = Contact::hit; return r;
    case kHitT: r.contact = Contact::hit, r.t = a.t; return r;
    case kHitTB:
      if (kind != io::Kind::triangle)
        return fmt::format("answer outside the vocabulary: RAYPROOF_HIT_TB (barycentrics) from {}",
                           function_name(kind));
      r.contact = Contact::hit, r.t = a.t, r.b1 = a.b1, r.b2 = a.b2;
      return r;
    default:
      return fmt::format("answer outside the vocabulary: {} returned {} (RAYPROOF_MISS, RAYPROOF_HIT, "
                         "RAYPROOF_HIT_T or RAYPROOF_HIT_TB)", function_name(kind), a.code);
  }
}

}  // namespace rayproof::opencl
