// libFuzzer harness: arbitrary bytes as a case file. The reader must never crash, must answer
// every line with a case or an error naming the line, and a parsed case must print back to a
// line that parses to the same doubles.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>

#include "io/case_file.h"

using namespace rayproof::io;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  const auto entries = read_cases(in, 4096);
  for (const auto& e : entries) {
    if (const auto* err = std::get_if<CaseError>(&e)) {
      if (err->line == 0 || err->message.empty()) std::abort();
      continue;
    }
    const Case& c = std::get<Case>(e);
    std::string family;
    const auto back = parse_case_line(format_case(c), 1, family);
    if (!back || !std::holds_alternative<Case>(*back)) std::abort();
    const Case& d = std::get<Case>(*back);
    if (std::memcmp(d.v.data(), c.v.data(), sizeof(double) * d.v.size()) != 0) {
      // NaN payloads may differ; anything else must round-trip.
      for (std::size_t i = 0; i < d.v.size(); ++i)
        if (!(d.v[i] != d.v[i] && c.v[i] != c.v[i]) && std::memcmp(&d.v[i], &c.v[i], sizeof(double)) != 0) std::abort();
    }
    (void)format_result(CaseResult{rayproof::Contact::hit, c.v[0], c.v[1]});
  }
  return 0;
}
