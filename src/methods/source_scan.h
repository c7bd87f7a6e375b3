#pragma once
/// Scanning a user's C-like source (OpenCL C for --opencl, GLSL for --glsl) for the functions
/// rayproof wraps around it.
#include <string>
#include <string_view>
#include <vector>

#include "io/case_file.h"

namespace rayproof {

/// `s` with every comment (// and /* */) turned into spaces, newlines kept so line numbers stay;
/// the insides of string literals are left alone.
[[nodiscard]] std::string blank_comments(std::string_view s);

/// The kinds whose function `name(kind)` appears outside comments as a whole identifier followed by
/// '(' (a definition or a call), in io::kAllKinds order.
[[nodiscard]] std::vector<io::Kind> kinds_defined(std::string_view source, std::string (*name)(io::Kind));

}  // namespace rayproof
