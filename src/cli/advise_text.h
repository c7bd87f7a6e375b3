#pragma once
/// What `rayproof advise` prints about an AdviseResult: the method table, every sentence, and the
/// JSON document with the same content. Kept apart from the command so that tests build them from
/// known tallies.
#include <string>
#include <vector>

#include "scene/advise.h"

namespace rayproof::cli {

/// One row per method: rays compared, leaks (of leak rays), false hits, false misses, wrong
/// primitives, wrong classes, t beyond tolerance, max t error (ulps), Mrays/s, promise.
[[nodiscard]] std::string advise_table(const scene::AdviseResult& r);

/// The sentences about the geometry (analysis), the rays, the reference, each method's errors, the
/// recommendation, what the scene does not need and what one sphere more costs; each true for the
/// numbers it states.
[[nodiscard]] std::vector<std::string> geometry_sentences(const scene::SceneAnalysis& a);
[[nodiscard]] std::vector<std::string> advise_sentences(const scene::AdviseResult& r);

/// The whole result as JSON (the analysis, ray sets, per-method tallies, path counts, the kind
/// cost, the recommendation and the sentences), `scene` naming the input.
[[nodiscard]] std::string advise_json(const scene::AdviseResult& r, const std::string& scene);

}  // namespace rayproof::cli
