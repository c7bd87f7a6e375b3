#pragma once
/// Case files (docs/cases.md): one ray/primitive case per line, and the result line
/// `CLASS T T2` every method prints; or one triangle/triangle pair per line (kind `tritri`),
/// answered by its class alone (docs/tritri.md). Parsing never throws on bad input: a bad line becomes an
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

enum class Kind : unsigned char { plane, sphere, ellipsoid, triangle, box, disk, tritri };
/// The ray kinds: a ray against one primitive (everything but `tritri`).
inline constexpr std::array<Kind, 6> kAllKinds = {Kind::plane, Kind::sphere, Kind::ellipsoid,
                                                  Kind::triangle, Kind::box, Kind::disk};
/// Every kind a case line may have: the ray kinds, then `tritri` (two triangles, no ray).
inline constexpr std::array<Kind, 7> kCaseKinds = {Kind::plane, Kind::sphere, Kind::ellipsoid, Kind::triangle,
                                                   Kind::box,   Kind::disk,   Kind::tritri};

[[nodiscard]] std::string_view to_string(Kind k);
[[nodiscard]] std::optional<Kind> kind_from_string(std::string_view s);
/// Number of numeric fields after the kind (12, 10, 12, 15, 12, 13; 18 for tritri).
[[nodiscard]] int field_count(Kind k);

/// The largest field count (tritri: p0 p1 p2 q0 q1 q2).
inline constexpr int kMaxFields = 18;

/// One case. Values are the doubles strtod gives; unused trailing fields are 0.
struct Case {
  Kind kind = Kind::plane;
  std::array<double, kMaxFields> v{};
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
  /// The answer to a triangle/triangle case: a full answer is then written as its class alone
  /// (`touching`), a coarse one as `hit` (they meet) or `miss` (they do not).
  bool pair = false;
  friend bool operator==(const CaseResult&, const CaseResult&) = default;
};

/// A full answer to a triangle/triangle case (CaseResult::pair set, no T).
[[nodiscard]] CaseResult pair_result(Contact c);
/// A coarse answer to a triangle/triangle case: `hit` when `meets`, else `miss`.
[[nodiscard]] CaseResult pair_coarse(bool meets);

/// Shortest text that reads back to the same double, as Python's repr prints it ("2.0", "1e-05",
/// "-0.0", "inf", "nan"). The expected files in data/ (*.expected) use this form.
[[nodiscard]] std::string format_double(double x);

/// `CLASS T T2` with `-` for absent values; `CLASS` alone for a pair's answer (CaseResult::pair).
[[nodiscard]] std::string format_result(const CaseResult& r);

/// format_result for a full answer; a coarse one as the kernel gave it: `hit T B1 B2`, `hit T`,
/// `hit` or `miss`.
[[nodiscard]] std::string format_answer(const CaseResult& r);

/// Parses a result line (`CLASS T T2`, or a pair's `CLASS` alone: CaseResult::pair, a class a
/// tritri case can have); nothing on malformed text.
[[nodiscard]] std::optional<CaseResult> parse_result(std::string_view text);

/// Parses a user kernel's answer line (docs/kernel_protocol.md): the full `CLASS T T2` form
/// (AnswerForm::full, as parse_result) or a coarse one, AnswerForm::coarse: `hit T B1 B2`, `hit T`,
/// `hit` (Contact::hit) or `miss` (Contact::miss). A pair's class alone is a full pair answer
/// (`hit` and `miss` alone stay coarse: for a pair, they meet or not). Nothing on anything else.
[[nodiscard]] std::optional<CaseResult> parse_answer(std::string_view text);

/// Whether an answer is one a case of kind k can have: for `tritri`, `hit`, `miss` or a pair's class
/// alone; for a ray kind, anything else parse_answer reads.
[[nodiscard]] bool answer_fits(Kind k, const CaseResult& r);

/// The case as a case-file line that reads back to the same doubles (a one-line reproducer).
[[nodiscard]] std::string format_case(const Case& c);

/// Appends format_double(x) to `out` without temporaries (the same text).
void append_double(std::string& out, double x);

/// Appends format_case(c) and a newline to `out` (the same text; for streaming many cases).
void append_case_line(std::string& out, const Case& c);

/// The case with every input rounded to float (the input a float method sees; docs/cases.md).
[[nodiscard]] Case round_to_float(const Case& c);

}  // namespace rayproof::io
