#include "methods/serve.h"

#include <istream>
#include <ostream>
#include <string>

namespace rayproof {

int serve_kernel_protocol(const Method& m, std::istream& in, std::ostream& out, bool header) {
  if (header) {
    out << "rayproof-kernel 1 " << (m.precision == Precision::float32 ? "float" : "double") << ' ';
    for (std::size_t i = 0; i < m.kinds.size(); ++i) out << (i ? "," : "") << io::to_string(m.kinds[i]);
    out << '\n' << std::flush;
  }
  std::string line, family;
  std::size_t n = 0;
  while (std::getline(in, line)) {
    const auto entry = io::parse_case_line(line, ++n, family);
    if (!entry) continue;  // blank or comment: no case, no answer
    const io::Case* c = std::get_if<io::Case>(&*entry);
    if (!c) {
      out << "error - -\n";
      continue;
    }
    const io::CaseResult r = m.run(*c);
    // A plugin's answer outside the vocabulary: a line that is no answer, so the --exec side
    // reports a kernel failure with this case.
    if (r.contact == Contact::error && m.take_failures) {
      const auto failures = m.take_failures();
      if (!failures.empty()) {
        out << "kernel-failure: " << failures.front().what << '\n';
        continue;
      }
    }
    out << io::format_answer(r) << '\n';
  }
  out << std::flush;
  return 0;
}

}  // namespace rayproof
