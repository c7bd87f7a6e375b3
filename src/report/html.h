#pragma once
/// report.html: the report's markdown rendered as one self-contained page (no network): the same
/// text and numbers as report.md (it is rendered from it, by cmark-gfm), its SVG charts inlined so
/// that each method's point shows its numbers on hover, and a copy button on every reproducer line.
#include <functional>
#include <string>

namespace rayproof::report {

/// `s` as XML/HTML text or attribute value: &, <, > and both quotes escaped (every SVG and HTML
/// string of the report goes through this one).
[[nodiscard]] std::string escape_xml(const std::string& s);

/// The page for `markdown`. `image` maps an image's file name (as the markdown names it) to the
/// SVG text to inline in its place, or "" to leave a link (a file that is not there).
[[nodiscard]] std::string markdown_to_html(const std::string& markdown,
                                           const std::function<std::string(const std::string&)>& image);

/// Renders `dir`/`md_name` into `dir`/`html_name`, inlining the SVG files of `dir` it shows; returns
/// an error message or "".
[[nodiscard]] std::string write_html(const std::string& dir, const std::string& md_name = "report.md",
                                     const std::string& html_name = "report.html");

}  // namespace rayproof::report
