/// error_vs_time.svg: for each kind, class error rate and max t error against ns per case, one
/// point per method, log scales, the Pareto front drawn as a line through its points.
#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <map>

#include "report/html.h"
#include "report/method_style.h"
#include "report/report.h"
#include "report/report_text.h"

namespace rayproof::report {

std::vector<bool> pareto_front(const std::vector<double>& time, const std::vector<double>& err) {
  std::vector<bool> front(time.size(), true);
  for (std::size_t i = 0; i < time.size(); ++i)
    for (std::size_t j = 0; j < time.size(); ++j)
      if (i != j && time[j] <= time[i] && err[j] <= err[i] && (time[j] < time[i] || err[j] < err[i])) front[i] = false;
  return front;
}

namespace {

struct KindPoint {
  std::string method;
  double ns = 0, rate = 0, ulps = 0;
  std::uint64_t max_ulps = 0;
  std::size_t cases = 0, class_errors = 0;
  bool f32 = false;
  bool highlight = false;  ///< the kernel under test (rayproof check)
};

/// One log-log panel. Values of 0 sit on a "0" line below the decades.
std::string panel(double x0, double y0, double w, double h, const std::string& kind, const std::string& title,
                  const std::string& ylabel,
                  const std::vector<KindPoint>& pts, bool rate, const std::map<std::string, int>& colour) {
  std::string s;
  auto yval = [&](const KindPoint& p) { return rate ? p.rate * 100 : p.ulps; };
  double xmin = 1e300, xmax = 0, ymin = 1e300, ymax = 0;
  const double kNoT = 1e19;  // max ulps of a NaN or missing t: drawn in a band above the decades
  bool any_not = false;
  for (const auto& p : pts) {
    xmin = std::min(xmin, p.ns), xmax = std::max(xmax, p.ns);
    if (yval(p) >= kNoT) any_not = true;
    else if (yval(p) > 0) ymin = std::min(ymin, yval(p)), ymax = std::max(ymax, yval(p));
  }
  const double lx0 = std::floor(std::log10(std::max(xmin, 1e-3))), lx1 = std::ceil(std::log10(std::max(xmax, 1e-3)) + 1e-9);
  double ly0 = ymax > 0 ? std::floor(std::log10(ymin)) : 0, ly1 = ymax > 0 ? std::ceil(std::log10(ymax) + 1e-9) : 1;
  if (ly1 <= ly0) ly1 = ly0 + 1;
  const double zero_band = 28;  // pixels below the lowest decade for exact zeros
  const double top_band = any_not ? 24 : 0;
  const double pw = w - 90, ph = h - 60 - zero_band - top_band;
  const double ox = x0 + 60, oy = y0 + 25 + top_band;
  auto X = [&](double v) { return ox + (std::log10(std::max(v, 1e-3)) - lx0) / std::max(lx1 - lx0, 1.0) * pw; };
  auto Y = [&](double v) {
    if (v >= kNoT) return oy - top_band + 8;
    return v <= 0 ? oy + ph + zero_band - 6 : oy + ph - (std::log10(v) - ly0) / (ly1 - ly0) * ph;
  };
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='13' font-weight='bold'>{}</text>\n", ox, y0 + 14, escape_xml(title));
  s += fmt::format("<rect x='{:.0f}' y='{:.0f}' width='{:.0f}' height='{:.0f}' fill='none' stroke='#888'/>\n", ox,
                   oy - top_band, pw, ph + zero_band + top_band);
  if (any_not)
    s += fmt::format("<text x='{:.0f}' y='{:.1f}' font-size='10' text-anchor='end'>NaN t</text>"
                     "<line x1='{:.0f}' y1='{:.1f}' x2='{:.0f}' y2='{:.1f}' stroke='#bbb' stroke-dasharray='3,3'/>\n",
                     ox - 4, Y(kNoT) + 3, ox, oy - 2, ox + pw, oy - 2);
  for (double e = lx0; e <= lx1 + 1e-9; ++e) {
    const double x = X(std::pow(10.0, e));
    s += fmt::format("<line x1='{:.1f}' y1='{:.0f}' x2='{:.1f}' y2='{:.0f}' stroke='#ddd'/>", x, oy, x, oy + ph + zero_band);
    s += fmt::format("<text x='{:.1f}' y='{:.0f}' font-size='10' text-anchor='middle'>{:g}</text>\n", x,
                     oy + ph + zero_band + 12, std::pow(10.0, e));
  }
  for (double e = ly0; e <= ly1 + 1e-9; ++e) {
    const double y = Y(std::pow(10.0, e));
    s += fmt::format("<line x1='{:.0f}' y1='{:.1f}' x2='{:.0f}' y2='{:.1f}' stroke='#ddd'/>", ox, y, ox + pw, y);
    s += fmt::format("<text x='{:.0f}' y='{:.1f}' font-size='10' text-anchor='end'>{:g}{}</text>\n", ox - 4, y + 3,
                     std::pow(10.0, e), rate ? "%" : "");
  }
  s += fmt::format("<line x1='{:.0f}' y1='{:.1f}' x2='{:.0f}' y2='{:.1f}' stroke='#bbb' stroke-dasharray='3,3'/>", ox,
                   oy + ph + 4, ox + pw, oy + ph + 4);
  s += fmt::format("<text x='{:.0f}' y='{:.1f}' font-size='10' text-anchor='end'>0</text>\n", ox - 4, Y(0) + 3);
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='11' text-anchor='middle'>ns per case (log)</text>\n",
                   ox + pw / 2, oy + ph + zero_band + 26);
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='11' text-anchor='middle' transform='rotate(-90 {:.0f} {:.0f})'>{}</text>\n",
                   x0 + 14, oy + ph / 2, x0 + 14, oy + ph / 2, escape_xml(ylabel));
  // Pareto front: sorted by time, a staircase through the non-dominated points.
  std::vector<double> t, e;
  for (const auto& p : pts) t.push_back(p.ns), e.push_back(yval(p));
  const auto front = pareto_front(t, e);
  std::vector<const KindPoint*> fp;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (front[i]) fp.push_back(&pts[i]);
  std::sort(fp.begin(), fp.end(), [](auto* a, auto* b) { return a->ns < b->ns; });
  if (fp.size() > 1) {
    std::string path;
    for (std::size_t i = 0; i < fp.size(); ++i) {
      const double x = X(fp[i]->ns), y = Y(yval(*fp[i]));
      if (i == 0) path += fmt::format("M{:.1f},{:.1f}", x, y);
      else path += fmt::format(" H{:.1f} V{:.1f}", x, y);
    }
    s += fmt::format("<path d='{}' fill='none' stroke='#444' stroke-width='1.5' stroke-dasharray='5,3'/>\n", path);
  }
  std::vector<std::pair<double, double>> placed;  // label anchors already used
  auto free_spot = [&](double x, double y) {
    for (double dy : {-6.0, 12.0, -18.0, 24.0, -30.0, 36.0, -42.0, 48.0}) {
      const double ly = y + dy;
      bool clash = false;
      for (const auto& [px, py] : placed)
        if (std::fabs(py - ly) < 11 && std::fabs(px - x) < 70) clash = true;
      if (!clash) return ly;
    }
    return y - 6;
  };
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const auto& p = pts[i];
    const double x = X(p.ns), y = Y(yval(p));
    const MethodStyle st = method_style(std::size_t(colour.at(p.method)));
    // One group per method and panel: its numbers in a <title> (shown on hover by any viewer, and by
    // report.html's tooltip), its marker, ring and label.
    s += fmt::format("<g class='point' data-method='{}' data-kind='{}' data-pareto='{}'><title>{}</title>", escape_xml(p.method),
                     escape_xml(kind), front[i] ? "yes" : "no",
                     escape_xml(fmt::format("{} on {} ({}): {:.1f} ns/case; class errors {} of {} ({:.4f}%); max t error {}{}",
                                        p.method, kind, p.f32 ? "float" : "double", p.ns, p.class_errors, p.cases,
                                        100 * p.rate, ulp_text(p.max_ulps, p.f32 ? Precision::float32 : Precision::float64),
                                        front[i] ? "; on the Pareto front" : "")));
    if (front[i]) s += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='9' fill='none' stroke='#000' stroke-width='1.5'/>", x, y);
    s += marker_svg(st.marker, x, y, 5, st.colour, p.f32);
    const double ly = free_spot(x + 10, y);
    placed.emplace_back(x + 10, ly);
    if (p.highlight)
      s += fmt::format("<circle cx='{:.1f}' cy='{:.1f}' r='12' fill='none' stroke='{}' stroke-width='2'/>", x, y, st.colour);
    s += fmt::format("<text x='{:.1f}' y='{:.1f}' font-size='10' fill='{}'{}>{}</text></g>\n", x + 10, ly, st.colour,
                     p.highlight ? " font-weight='bold'" : "", escape_xml(p.highlight ? p.method + " (checked)" : p.method));
  }
  return s;
}

}  // namespace

std::string to_svg(const Report& r) {
  std::map<std::string, int> colour;
  for (const auto& p : r.points) colour.emplace(p.method, static_cast<int>(colour.size()));
  std::vector<io::Kind> kinds;
  for (io::Kind k : io::kCaseKinds)
    if (std::any_of(r.rows.begin(), r.rows.end(), [&](const Row& row) { return row.kind == k; })) kinds.push_back(k);
  const double pw = 540, ph = 300;
  const double W = 2 * pw + 20;
  // The legend first: it takes as many rows as the methods need, and the panels start below it.
  std::string legend;
  double lx = 20, ly = 80;
  for (const auto& p : r.points) {
    const MethodStyle st = method_style(std::size_t(colour.at(p.method)));
    const double w = 22 + 6.5 * double(p.method.size());
    if (lx + w > W - 10) lx = 20, ly += 18;
    legend += marker_svg(st.marker, lx + 5, ly, 5, st.colour, p.precision == Precision::float32);
    legend += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='11'>{}</text>", lx + 13, ly + 4, escape_xml(p.method));
    lx += w;
  }
  const double top = ly + 15;
  const double H = top + ph * double(kinds.size()) + 20;
  std::string s = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{:.0f}' height='{:.0f}' font-family='sans-serif' "
      "class='error-vs-time'>\n<rect width='100%' height='100%' fill='white'/>\n",
      W, H);
  s += fmt::format("<text x='20' y='26' font-size='17' font-weight='bold'>{}</text>\n", escape_xml(r.title));
  s += "<text x='20' y='46' font-size='12'>Each point is one method on every case of that kind (all families); "
       "down and left is better. Hollow markers: float methods (float inputs, float ulps); filled: double or exact.</text>\n";
  s += "<text x='20' y='62' font-size='12'>Ringed points, joined by the dashed line, form the Pareto front. "
       "Zero sits on the dashed line below the lowest decade; a NaN or missing t above the highest.</text>\n";
  s += legend;
  s += "\n";
  for (std::size_t i = 0; i < kinds.size(); ++i) {
    std::map<std::string, KindPoint> agg;
    std::map<std::string, verify::Stats> st;
    for (const auto& row : r.rows) {
      if (row.kind != kinds[i]) continue;
      auto& p = agg[row.method];
      p.method = row.method;
      p.f32 = row.precision == Precision::float32;
      p.highlight = row.method == r.highlight;
      p.ns += row.ns_per_case * double(row.stats.cases);
      st[row.method].merge(row.stats);
    }
    std::vector<KindPoint> pts;
    for (auto& [m, p] : agg) {
      const auto& s2 = st[m];
      p.ns /= double(std::max<std::size_t>(s2.cases, 1));
      p.rate = s2.class_error_rate();
      const auto mx = s2.ulp_quantile(1.0);
      p.ulps = mx == std::numeric_limits<std::uint64_t>::max() ? 1e19 : double(mx);
      p.max_ulps = mx;
      p.cases = s2.cases;
      p.class_errors = s2.class_errors();
      pts.push_back(p);
    }
    const std::string k(io::to_string(kinds[i]));
    const double y = top + ph * double(i);
    s += panel(0, y, pw, ph, k, k + ": class error rate", "class errors (% of cases)", pts, true, colour);
    s += panel(pw + 20, y, pw, ph, k, k + ": max t error", "max t error (ulps)", pts, false, colour);
  }
  s += "</svg>\n";
  return s;
}

}  // namespace rayproof::report
