#pragma once
/// Ray files for `rayproof cast`: one ray `ox oy oz dx dy dz` per line, `#` comments, blank lines
/// skipped. Numbers are whatever strtod reads whole (so `nan` and `inf` read, and make the ray
/// `invalid` as docs/cases.md says). A line that cannot be read is kept as an error naming the file and
/// the line, so that the caller can answer it in place and go on with the good lines.
#include <iosfwd>
#include <string>
#include <vector>

#include "rayproof/ray.h"

namespace rayproof::scene {

struct RayLine {
  Ray<double> ray{};
  std::size_t line = 0;  ///< 1-based line number in the file
  std::string error;     ///< empty, or "NAME:LINE: what"
};

/// Reads every non-blank line. Throws SceneError ("NAME:LINE: ...") only when the file cannot be
/// read at all (a line longer than the reader's bound); never holds more than one line of text.
[[nodiscard]] std::vector<RayLine> read_rays(std::istream& in, const std::string& name);

}  // namespace rayproof::scene
