#pragma once
/// How a method is drawn in every chart of the report (error_vs_time.svg, stability.svg and the
/// same charts in report.html): a colour and a marker from fixed lists. The i-th method takes
/// colour i mod 10 and marker (i + 3 (i div 10)) mod 7, so no two of the first 70 methods share
/// both, the first ten all differ in colour, and two methods of one colour differ in marker.
#include <cstddef>
#include <string>

namespace rayproof::report {

enum class Marker { circle, square, triangle, diamond, triangle_down, plus, cross };

struct MethodStyle {
  const char* colour;  ///< "#rrggbb"
  Marker marker;
};

inline constexpr std::size_t kColourCount = 10, kMarkerCount = 7;

/// The style of the method at `index` in the report's method order.
[[nodiscard]] MethodStyle method_style(std::size_t index);

/// The marker as SVG shapes centred on (x, y), about 2r across; `hollow` draws its outline only
/// (float methods in error_vs_time.svg).
[[nodiscard]] std::string marker_svg(Marker m, double x, double y, double r, const char* colour, bool hollow);

}  // namespace rayproof::report
