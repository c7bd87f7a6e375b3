/// irradiance_sweep.svg: see sweep_svg.h.
#include "report/sweep_svg.h"
#include "report/html.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace rayproof::report {

namespace {

const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"};
const char* kDashes[] = {"", "6,3", "2,2", "8,3,2,3", "1,3", "10,4", "4,4,1,4", "12,2"};

struct Range {
  double lo = 1e300, hi = -1e300;
  void add(double v) {
    if (v > 0 && std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  }
  [[nodiscard]] double l0() const { return std::floor(std::log10(lo)); }
  [[nodiscard]] double l1() const { return std::max(std::ceil(std::log10(hi)), l0() + 1); }
};

std::string panel(double x0, double y0, double w, double h, bool by_time, const std::vector<SweepSeries>& series,
                  const std::map<std::string, int>& colour, const std::map<std::string, int>& dash) {
  auto xval = [&](const SweepPoint& p) { return by_time ? p.seconds : static_cast<double>(p.samples); };
  Range xr, yr;
  for (const auto& s : series)
    for (const auto& p : s.points) xr.add(xval(p)), yr.add(p.rms_error), yr.add(p.mean_std_error);
  if (xr.lo > xr.hi) xr = {1, 10};
  if (yr.lo > yr.hi) yr = {1e-3, 1};
  const double ox = x0 + 60, oy = y0 + 25, pw = w - 80, ph = h - 70;
  const double lx0 = xr.l0(), lx1 = xr.l1(), ly0 = yr.l0(), ly1 = yr.l1();
  auto X = [&](double v) { return ox + (std::log10(v) - lx0) / (lx1 - lx0) * pw; };
  auto Y = [&](double v) { return oy + ph - (std::log10(v) - ly0) / (ly1 - ly0) * ph; };
  std::string s;
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='13' font-weight='bold'>RMS error against {}</text>\n", ox,
                   y0 + 14, by_time ? "run time" : "sample count");
  s += fmt::format("<rect x='{:.0f}' y='{:.0f}' width='{:.0f}' height='{:.0f}' fill='none' stroke='#888'/>\n", ox, oy, pw, ph);
  for (double e = lx0; e <= lx1 + 1e-9; ++e) {
    const double x = X(std::pow(10.0, e));
    s += fmt::format("<line x1='{:.1f}' y1='{:.0f}' x2='{:.1f}' y2='{:.0f}' stroke='#ddd'/>", x, oy, x, oy + ph);
    s += fmt::format("<text x='{:.1f}' y='{:.0f}' font-size='10' text-anchor='middle'>{:g}</text>\n", x, oy + ph + 12,
                     std::pow(10.0, e));
  }
  for (double e = ly0; e <= ly1 + 1e-9; ++e) {
    const double y = Y(std::pow(10.0, e));
    s += fmt::format("<line x1='{:.0f}' y1='{:.1f}' x2='{:.0f}' y2='{:.1f}' stroke='#ddd'/>", ox, y, ox + pw, y);
    s += fmt::format("<text x='{:.0f}' y='{:.1f}' font-size='10' text-anchor='end'>{:g}</text>\n", ox - 4, y + 3,
                     std::pow(10.0, e));
  }
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='11' text-anchor='middle'>{}</text>\n", ox + pw / 2,
                   oy + ph + 28, by_time ? "seconds per estimate (log)" : "samples N (log)");
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='11' text-anchor='middle' transform='rotate(-90 {:.0f} {:.0f})'>"
                   "RMS error over seeds (log)</text>\n", x0 + 14, oy + ph / 2, x0 + 14, oy + ph / 2);
  s += fmt::format("<clipPath id='clip{}'><rect x='{:.0f}' y='{:.0f}' width='{:.0f}' height='{:.0f}'/></clipPath>\n",
                   by_time ? 1 : 0, ox, oy, pw, ph);
  s += fmt::format("<g clip-path='url(#clip{})'>\n", by_time ? 1 : 0);
  // The N^-1/2 slope through the geometric mean of the first points: error ~ C x^-1/2.
  double log_c = 0;
  int n_first = 0;
  for (const auto& se : series)
    if (!se.points.empty() && se.points.front().rms_error > 0 && xval(se.points.front()) > 0) {
      log_c += std::log10(se.points.front().rms_error) + 0.5 * std::log10(xval(se.points.front()));
      ++n_first;
    }
  if (n_first) {
    log_c /= n_first;
    const double xa = std::pow(10.0, lx0), xb = std::pow(10.0, lx1);
    s += fmt::format("<line x1='{:.1f}' y1='{:.1f}' x2='{:.1f}' y2='{:.1f}' stroke='#000' stroke-width='2' "
                     "stroke-opacity='0.35'/>\n", X(xa), Y(std::pow(10.0, log_c - 0.5 * lx0)), X(xb),
                     Y(std::pow(10.0, log_c - 0.5 * lx1)));
  }
  for (const auto& se : series) {
    std::string path;
    for (const auto& p : se.points) {
      if (!(p.rms_error > 0) || !(xval(p) > 0)) continue;
      path += fmt::format("{}{:.1f},{:.1f}", path.empty() ? "M" : " L", X(xval(p)), Y(p.rms_error));
    }
    if (path.empty()) continue;
    const char* col = kColours[colour.at(se.estimator) % 6];
    const char* da = kDashes[dash.at(se.method) % 8];
    s += fmt::format("<path d='{}' fill='none' stroke='{}' stroke-width='1.3' stroke-dasharray='{}'><title>{} / {}</title></path>\n",
                     path, col, da, escape_xml(se.estimator), escape_xml(se.method));
  }
  s += "</g>\n";
  return s;
}

}  // namespace

std::string sweep_svg(const std::vector<SweepSeries>& series, const std::string& title) {
  std::map<std::string, int> colour, dash;
  for (const auto& s : series) {
    colour.emplace(s.estimator, static_cast<int>(colour.size()));
    dash.emplace(s.method, static_cast<int>(dash.size()));
  }
  const double pw = 520, ph = 420, legend_h = 20.0 * static_cast<double>(std::max(colour.size(), dash.size()) + 2);
  const double W = 2 * pw + 20, H = ph + legend_h + 40;
  std::string s = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{:.0f}' height='{:.0f}' font-family='sans-serif'>\n"
      "<rect width='100%' height='100%' fill='white'/>\n"
      "<text x='10' y='18' font-size='14' font-weight='bold'>{}</text>\n",
      W, H, escape_xml(title));
  s += panel(0, 28, pw, ph, false, series, colour, dash);
  s += panel(pw + 20, 28, pw, ph, true, series, colour, dash);
  double y = ph + 48;
  s += fmt::format("<line x1='20' y1='{:.0f}' x2='50' y2='{:.0f}' stroke='#000' stroke-width='2' stroke-opacity='0.35'/>"
                   "<text x='56' y='{:.0f}' font-size='11'>slope -1/2 (error ~ N^-1/2)</text>\n", y, y, y + 4);
  y += 20;
  s += fmt::format("<text x='20' y='{:.0f}' font-size='11' font-weight='bold'>estimator (colour)</text>"
                   "<text x='300' y='{:.0f}' font-size='11' font-weight='bold'>method (dash)</text>\n", y, y);
  double ye = y + 18, ym = y + 18;
  for (const auto& [name, c] : colour) {
    s += fmt::format("<line x1='20' y1='{:.0f}' x2='50' y2='{:.0f}' stroke='{}' stroke-width='2'/>"
                     "<text x='56' y='{:.0f}' font-size='11'>{}</text>\n", ye, ye, kColours[c % 6], ye + 4, escape_xml(name));
    ye += 18;
  }
  for (const auto& [name, d] : dash) {
    s += fmt::format("<line x1='300' y1='{:.0f}' x2='340' y2='{:.0f}' stroke='#333' stroke-width='1.5' stroke-dasharray='{}'/>"
                     "<text x='346' y='{:.0f}' font-size='11'>{}</text>\n", ym, ym, kDashes[d % 8], ym + 4, escape_xml(name));
    ym += 18;
  }
  s += "</svg>\n";
  return s;
}

}  // namespace rayproof::report
