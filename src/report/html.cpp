#include "report/html.h"

#include <cmark-gfm-core-extensions.h>
#include <cmark-gfm.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <mutex>
#include <sstream>

#include "report/report.h"

namespace rayproof::report {

namespace {

std::string read_file(const std::filesystem::path& p, bool* ok = nullptr) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  if (ok) *ok = bool(in);
  return s.str();
}

/// cmark-gfm: CommonMark plus GitHub's tables (the report's tables are GFM pipe tables).
std::string render_gfm(const std::string& md) {
  static std::once_flag once;
  std::call_once(once, [] { cmark_gfm_core_extensions_ensure_registered(); });
  const int options = CMARK_OPT_DEFAULT;
  std::unique_ptr<cmark_parser, decltype(&cmark_parser_free)> parser(cmark_parser_new(options), cmark_parser_free);
  if (cmark_syntax_extension* table = cmark_find_syntax_extension("table"))
    cmark_parser_attach_syntax_extension(parser.get(), table);
  cmark_parser_feed(parser.get(), md.data(), md.size());
  std::unique_ptr<cmark_node, decltype(&cmark_node_free)> doc(cmark_parser_finish(parser.get()), cmark_node_free);
  char* html = cmark_render_html(doc.get(), options, cmark_parser_get_syntax_extensions(parser.get()));
  std::string out = html ? html : "";
  std::free(html);
  return out;
}

std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = name + "=\"";
  const auto a = tag.find(key);
  if (a == std::string::npos) return "";
  const auto b = tag.find('"', a + key.size());
  return b == std::string::npos ? "" : tag.substr(a + key.size(), b - a - key.size());
}

/// Every <img src="X.svg" alt="..." /> whose file `image` gives becomes a figure holding the SVG.
std::string inline_images(const std::string& html, const std::function<std::string(const std::string&)>& image) {
  std::string out;
  std::size_t at = 0;
  for (;;) {
    const auto a = html.find("<img ", at);
    if (a == std::string::npos) break;
    const auto b = html.find('>', a);
    if (b == std::string::npos) break;
    const std::string tag = html.substr(a, b + 1 - a);
    const std::string src = attribute(tag, "src");
    std::string svg = src.find('/') == std::string::npos ? image(src) : "";
    if (const auto x = svg.find("<?xml"); x == 0) svg = svg.substr(svg.find("?>") + 2);
    out += html.substr(at, a - at);
    if (svg.empty()) out += tag;
    else out += "<figure class=\"chart\" data-file=\"" + src + "\">" + svg + "<figcaption>" + attribute(tag, "alt") +
                " (" + src + ")</figcaption></figure>";  // src and alt come escaped from cmark
    at = b + 1;
  }
  return out + html.substr(at);
}

constexpr const char* kStyle = R"(
body{font-family:system-ui,sans-serif;margin:1.5em auto;max-width:1180px;padding:0 1em;color:#222;line-height:1.45}
h1{font-size:1.6em}h2{margin-top:1.8em;border-bottom:1px solid #ddd}
table{border-collapse:collapse;margin:.6em 0;font-size:.86em;display:block;overflow-x:auto;max-width:100%}
th,td{border:1px solid #ccc;padding:.2em .5em;white-space:nowrap}th{background:#f2f2f2}tr:nth-child(even) td{background:#fafafa}
code{font-family:ui-monospace,monospace;font-size:.9em;background:#f4f4f4;padding:0 .2em;overflow-wrap:anywhere}
pre{background:#f7f7f7;padding:.5em;overflow-x:auto}
figure.chart{margin:1em 0}figure.chart svg{max-width:100%;height:auto}figcaption{color:#666;font-size:.85em}
g.point{cursor:pointer}g.point:hover text{font-weight:bold}
.repro{display:flex;gap:.5em;align-items:baseline;margin:.15em 0}.repro code{white-space:pre-wrap;word-break:break-all}
button.copy{font-size:.78em;padding:.05em .5em;cursor:pointer;flex:none}
#tip{position:fixed;display:none;background:#222;color:#fff;padding:.35em .6em;border-radius:4px;font-size:.85em;
pointer-events:none;max-width:420px;z-index:9}
.source{color:#666;font-size:.85em}
)";

// Tooltips on the charts' points (their <title> holds the numbers); a copy button per reproducer:
// each line of a code block, and each inline case line (it starts with a primitive kind).
constexpr const char* kScript = R"(
(function(){
const tip=document.getElementById('tip');
document.querySelectorAll('g.point').forEach(function(g){
  const t=g.querySelector('title'); if(!t) return; g.dataset.tip=t.textContent;
  g.addEventListener('mousemove',function(e){tip.textContent=g.dataset.tip;tip.style.display='block';
    tip.style.left=(e.clientX+14)+'px';tip.style.top=(e.clientY+14)+'px';});
  g.addEventListener('mouseleave',function(){tip.style.display='none';});
});
function copy(text,b){
  function done(){b.textContent='copied';setTimeout(function(){b.textContent='copy';},1200);}
  function fallback(){const a=document.createElement('textarea');a.value=text;document.body.appendChild(a);a.select();
    try{document.execCommand('copy');}catch(e){}a.remove();done();}
  if(navigator.clipboard&&window.isSecureContext) navigator.clipboard.writeText(text).then(done,fallback); else fallback();
}
function button(text){const b=document.createElement('button');b.className='copy';b.textContent='copy';
  b.title='copy this line';b.dataset.copy=text;b.addEventListener('click',function(){copy(text,b);});return b;}
const kinds=/^(plane|sphere|ellipsoid|triangle|box|disk) /;
document.querySelectorAll('pre > code').forEach(function(c){
  const pre=c.parentNode, box=document.createElement('div'); box.className='reproducers';
  c.textContent.split('\n').forEach(function(line){ if(!line.trim()) return;
    const row=document.createElement('div'); row.className='repro'; const code=document.createElement('code');
    code.textContent=line; if(kinds.test(line)) row.appendChild(button(line)); row.appendChild(code); box.appendChild(row);});
  pre.replaceWith(box);
});
document.querySelectorAll('li code, p code, td code').forEach(function(c){
  if(kinds.test(c.textContent)&&c.textContent.split(' ').length>4) c.after(' ',button(c.textContent));
});
// #show=METHOD: the chart first on the page, that method's first point's numbers shown (for screenshots).
const show=location.hash.match(/^#show=(.+)$/);
if(show){const g=document.querySelector('g.point[data-method="'+decodeURIComponent(show[1])+'"]');
  if(g){document.body.prepend(g.closest('figure'));const b=g.getBoundingClientRect();tip.textContent=g.dataset.tip;
    tip.style.display='block';tip.style.left=(b.right+8)+'px';tip.style.top=(b.bottom+8)+'px';}}
})();
)";

}  // namespace

std::string escape_xml(const std::string& s) {
  std::string o;
  for (char c : s) switch (c) {
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '&': o += "&amp;"; break;
      case '\'': o += "&#39;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  return o;
}

std::string markdown_to_html(const std::string& markdown, const std::function<std::string(const std::string&)>& image) {
  std::string title = "rayproof report";
  if (markdown.rfind("# ", 0) == 0) title = markdown.substr(2, markdown.find('\n') - 2);
  std::string s = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<meta name=\"viewport\" "
                  "content=\"width=device-width\">\n<title>" + escape_xml(title) + "</title>\n<style>" + kStyle +
                  "</style></head>\n<body>\n";
  s += inline_images(render_gfm(markdown), image);
  s += "<p class=\"source\">This page is report.md rendered, with its charts inlined: the same numbers. "
       "Hover a chart's point for its numbers; each reproducer line has a copy button.</p>\n";
  s += "<div id=\"tip\"></div>\n<script>" + std::string(kScript) + "</script>\n</body></html>\n";
  return s;
}

std::string write_html(const std::string& dir, const std::string& md_name, const std::string& html_name) {
  namespace fs = std::filesystem;
  bool ok = false;
  const std::string md = read_file(fs::path(dir) / md_name, &ok);
  if (!ok) return (fs::path(dir) / md_name).string() + ": cannot read";
  const std::string html = markdown_to_html(md, [&](const std::string& name) -> std::string {
    const fs::path p = fs::path(dir) / name;
    if (p.extension() != ".svg" || !fs::is_regular_file(p)) return "";
    return read_file(p);
  });
  const std::pair<const char*, std::string> files[] = {{html_name.c_str(), html}};
  return write_files(dir, files);
}

}  // namespace rayproof::report
