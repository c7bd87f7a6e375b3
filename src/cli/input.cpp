#include "cli/input.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace rayproof::cli {

Input open_input(const std::string& path) {
  Input in;
  if (path == "-") {
    in.stream = &std::cin;
    return in;
  }
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) {
    in.error = path + ": no such file";
    return in;
  }
  if (std::filesystem::is_directory(st)) {
    in.error = path + ": is a directory, not a file";
    return in;
  }
  auto f = std::make_unique<std::ifstream>(path, std::ios::binary);
  if (!*f) {
    in.error = path + ": cannot open (" + std::strerror(errno) + ")";
    return in;
  }
  in.stream = f.get();
  in.owned = std::move(f);
  return in;
}

CaseInput read_case_input(const std::string& path) {
  CaseInput out;
  Input in = open_input(path);
  if (!in.stream) {
    out.error = in.error;
    return out;
  }
  out.entries = io::read_cases(*in.stream);
  if (in.stream->bad()) out.error = path + ": read error";
  else if (out.entries.empty()) out.error = path + ": no cases (empty file or only comments)";
  return out;
}

std::string located(const std::string& path, const io::CaseError& e) {
  return path + ":" + std::to_string(e.line) + ": " + e.message;
}

}  // namespace rayproof::cli
