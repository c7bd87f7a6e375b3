#include "report/timing.h"

#include <algorithm>
#include <chrono>

namespace rayproof::report {

double ns_per_case(const Method& m, const std::vector<io::Case>& inputs, int reps) {
  if (inputs.empty()) return 0.0;
  using clock = std::chrono::steady_clock;
  std::vector<double> samples;
  volatile unsigned sink = 0;  // keeps the answers observable so no call is optimized away
  std::vector<io::CaseResult> batch(m.classify_batch ? inputs.size() : 0);
  for (int r = 0; r < reps; ++r) {
    const auto t0 = clock::now();
    unsigned acc = 0;
    if (m.classify_batch) {
      // A kernel behind a pipe (--exec, a forked --plugin) answers a batch, as it does in the checks:
      // timed per case over the batch, process start and pipe included.
      m.classify_many(inputs, batch);
      for (const auto& res : batch) acc += static_cast<unsigned>(res.contact) + (res.t ? 1u : 0u);
    } else {
      for (const auto& c : inputs) {
        const io::CaseResult res = m.classify(c);
        acc += static_cast<unsigned>(res.contact) + (res.t ? 1u : 0u);
      }
    }
    const auto t1 = clock::now();
    sink = sink + acc;
    samples.push_back(std::chrono::duration<double, std::nano>(t1 - t0).count() / double(inputs.size()));
    // A batch over 50 ms (exact arithmetic) is stable enough: three samples suffice.
    if (r == 2 && samples[0] > 5e7 / double(inputs.size())) break;
  }
  std::sort(samples.begin(), samples.end());
  return samples[samples.size() / 2];
}

}  // namespace rayproof::report
