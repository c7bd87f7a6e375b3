#pragma once
/// Internal helpers shared by the mesh readers: located errors, whole-token number parsing,
/// a line reader with a line-length bound, and fan triangulation.
#include <cmath>
#include <cstdint>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

#include "mesh/mesh.h"

namespace rayproof::mesh::detail {

/// Longest text line any reader accepts (a longer line is an error, never loaded whole).
inline constexpr std::size_t kMaxLine = 1 << 20;
/// Reservation cap: counts from headers are only trusted up to this before data confirms them.
inline constexpr std::size_t kMaxReserve = 1 << 16;

/// A token quoted for a message ('tok'), cut short after 40 bytes so that a huge token (a line can
/// hold a megabyte) never makes a huge message.
std::string quote(std::string_view tok);

[[noreturn]] void fail_line(const std::string& name, std::size_t line, const std::string& what);
[[noreturn]] void fail_byte(const std::string& name, std::uint64_t byte, const std::string& what);

/// Reads lines (any of \n, \r\n), counting them; strips what follows `comment` when non-zero.
class LineReader {
 public:
  LineReader(std::istream& in, std::string name, char comment) : in_(in), name_(std::move(name)), comment_(comment) {}
  /// Next line split into whitespace tokens; false at end of file. Blank lines give no tokens.
  bool next(std::vector<std::string_view>& tokens);
  /// Next line holding at least one token; false at end of file.
  bool next_nonblank(std::vector<std::string_view>& tokens);
  [[nodiscard]] std::size_t line() const { return line_; }
  [[nodiscard]] const std::string& name() const { return name_; }
  [[noreturn]] void fail(const std::string& what) const { fail_line(name_, line_, what); }
  std::istream& stream() { return in_; }

 private:
  std::istream& in_;
  std::string name_;
  char comment_;
  std::string buf_;
  std::size_t line_ = 0;
};

/// Pulls tokens one at a time across lines (OFF and ASCII PLY allow any line breaks).
class TokenReader {
 public:
  explicit TokenReader(LineReader& lines) : lines_(lines) {}
  /// Next token; false at end of file.
  bool next(std::string_view& tok);
  std::string_view need(const char* what);  ///< next token or a located "unexpected end" error
  double need_double(const char* what);
  std::uint64_t need_uint(const char* what);
  /// Drops what is left of the current line (OFF face colours).
  void skip_line() { pos_ = toks_.size(); }
  LineReader& lines() { return lines_; }

 private:
  LineReader& lines_;
  std::vector<std::string_view> toks_;
  std::size_t pos_ = 0;
};

/// The double strtod reads from the whole token, or nothing.
bool parse_double(std::string_view tok, double& out);
/// A decimal unsigned integer (no sign, no exponent), or nothing; overflow is nothing.
bool parse_uint(std::string_view tok, std::uint64_t& out);
/// A decimal signed integer, or nothing.
bool parse_int(std::string_view tok, std::int64_t& out);

/// Appends the fan (i0, i_k, i_k+1) of a polygon with n >= 3 corners.
void add_fan(Mesh& m, const std::uint32_t* idx, std::size_t n);

/// Size of the rest of a seekable stream from the current position, or -1 when unknown.
std::int64_t remaining_bytes(std::istream& in);

}  // namespace rayproof::mesh::detail
