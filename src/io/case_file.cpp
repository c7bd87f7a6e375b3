#include "io/case_file.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <istream>

namespace rayproof::io {

namespace {
constexpr std::array<std::string_view, 6> kKindNames = {"plane", "sphere", "ellipsoid", "triangle", "box", "disk"};
constexpr std::array<int, 6> kFieldCounts = {12, 10, 12, 15, 12, 13};

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
    return CaseError{line_no, "unknown kind '" + shown + "' (expected plane, sphere, ellipsoid, triangle, box or disk)"};
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

std::string format_double(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x < 0 ? "-inf" : "inf";
  if (x == 0) return std::signbit(x) ? "-0.0" : "0.0";
  // Shortest round-trip digits in scientific form, then Python repr's layout:
  // positional when -4 <= exponent < 16, else d.ddde+XX.
  char buf[64];
  auto res = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::scientific);
  std::string s(buf, res.ptr);
  const bool neg = s[0] == '-';
  if (neg) s.erase(0, 1);
  const std::size_t e = s.find('e');
  std::string mant = s.substr(0, e);
  const int exp10 = std::atoi(s.c_str() + e + 1);
  std::string digits;
  for (char c : mant)
    if (c != '.') digits.push_back(c);
  std::string out;
  if (exp10 >= -4 && exp10 < 16) {
    const int point = exp10 + 1;  // digits before the decimal point
    if (point <= 0) {
      out.assign("0.");
      out.append(static_cast<std::size_t>(-point), '0');
      out.append(digits);
    } else if (static_cast<std::size_t>(point) >= digits.size()) {
      out = digits + std::string(static_cast<std::size_t>(point) - digits.size(), '0') + ".0";
    } else {
      out = digits.substr(0, static_cast<std::size_t>(point)) + "." + digits.substr(static_cast<std::size_t>(point));
    }
  } else {
    out = digits.substr(0, 1);
    if (digits.size() > 1) {
      out += '.';
      out.append(digits, 1);
    }
    char eb[16];
    std::snprintf(eb, sizeof eb, "e%c%02d", exp10 < 0 ? '-' : '+', exp10 < 0 ? -exp10 : exp10);
    out += eb;
  }
  if (neg) out.insert(out.begin(), '-');
  return out;
}

std::string format_result(const CaseResult& r) {
  std::string s(to_string(r.contact));
  s += ' ';
  s += r.t ? format_double(*r.t) : "-";
  s += ' ';
  s += r.t2 ? format_double(*r.t2) : "-";
  return s;
}

std::string format_answer(const CaseResult& r) {
  if (r.form != AnswerForm::coarse || (r.contact != Contact::hit && r.contact != Contact::miss)) return format_result(r);
  if (r.contact == Contact::miss) return "miss";
  std::string s = "hit";
  if (r.t) {
    s += ' ' + format_double(*r.t);
    if (r.b1 && r.b2) s += ' ' + format_double(*r.b1) + ' ' + format_double(*r.b2);
  }
  return s;
}

std::optional<CaseResult> parse_result(std::string_view text) {
  const auto f = split_fields(text);
  if (f.size() != 3) return std::nullopt;
  auto c = contact_from_string(f[0]);
  if (!c) return std::nullopt;
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

std::string format_case(const Case& c) {
  std::string s(to_string(c.kind));
  for (int i = 0; i < field_count(c.kind); ++i) {
    s += ' ';
    s += format_double(c.v[static_cast<std::size_t>(i)]);
  }
  return s;
}

Case round_to_float(const Case& c) {
  Case f = c;
  for (double& x : f.v) x = static_cast<double>(static_cast<float>(x));
  return f;
}

}  // namespace rayproof::io
