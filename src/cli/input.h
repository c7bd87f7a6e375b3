#pragma once
/// Opening the user's input files with one clear error per failure (missing, directory, unreadable).
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "io/case_file.h"

namespace rayproof::cli {

/// An open input: standard input for "-", else the file. `error` is set instead when it cannot be
/// opened ("PATH: no such file", "PATH: is a directory", ...).
struct Input {
  std::unique_ptr<std::istream> owned;
  std::istream* stream = nullptr;
  std::string error;
};
[[nodiscard]] Input open_input(const std::string& path);

/// Reads a case file; on failure to open, or when it holds no case at all, sets `error`.
struct CaseInput {
  std::vector<io::CaseEntry> entries;
  std::string error;
};
[[nodiscard]] CaseInput read_case_input(const std::string& path);

/// `PATH:LINE: message` for a case-line error.
[[nodiscard]] std::string located(const std::string& path, const io::CaseError& e);

}  // namespace rayproof::cli
