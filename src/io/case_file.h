#pragma once
/// Case files (docs/cases.md): one ray/primitive case per line, and the result line
/// `CLASS T T2` every method prints. Parsing never throws on bad input: a bad line becomes an
/// error entry naming the line and the problem.
#include <array>
#include <cstddef>
#include <iosfwd>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "rayproof/contact.h"

namespace rayproof::io {

enum class Kind : unsigned char { plane, sphere, ellipsoid, triangle, box, disk };
inline constexpr std::array<Kind, 6> kAllKinds = {Kind::plane, Kind::sphere, Kind::ellipsoid,
                                                  Kind::triangle, Kind::box, Kind::disk};

[[nodiscard]] std::string_view to_string(Kind k);
[[nodiscard]] std::optional<Kind> kind_from_string(std::string_view s);
/// Number of numeric fields after the kind (12, 10, 12, 15, 12, 13).
[[nodiscard]] int field_count(Kind k);

/// One case. Values are the doubles strtod gives; unused trailing fields are 0.
struct Case {
  Kind kind = Kind::plane;
  std::array<double, 15> v{};
  std::string family;     ///< from the last `# family NAME` comment, else empty
  std::size_t line = 0;   ///< 1-based line in its file, 0 when generated
};

/// A line that could not be read.
struct CaseError {
  std::size_t line = 0;
  std::string message;
};

using CaseEntry = std::variant<Case, CaseError>;

/// Parses one line. Returns nothing for blank and comment-only lines; `family` is updated by a
/// `# family NAME` comment line.
[[nodiscard]] std::optional<CaseEntry> parse_case_line(std::string_view text, std::size_t line_no,
                                                       std::string& family);

/// Reads a whole stream of case lines (lines longer than max_line bytes are errors, not loaded).
[[nodiscard]] std::vector<CaseEntry> read_cases(std::istream& in, std::size_t max_line = 1 << 16);

/// How much a kernel answered. `full`: a docs/cases.md class with the T, T2 it carries. `coarse`: only
/// whether the ray touches the primitive at some t >= 0 (most user kernels know no more), with the
/// first contact's t and, for triangles, the barycentrics of p1 and p2 where the kernel gave them.
/// A coarse answer's contact is Contact::hit or Contact::miss (Contact::error for a kernel failure).
enum class AnswerForm : unsigned char { full, coarse };

/// The answer of a method on a case: the class and T, T2 where the class carries them.
struct CaseResult {
  Contact contact = Contact::error;
  std::optional<double> t{};
  std::optional<double> t2{};
  AnswerForm form = AnswerForm::full;
  std::optional<double> b1{};  ///< coarse triangle answers only: barycentric of p1, where given
  std::optional<double> b2{};  ///< coarse triangle answers only: barycentric of p2, where given
  friend bool operator==(const CaseResult&, const CaseResult&) = default;
};

/// Shortest text that reads back to the same double, as Python's repr prints it ("2.0", "1e-05",
/// "-0.0", "inf", "nan"). The expected files in data/ (*.expected) use this form.
[[nodiscard]] std::string format_double(double x);

/// `CLASS T T2` with `-` for absent values.
[[nodiscard]] std::string format_result(const CaseResult& r);

/// format_result for a full answer; a coarse one as the kernel gave it: `hit T B1 B2`, `hit T`,
/// `hit` or `miss`.
[[nodiscard]] std::string format_answer(const CaseResult& r);

/// Parses a result line (`CLASS T T2`); nothing on malformed text.
[[nodiscard]] std::optional<CaseResult> parse_result(std::string_view text);

/// Parses a user kernel's answer line (docs/kernel_protocol.md): the full `CLASS T T2` form
/// (AnswerForm::full, as parse_result) or a coarse one, AnswerForm::coarse: `hit T B1 B2`, `hit T`,
/// `hit` (Contact::hit) or `miss` (Contact::miss). Nothing on anything else.
[[nodiscard]] std::optional<CaseResult> parse_answer(std::string_view text);

/// The case as a case-file line that reads back to the same doubles (a one-line reproducer).
[[nodiscard]] std::string format_case(const Case& c);

/// Appends format_double(x) to `out` without temporaries (the same text).
void append_double(std::string& out, double x);

/// Appends format_case(c) and a newline to `out` (the same text; for streaming many cases).
void append_case_line(std::string& out, const Case& c);

/// The case with every input rounded to float (the input a float method sees; docs/cases.md).
[[nodiscard]] Case round_to_float(const Case& c);

}  // namespace rayproof::io
