// report.html, read by a real browser (Debian's chromium, headless) after its scripts ran:
// the chart with one point per method and kind, hover numbers equal to report.md's, the tables,
// the stability chart, a copy button per reproducer; and every method drawn in its own style.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <regex>
#include <set>

#include "registry/registry.h"
#include "cli_support.h"
#include "report/html.h"
#include "report/method_style.h"

using rayproof::testing::run_rayproof;
using rayproof::testing::scratch_dir;
using rayproof::testing::slurp;

namespace {

std::string chromium() {
  for (const char* p : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (std::filesystem::exists(p)) return p;
  return "";
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (auto at = s.find(what); at != std::string::npos; at = s.find(what, at + what.size())) ++n;
  return n;
}

/// Runs headless chromium on a file:// page; "" when it failed (the message in `err`).
std::string browser(const std::string& args, const std::filesystem::path& page, std::string& err) {
  const auto out = scratch_dir() / "chromium.out", log = scratch_dir() / "chromium.err";
  const std::string cmd = "timeout 60 " + chromium() + " --headless --no-sandbox --disable-gpu --hide-scrollbars " + args +
                          " file://" + page.string() + " >" + out.string() + " 2>" + log.string();
  const int rc = std::system(cmd.c_str());
  if (rc != 0) err = "chromium exit " + std::to_string(rc) + ": " + slurp(log);
  return slurp(out);
}

double rgb_distance(const char* a, const char* b) {
  auto ch = [](const char* h, int i) { return std::stoi(std::string(h + 1 + 2 * i, 2), nullptr, 16); };
  double d = 0;
  for (int i = 0; i < 3; ++i) d += std::pow(ch(a, i) - ch(b, i), 2);
  return std::sqrt(d);
}

}  // namespace

TEST(MethodStyle, NoTwoMethodsOfTheDefaultReportShareColourAndMarker) {
  const auto methods = rayproof::registry::select_methods("report", {}, true);
  ASSERT_TRUE(methods);
  ASSERT_GE(methods->size(), 10u);
  std::set<std::pair<std::string, int>> seen;
  std::set<std::string> colours;
  for (std::size_t i = 0; i < methods->size(); ++i) {
    const auto st = rayproof::report::method_style(i);
    EXPECT_TRUE(seen.insert({st.colour, int(st.marker)}).second) << (*methods)[i]->name << " repeats a style";
    colours.insert(st.colour);
  }
  // The first ten differ in colour alone, and every two colours of the palette are far apart in RGB
  // (two browns of an earlier palette were 17 apart); the 70 first indices never repeat colour + marker.
  EXPECT_EQ(colours.size(), std::min<std::size_t>(methods->size(), rayproof::report::kColourCount));
  for (std::size_t i = 0; i < rayproof::report::kColourCount; ++i)
    for (std::size_t j = i + 1; j < rayproof::report::kColourCount; ++j)
      EXPECT_GT(rgb_distance(rayproof::report::method_style(i).colour, rayproof::report::method_style(j).colour), 70)
          << i << " " << j;
  // Two methods of one colour (the 11th and 12th reuse the first two colours) are far apart in
  // marker too: not the same one, and not the default report's `exact` beside `certified` again.
  for (std::size_t i = 0; i < methods->size(); ++i)
    for (std::size_t j = i + 1; j < methods->size(); ++j) {
      const auto a = rayproof::report::method_style(i), b = rayproof::report::method_style(j);
      if (a.marker == b.marker) {
        EXPECT_GT(rgb_distance(a.colour, b.colour), 70) << (*methods)[i]->name << " and " << (*methods)[j]->name;
      }
    }
  std::set<std::pair<std::string, int>> all;
  for (std::size_t i = 0; i < 70; ++i) {
    const auto st = rayproof::report::method_style(i);
    EXPECT_TRUE(all.insert({st.colour, int(st.marker)}).second) << i;
  }
}

TEST(ReportHtml, RendersTheMarkdownAndInlinesItsCharts) {
  const std::string md = "# t\n\n| a | b |\n|---|---:|\n| x | 1.5 |\n\n![chart](c.svg)\n\n```\ntriangle 0 0 0\n```\n";
  const std::string html = rayproof::report::markdown_to_html(md, [](const std::string& f) {
    return f == "c.svg" ? std::string("<svg class='c'><g class='point'><title>n</title></g></svg>") : std::string();
  });
  EXPECT_NE(html.find("<td align=\"right\">1.5</td>"), std::string::npos) << html;
  EXPECT_NE(html.find("<svg class='c'>"), std::string::npos);
  EXPECT_EQ(html.find("<img"), std::string::npos);
  EXPECT_NE(html.find("<pre><code>triangle 0 0 0\n</code></pre>"), std::string::npos);
  // A missing image stays a link rather than vanishing.
  const std::string kept = rayproof::report::markdown_to_html("![x](gone.svg)\n", [](const std::string&) { return ""; });
  EXPECT_NE(kept.find("<img src=\"gone.svg\""), std::string::npos);
}

TEST(ReportHtml, ChromiumShowsTheChartTablesStabilityAndCopyButtons) {
  if (chromium().empty()) GTEST_SKIP() << "chromium is not installed (Debian: apt-get install chromium): report.html not tested in a browser";
  const auto dir = scratch_dir() / "report_html";
  std::filesystem::remove_all(dir);
  const std::vector<std::string> methods = {"float", "double", "robust", "certified"};
  const auto r = run_rayproof("report --count 40 --seed 3 --families tri_edge,tri_vertex,sph_tangent_exact,box_graze "
                              "--methods float,double,robust,certified --stability-count 4 --irradiance-samples 0 --out " +
                              dir.string());
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string md = slurp(dir / "report.md"), html = slurp(dir / "report.html");
  ASSERT_FALSE(html.empty());
  // Self-contained: nothing to fetch (xmlns is a name, not a request).
  for (const char* net : {"src=\"http", "href=\"http", "src='http", "<link", "@import", "url("})
    EXPECT_EQ(html.find(net), std::string::npos) << net;

  std::string err;
  const std::string dom = browser("--dump-dom", dir / "report.html", err);
  ASSERT_TRUE(err.empty()) << err;
  ASSERT_NE(dom.find("</html>"), std::string::npos) << dom.substr(0, 400);
  // The chart: per kind, two panels, one point per method in each, with the numbers of report.md.
  EXPECT_NE(dom.find("class=\"error-vs-time\""), std::string::npos);
  const std::regex point("<g class=\"point\" data-method=\"([^\"]+)\" data-kind=\"([^\"]+)\"[^>]*><title>([^<]*)</title>");
  std::map<std::pair<std::string, std::string>, int> points;
  for (auto it = std::sregex_iterator(dom.begin(), dom.end(), point); it != std::sregex_iterator(); ++it) {
    const std::string m = (*it)[1], k = (*it)[2], title = (*it)[3];
    ++points[{m, k}];
    // The hover text's ns/case is the kind table's cell for that method, to the digit.
    const std::smatch ns = [&] { std::smatch x; std::regex_search(title, x, std::regex(": ([0-9.]+) ns/case")); return x; }();
    ASSERT_FALSE(ns.empty()) << title;
    const auto section = md.find("\n## " + k + "\n");
    ASSERT_NE(section, std::string::npos) << k;
    EXPECT_NE(md.find("| " + m + " | " + ns[1].str() + " |", section), std::string::npos) << title;
  }
  for (const char* k : {"triangle", "sphere", "box"})
    for (const auto& m : methods) EXPECT_EQ((points[{m, k}]), 2) << m << " on " << k;
  EXPECT_EQ(points.size(), 3 * methods.size());
  // The tables: summary, promises-free kind tables and per-family tables, the stability breaks.
  EXPECT_GE(count(dom, "<table"), 1u + 2 * 3 + 1);
  EXPECT_NE(dom.find("<th>method</th>"), std::string::npos);
  EXPECT_NE(dom.find("class=\"stability\""), std::string::npos);
  // One copy button per reproducer line (the scripts ran: the buttons are made by them).
  std::size_t repro = 0;
  const auto at = md.find("## Reproducers");
  ASSERT_NE(at, std::string::npos);
  const auto fence = md.find("\n```\n", at);  // the block opens; its lines run to the closing fence
  ASSERT_NE(fence, std::string::npos);
  for (auto p = fence + 4; p != std::string::npos && md.compare(p + 1, 3, "```") != 0; p = md.find('\n', p + 1))
    if (std::regex_search(md.substr(p + 1, 12), std::regex("^(triangle|sphere|box) "))) ++repro;
  EXPECT_GT(repro, 0u);
  EXPECT_GE(count(dom, "class=\"copy\""), repro);
  EXPECT_EQ(dom.find("<pre>"), std::string::npos);  // every code block became copyable lines

  // A screenshot, showing one point's numbers, for docs/report_html.png (docs/report_html.md: how it is made).
  const auto png = std::filesystem::path(RAYPROOF_BUILD_DIR) / "report_html.png";
  std::filesystem::remove(png);
  browser("--screenshot=" + png.string() + " --window-size=1200,900", dir / "report.html#show=robust", err);
  EXPECT_TRUE(err.empty()) << err;
  EXPECT_TRUE(std::filesystem::exists(png) && std::filesystem::file_size(png) > 10000);
}

TEST(ReportHtml, CheckOutWritesReportHtmlWithTheKernelsReproducers) {
  const auto dir = scratch_dir() / "check_html";
  std::filesystem::remove_all(dir);
  const auto r = run_rayproof("check --exec 'mt=python3 " + std::string(RAYPROOF_SOURCE_DIR) +
                              "/examples/python/moller_trumbore.py' --families tri_edge --count 20 --compare float,robust "
                              "--out " + dir.string());
  ASSERT_LE(r.status, 1) << r.err;
  const std::string md = slurp(dir / "report.md"), html = slurp(dir / "report.html");
  ASSERT_NE(md.find("## Reproducers"), std::string::npos) << md;
  EXPECT_NE(html.find("The worst cases of mt per family"), std::string::npos);
  EXPECT_NE(html.find("data-method='mt'"), std::string::npos);  // the kernel's points in the chart
}
