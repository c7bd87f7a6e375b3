#include "methods/source_scan.h"

#include <cctype>

namespace rayproof {

namespace {
bool ident_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }
}  // namespace

std::string blank_comments(std::string_view s) {
  std::string out(s);
  for (std::size_t i = 0; i < out.size();) {
    if (out[i] == '"') {  // a string literal: skip to its end
      for (++i; i < out.size() && out[i] != '"' && out[i] != '\n'; ++i)
        if (out[i] == '\\') ++i;
      ++i;
    } else if (out.compare(i, 2, "//") == 0) {
      while (i < out.size() && out[i] != '\n') out[i++] = ' ';
    } else if (out.compare(i, 2, "/*") == 0) {
      const std::size_t end = out.find("*/", i + 2);
      const std::size_t stop = end == std::string::npos ? out.size() : end + 2;
      for (; i < stop; ++i)
        if (out[i] != '\n') out[i] = ' ';
    } else {
      ++i;
    }
  }
  return out;
}

std::vector<io::Kind> kinds_defined(std::string_view source, std::string (*name_of)(io::Kind)) {
  const std::string s = blank_comments(source);
  std::vector<io::Kind> out;
  for (io::Kind k : io::kAllKinds) {
    const std::string name = name_of(k);
    for (std::size_t at = s.find(name); at != std::string::npos; at = s.find(name, at + 1)) {
      if (at > 0 && ident_char(s[at - 1])) continue;
      std::size_t j = at + name.size();
      if (j < s.size() && ident_char(s[j])) continue;
      while (j < s.size() && std::isspace(static_cast<unsigned char>(s[j]))) ++j;
      if (j < s.size() && s[j] == '(') {
        out.push_back(k);
        break;
      }
    }
  }
  return out;
}

}  // namespace rayproof
