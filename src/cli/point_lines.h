#pragma once
/// The point files of `rayproof contains` and `rayproof distance`: lines of numbers (cmd_contains.cpp).
#include <istream>
#include <string>
#include <vector>

namespace rayproof::cli {

/// Reads lines of `want` numbers (blank lines and # comments skipped; spaces, tabs or commas
/// between numbers) into `out`; on error returns false with "PATH:LINE: what" in `error` (a
/// token that is not a number, too many or too few numbers, a NaN or infinite coordinate).
bool read_numbers(std::istream& in, const std::string& path, int want, std::vector<double>& out, std::string& error);

}  // namespace rayproof::cli
