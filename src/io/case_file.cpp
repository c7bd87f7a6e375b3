#include "io/case_file.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <istream>
#include <system_error>

namespace rayproof::io {

namespace {
constexpr std::array<std::string_view, 7> kKindNames = {"plane", "sphere", "ellipsoid", "triangle", "box", "disk", "tritri"};
constexpr std::array<int, 7> kFieldCounts = {12, 10, 12, 15, 12, 13, 18};
static_assert(kFieldCounts.size() == kCaseKinds.size());

/// The classes a triangle/triangle answer may name (docs/tritri.md).
bool pair_class_name(Contact c) { return is_pair_class(c) || c == Contact::invalid || c == Contact::degenerate; }

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

std::vector<std::string_view> split_fields(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    std::size_t j = i;
    while (j < s.size() && !is_space(s[j])) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

/// strtod on the whole token; false when any character is left over or nothing was read.
bool parse_number(std::string_view tok, double& out) {
  if (tok.size() > 4096) return false;
  std::string buf(tok);
  char* end = nullptr;
  out = std::strtod(buf.c_str(), &end);
  return end == buf.c_str() + buf.size() && !buf.empty();
}
}  // namespace

std::string_view to_string(Kind k) { return kKindNames[static_cast<std::size_t>(k)]; }

std::optional<Kind> kind_from_string(std::string_view s) {
  for (std::size_t i = 0; i < kKindNames.size(); ++i)
    if (kKindNames[i] == s) return static_cast<Kind>(i);
  return std::nullopt;
}

int field_count(Kind k) { return kFieldCounts[static_cast<std::size_t>(k)]; }

std::optional<CaseEntry> parse_case_line(std::string_view text, std::size_t line_no, std::string& family) {
  const std::size_t hash = text.find('#');
  if (hash != std::string_view::npos) {
    const auto comment = split_fields(text.substr(hash + 1));
    if (comment.size() >= 2 && comment[0] == "family") family = std::string(comment[1]);
    text = text.substr(0, hash);
  }
  const auto fields = split_fields(text);
  if (fields.empty()) return std::nullopt;
  const auto kind = kind_from_string(fields[0]);
  if (!kind) {
    std::string shown(fields[0].substr(0, 40));
    return CaseError{line_no, "unknown kind '" + shown + "' (expected plane, sphere, ellipsoid, triangle, box, disk or tritri)"};
  }
  const int want = field_count(*kind);
  const int got = static_cast<int>(fields.size()) - 1;
  if (got != want)
    return CaseError{line_no, std::string(to_string(*kind)) + " needs " + std::to_string(want) + " numbers, got " +
                                  std::to_string(got)};
  Case c;
  c.kind = *kind;
  c.family = family;
  c.line = line_no;
  for (int i = 0; i < want; ++i) {
    if (!parse_number(fields[static_cast<std::size_t>(i) + 1], c.v[static_cast<std::size_t>(i)])) {
      std::string shown(fields[static_cast<std::size_t>(i) + 1].substr(0, 40));
      return CaseError{line_no, "field " + std::to_string(i + 1) + " '" + shown + "' is not a number"};
    }
  }
  return c;
}

std::vector<CaseEntry> read_cases(std::istream& in, std::size_t max_line) {
  std::vector<CaseEntry> out;
  std::string family;
  std::string line;
  std::size_t line_no = 0;
  // Read in bounded chunks so a gigantic line costs bounded memory.
  while (true) {
    line.clear();
    bool too_long = false, any = false;
    char ch;
    while (in.get(ch)) {
      any = true;
      if (ch == '\n') break;
      if (line.size() < max_line) line.push_back(ch);
      else too_long = true;
    }
    if (!any) break;
    ++line_no;
    if (too_long) {
      out.emplace_back(CaseError{line_no, "line longer than " + std::to_string(max_line) + " bytes"});
      continue;
    }
    if (line.find('\0') != std::string::npos) {
      out.emplace_back(CaseError{line_no, "line holds a NUL byte (binary data?)"});
      continue;
    }
    if (auto e = parse_case_line(line, line_no, family)) out.push_back(std::move(*e));
  }
  return out;
}

void append_double(std::string& out, double x) {
  if (std::isnan(x)) return void(out += "nan");
  if (std::isinf(x)) return void(out += x < 0 ? "-inf" : "inf");
  if (x == 0) return void(out += std::signbit(x) ? "-0.0" : "0.0");
  // Shortest round-trip digits in scientific form, then Python repr's layout:
  // positional when -4 <= exponent < 16, else d.ddde+XX.
  char buf[64];
  const char* const end = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific).ptr;
  const char* p = buf;
  if (*p == '-') out += '-', ++p;
  char digits[32];
  int nd = 0;
  for (; p < end && *p != 'e'; ++p)
    if (*p != '.') digits[nd++] = *p;
  int exp10 = 0;
  std::from_chars(p + 1 + (p[1] == '+'), end, exp10);
  const std::string_view dv(digits, static_cast<std::size_t>(nd));
  char small[48];
  char* o = small;
  if (exp10 >= -4 && exp10 < 16) {
    const int point = exp10 + 1;  // digits before the decimal point
    if (point <= 0) {
      *o++ = '0', *o++ = '.';
      for (int i = 0; i < -point; ++i) *o++ = '0';
      for (char c : dv) *o++ = c;
    } else if (point >= nd) {
      for (char c : dv) *o++ = c;
      for (int i = nd; i < point; ++i) *o++ = '0';
      *o++ = '.', *o++ = '0';
    } else {
      for (int i = 0; i < nd; ++i) {
        if (i == point) *o++ = '.';
        *o++ = digits[i];
      }
    }
  } else {
    *o++ = digits[0];
    if (nd > 1) {
      *o++ = '.';
      for (int i = 1; i < nd; ++i) *o++ = digits[i];
    }
    *o++ = 'e';
    *o++ = exp10 < 0 ? '-' : '+';
    const int a = exp10 < 0 ? -exp10 : exp10;
    if (a < 10) *o++ = '0';
    o = std::to_chars(o, small + sizeof small, a).ptr;
  }
  out.append(small, static_cast<std::size_t>(o - small));
}

std::string format_double(double x) {
  std::string s;
  append_double(s, x);
  return s;
}

CaseResult pair_result(Contact c) {
  CaseResult r{c};
  r.pair = true;
  return r;
}

CaseResult pair_coarse(bool meets) {
  CaseResult r{meets ? Contact::hit : Contact::miss};
  r.form = AnswerForm::coarse;
  r.pair = true;
  return r;
}

std::string format_result(const CaseResult& r) {
  std::string s(to_string(r.contact));
  if (r.pair) return s;
  s += ' ';
  s += r.t ? format_double(*r.t) : "-";
  s += ' ';
  s += r.t2 ? format_double(*r.t2) : "-";
  return s;
}

std::string format_answer(const CaseResult& r) {
  if (r.form == AnswerForm::full) return format_result(r);
  std::string s(to_string(r.contact));
  for (const auto& v : {r.t, r.b1, r.b2}) {
    if (!v) break;
    s += ' ';
    append_double(s, *v);
  }
  return s;
}

std::optional<CaseResult> parse_result(std::string_view text) {
  const auto f = split_fields(text);
  if (f.size() == 1) {
    const auto c = contact_from_string(f[0]);
    if (!c || !pair_class_name(*c)) return std::nullopt;
    return pair_result(*c);
  }
  if (f.size() != 3) return std::nullopt;
  auto c = contact_from_string(f[0]);
  if (!c || is_pair_class(*c)) return std::nullopt;
  CaseResult r;
  r.contact = *c;
  for (int i = 1; i <= 2; ++i) {
    if (f[static_cast<std::size_t>(i)] == "-") continue;
    double v;
    if (!parse_number(f[static_cast<std::size_t>(i)], v)) return std::nullopt;
    (i == 1 ? r.t : r.t2) = v;
  }
  return r;
}

std::optional<CaseResult> parse_answer(std::string_view text) {
  // Up to five fields without allocating: answers are read at millions per second.
  std::array<std::string_view, 5> f;
  std::size_t n = 0, i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_space(text[i])) ++i;
    std::size_t j = i;
    while (j < text.size() && !is_space(text[j])) ++j;
    if (j > i) {
      if (n == f.size()) return std::nullopt;
      f[n++] = text.substr(i, j - i);
    }
    i = j;
  }
  if (n == 3) return parse_result(text);
  if (n == 0 || n > 4) return std::nullopt;
  if (n == 1 && f[0] != "hit" && f[0] != "miss") return parse_result(text);
  CaseResult r;
  r.form = AnswerForm::coarse;
  if (f[0] == "miss") {
    if (n != 1) return std::nullopt;
    r.contact = Contact::miss;
    return r;
  }
  if (f[0] != "hit") return std::nullopt;
  r.contact = Contact::hit;
  double v[3];
  for (std::size_t k = 1; k < n; ++k) {
    const char* b = f[k].data();
    const char* e = b + f[k].size();
    const auto res = std::from_chars(b, e, v[k - 1]);
    if ((res.ec != std::errc() || res.ptr != e) && !parse_number(f[k], v[k - 1])) return std::nullopt;
  }
  if (n >= 2) r.t = v[0];
  if (n == 4) r.b1 = v[1], r.b2 = v[2];
  return r;
}

bool answer_fits(Kind k, const CaseResult& r) {
  if (k != Kind::tritri) return !r.pair;
  if (r.form == AnswerForm::coarse) return !r.t && !r.b1 && !r.b2;
  return r.pair;
}

std::string format_case(const Case& c) {
  std::string s(to_string(c.kind));
  for (int i = 0; i < field_count(c.kind); ++i) {
    s += ' ';
    append_double(s, c.v[static_cast<std::size_t>(i)]);
  }
  return s;
}

void append_case_line(std::string& out, const Case& c) {
  out += to_string(c.kind);
  for (int i = 0; i < field_count(c.kind); ++i) {
    out += ' ';
    append_double(out, c.v[static_cast<std::size_t>(i)]);
  }
  out += '\n';
}

Case round_to_float(const Case& c) {
  Case f = c;
  for (double& x : f.v) x = static_cast<double>(static_cast<float>(x));
  return f;
}

}  // namespace rayproof::io
