#include "report/method_style.h"

#include <fmt/core.h>

namespace rayproof::report {

namespace {
// Ten colours a reader tells apart on white, one hue each (blue, vermilion, bluish green, purple,
// gold, sky blue, black, magenta, brown, olive); no two browns or two greys, no orange beside
// vermilion. Every two are at least 77 apart in RGB (the test asks for 70).
constexpr const char* kColours[kColourCount] = {"#0072b2", "#d55e00", "#009e73", "#7b3294", "#e6b800",
                                                "#56b4e9", "#000000", "#e7298a", "#8c564b", "#808000"};
constexpr Marker kMarkers[kMarkerCount] = {Marker::circle,   Marker::square,        Marker::triangle, Marker::diamond,
                                           Marker::triangle_down, Marker::plus, Marker::cross};
}  // namespace

// Colour i mod 10; marker (i + 3 (i div 10)) mod 7: methods 10 colours apart differ in marker by
// 13k mod 7, never 0 for k = 1..6, so the first 70 never repeat a pair, and the eleventh and twelfth
// methods (the default report has twelve) take markers their colour's first user does not have.
MethodStyle method_style(std::size_t index) {
  return {kColours[index % kColourCount], kMarkers[(index + 3 * (index / kColourCount)) % kMarkerCount]};
}

std::string marker_svg(Marker m, double x, double y, double r, const char* colour, bool hollow) {
  const std::string paint = hollow ? fmt::format("fill='white' stroke='{}' stroke-width='2'", colour)
                                   : fmt::format("fill='{}' stroke='{}' stroke-width='0.5'", colour, colour);
  switch (m) {
    case Marker::circle:
      return fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='{:.1f}' {}/>", x, y, r, paint);
    case Marker::square:
      return fmt::format("<rect x='{:.1f}' y='{:.1f}' width='{:.1f}' height='{:.1f}' {}/>", x - 0.9 * r, y - 0.9 * r,
                         1.8 * r, 1.8 * r, paint);
    case Marker::triangle:
      return fmt::format("<polygon points='{:.1f},{:.1f} {:.1f},{:.1f} {:.1f},{:.1f}' {}/>", x, y - 1.15 * r,
                         x - 1.1 * r, y + 0.85 * r, x + 1.1 * r, y + 0.85 * r, paint);
    case Marker::triangle_down:
      return fmt::format("<polygon points='{:.1f},{:.1f} {:.1f},{:.1f} {:.1f},{:.1f}' {}/>", x, y + 1.15 * r,
                         x - 1.1 * r, y - 0.85 * r, x + 1.1 * r, y - 0.85 * r, paint);
    case Marker::diamond:
      return fmt::format("<polygon points='{:.1f},{:.1f} {:.1f},{:.1f} {:.1f},{:.1f} {:.1f},{:.1f}' {}/>", x, y - 1.25 * r,
                         x + 1.0 * r, y, x, y + 1.25 * r, x - 1.0 * r, y, paint);
    case Marker::plus:
    case Marker::cross: {
      // A thick plus (or x): two bars as one outlined polygon, so that hollow works like the others.
      const double a = 1.2 * r, b = 0.42 * r;
      const double px[] = {-b, b, b, a, a, b, b, -b, -b, -a, -a, -b};
      const double py[] = {-a, -a, -b, -b, b, b, a, a, b, b, -b, -b};
      const double c = m == Marker::cross ? 0.70710678 : 1.0, s = m == Marker::cross ? 0.70710678 : 0.0;
      std::string pts;
      for (int i = 0; i < 12; ++i)
        pts += fmt::format("{:.1f},{:.1f} ", x + c * px[i] - s * py[i], y + s * px[i] + c * py[i]);
      pts.pop_back();
      return fmt::format("<polygon points='{}' {}/>", pts, paint);
    }
  }
  return "";
}

}  // namespace rayproof::report
