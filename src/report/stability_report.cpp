/// The report's stability part (stability_report.h).
#include "report/stability_report.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "report/html.h"
#include "report/method_style.h"
#include "report/report.h"
#include "report/stability_text.h"

namespace rayproof::report {

namespace {

constexpr std::uint64_t kNoT = std::numeric_limits<std::uint64_t>::max();

/// One panel: x is the knob's exponent (stiffer to the right), y either the class error rate
/// (log, 0.1% .. 100%, zero on a band below) or the t error in ulps (log2, 2^0 .. 2^64, zero on
/// the band, a t missing on one side or NaN above the top).
std::string panel(double x0, double y0, double w, double h, const gen::Knob& k, bool rate,
                  const std::vector<const verify::StabilityCurve*>& curves, const std::map<std::string, int>& colour) {
  const double ox = x0 + 58, oy = y0 + 24, pw = w - 76, ph = h - 64, band = 10;
  const int e0 = k.exponents.front(), e1 = k.exponents.back();
  auto X = [&](int e) { return ox + (e1 == e0 ? 0.0 : double(e - e0) / double(e1 - e0) * pw); };
  // y in [0, 1] from the bottom of the plot area.
  auto Y = [&](double f) { return oy + ph - f * ph; };
  auto rate_f = [](double r) { return (std::log10(r * 100) + 1) / 3; };  // 0.1% .. 100%
  auto ulp_f = [](std::uint64_t u) { return std::log2(double(u)) / 64; };
  std::string s;
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='13' font-weight='bold'>{}: {}</text>\n", ox, y0 + 14, escape_xml(k.name),
                   rate ? "class error rate" : "t error (median solid, max dashed)");
  s += fmt::format("<rect x='{:.0f}' y='{:.0f}' width='{:.0f}' height='{:.0f}' fill='none' stroke='#888'/>\n", ox, oy, pw, ph);
  // x ticks: about eight labels, none closer than 44 px to the previous one (the magnitude knobs'
  // steps are denser near 2^0 than far out).
  const std::size_t every = std::max<std::size_t>(1, (k.exponents.size() + 7) / 8);
  double last_x = -1e9;
  for (std::size_t i = 0; i < k.exponents.size(); i += every) {
    const double x = X(k.exponents[i]);
    if (x - last_x < 44) continue;
    last_x = x;
    s += fmt::format("<line x1='{:.1f}' y1='{:.0f}' x2='{:.1f}' y2='{:.0f}' stroke='#ddd'/>", x, oy, x, oy + ph);
    s += fmt::format("<text x='{:.1f}' y='{:.0f}' font-size='10' text-anchor='middle'>2^{}</text>\n", x,
                     oy + ph + band + 12, k.exponents[i]);
  }
  if (rate) {
    for (int d = 0; d <= 3; ++d) {
      const double y = Y(d / 3.0);
      s += fmt::format("<line x1='{:.0f}' y1='{:.1f}' x2='{:.0f}' y2='{:.1f}' stroke='#ddd'/>", ox, y, ox + pw, y);
      s += fmt::format("<text x='{:.0f}' y='{:.1f}' font-size='10' text-anchor='end'>{:g}%</text>\n", ox - 4, y + 3,
                       std::pow(10.0, d - 1));
    }
  } else {
    for (int d = 0; d <= 64; d += 16) {
      const double y = Y(d / 64.0);
      s += fmt::format("<line x1='{:.0f}' y1='{:.1f}' x2='{:.0f}' y2='{:.1f}' stroke='#ddd'/>", ox, y, ox + pw, y);
      s += fmt::format("<text x='{:.0f}' y='{:.1f}' font-size='10' text-anchor='end'>2^{}</text>\n", ox - 4, y + 3, d);
    }
  }
  s += fmt::format("<text x='{:.0f}' y='{:.1f}' font-size='10' text-anchor='end'>0</text>\n", ox - 4, oy + ph + band / 2 + 3);
  s += fmt::format("<text x='{:.0f}' y='{:.0f}' font-size='11' text-anchor='middle'>{} = 2^k</text>\n", ox + pw / 2,
                   oy + ph + band + 26, escape_xml(k.quantity));
  auto point = [&](double f, bool zero) { return zero ? oy + ph + band / 2 : Y(std::clamp(f, 0.0, 1.02)); };
  for (const auto* c : curves) {
    const MethodStyle style = method_style(std::size_t(colour.at(c->method)));
    const char* col = style.colour;
    // `marked`: the method's marker on each drawn vertex, so that two curves of near colours differ.
    auto polyline = [&](auto&& value, const char* dash, bool marked) {
      std::vector<std::pair<double, double>> xy;
      for (const auto& st : c->steps) {
        if (st.stats.cases == 0) continue;
        const auto [f, zero] = value(st.stats);
        xy.emplace_back(std::round(X(st.exponent)), std::round(point(f, zero)));
      }
      // A point between two at the same height adds nothing to the line: left out (keeps the file small).
      std::string pts;
      for (std::size_t i = 0; i < xy.size(); ++i)
        if (i == 0 || i + 1 == xy.size() || xy[i - 1].second != xy[i].second || xy[i + 1].second != xy[i].second)
          pts += fmt::format("{:.0f},{:.0f} ", xy[i].first, xy[i].second);
      if (!pts.empty())
        s += fmt::format("<polyline points='{}' fill='none' stroke='{}' stroke-width='1.6' stroke-opacity='0.85'{}/>\n",
                         pts, col, dash);
      if (marked)
        for (std::size_t i = 0; i < xy.size(); ++i)
          if (i == 0 || i + 1 == xy.size() || xy[i - 1].second != xy[i].second || xy[i + 1].second != xy[i].second)
            s += marker_svg(style.marker, xy[i].first, xy[i].second, 3, col, false);
    };
    if (rate) {
      polyline([&](const verify::Stats& st) {
        const double r = st.class_error_rate();
        return std::pair<double, bool>{r > 0 ? std::max(rate_f(r), 0.0) : 0.0, r == 0};
      }, "", true);
    } else {
      auto ulps = [&](std::uint64_t u) {
        if (u == kNoT) return std::pair<double, bool>{1.02, false};
        return std::pair<double, bool>{u ? ulp_f(u) : 0.0, u == 0};
      };
      polyline([&](const verify::Stats& st) { return ulps(st.ulp_quantile(0.5)); }, "", true);
      polyline([&](const verify::Stats& st) { return ulps(st.ulp_quantile(1.0)); }, " stroke-dasharray='5,3'", false);
    }
  }
  return s;
}

}  // namespace

std::string stability_svg(const verify::StabilityRun& run) {
  std::map<std::string, int> colour;
  for (const auto& c : run.curves) colour.emplace(c.method, static_cast<int>(colour.size()));
  const double pw = 560, ph = 250, top = 92;
  const double W = 2 * pw + 20, H = top + ph * double(run.knobs.size()) + 10;
  std::string s = fmt::format(
      "<svg xmlns='http://www.w3.org/2000/svg' width='{:.0f}' height='{:.0f}' font-family='sans-serif' class='stability'>\n"
      "<rect width='100%' height='100%' fill='white'/>\n",
      W, H);
  s += "<text x='20' y='26' font-size='17' font-weight='bold'>rayproof: stability along each stiffness knob</text>\n";
  s += fmt::format("<text x='20' y='46' font-size='12'>{} cases per step (seed {}), every method against exact; stiffer "
                   "to the right. Left: class error rate; right: t error in ulps of the method's precision.</text>\n",
                   run.count, run.seed);
  s += "<text x='20' y='62' font-size='12'>Zero sits on the band below each plot; a t missing on one side or NaN "
       "is drawn above the top.</text>\n";
  double lx = 20;
  std::vector<std::string> order;
  for (const auto& c : run.curves)
    if (std::find(order.begin(), order.end(), c.method) == order.end()) order.push_back(c.method);
  for (const auto& m : order) {
    const MethodStyle style = method_style(std::size_t(colour.at(m)));
    s += fmt::format("<line x1='{:.0f}' y1='80' x2='{:.0f}' y2='80' stroke='{}' stroke-width='3'/>", lx, lx + 14, style.colour);
    s += marker_svg(style.marker, lx + 7, 80, 3.5, style.colour, false);
    s += fmt::format("<text x='{:.0f}' y='84' font-size='11'>{}</text>", lx + 18, escape_xml(m));
    lx += 26 + 6.5 * double(m.size());
  }
  s += "\n";
  for (std::size_t i = 0; i < run.knobs.size(); ++i) {
    const gen::Knob* k = gen::find_knob(run.knobs[i]);
    if (!k || k->exponents.empty()) continue;
    std::vector<const verify::StabilityCurve*> curves;
    for (const auto& c : run.curves)
      if (c.knob == k->name) curves.push_back(&c);
    const double y = top + ph * double(i);
    s += panel(0, y, pw, ph, *k, true, curves, colour);
    s += panel(pw + 20, y, pw, ph, *k, false, curves, colour);
  }
  s += "</svg>\n";
  return s;
}

std::string stability_markdown(const verify::StabilityRun& run) {
  std::string s = "## Stability: where each method breaks\n\n";
  s += fmt::format(
      "Each stiffness knob (docs/stability.md) is swept in powers of two, {} cases per step (seed {}), every method "
      "judged against exact as in the rest of the report. *class errors > 0.1% from*: the first step (in sweep order) whose class error "
      "rate is above 0.1%; *median t error > 1 ulp from*: the first whose median t error, over class-correct cases, "
      "is above 1 ulp; \"never\": no step in the swept range. *Predicted*: where the first class errors should "
      "appear by the derivation given below (only where there is one); *measured*: whether the break falls there. "
      "Numbers per step: stability.csv.\n\n",
      run.count, run.seed);
  s += "![stability along each knob](stability.svg)\n\n";
  s += breaks_table(run);
  const auto ps = prediction_sentences(run);
  if (!ps.empty()) {
    s += "\n";
    for (const auto& x : ps) s += "- " + x + "\n";
  }
  return s;
}

std::string stability_csv(const verify::StabilityRun& run) {
  std::string s = "knob,method,precision,exponent,cases,class_errors,false_hit,false_miss,wrong_hit_class,wrong_class,"
                  "ulp_median,ulp_max\n";
  for (const auto& c : run.curves)
    for (const auto& t : c.steps) {
      const auto& st = t.stats;
      s += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}\n", c.knob, c.method,
                       c.precision == Precision::float32 ? "float" : "double", t.exponent, st.cases, st.class_errors(),
                       st.false_hit, st.false_miss, st.wrong_hit_class, st.wrong_class, st.ulp_quantile(0.5),
                       st.ulp_quantile(1.0));
    }
  return s;
}

std::string write_stability(const verify::StabilityRun& run, const std::string& dir) {
  const std::pair<const char*, std::string> files[] = {{"stability.md", "# rayproof: stability\n\n" + stability_markdown(run)},
                                                       {"stability.csv", stability_csv(run)},
                                                       {"stability.svg", stability_svg(run)}};
  return write_files(dir, files);
}

}  // namespace rayproof::report
