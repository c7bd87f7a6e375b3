#pragma once
/// `check --caster --out DIR`: the casters' findings beside rayproof's own casters (float, robust,
/// certified MeshCasters) judged on the same rays, as report.md and report.html.
#include <string>
#include <vector>

#include "rayproof/verify/caster_check.h"

namespace rayproof::verify {

struct CasterReportRow {
  std::string caster;   ///< a name
  std::string command;  ///< how it ran ("built-in" for rayproof's)
  std::string mesh;
  std::size_t triangles = 0;
  CasterTally tally;
  std::vector<std::string> events;  ///< crashes, hangs, garbage
};

/// rayproof's float, robust and certified casters on the rays, judged with `opt` (their answers
/// as MeshCaster::closest gives them, crossings at t > 0).
[[nodiscard]] std::vector<CasterReportRow> builtin_caster_rows(const CasterMesh& mesh, const CasterRays& rays,
                                                               const CasterJudge& judge, const CasterCheckOptions& opt);

/// Writes DIR/report.md and DIR/report.html (DIR created). Throws std::runtime_error naming the
/// file that could not be written.
void write_caster_report(const std::string& dir, const std::vector<CasterReportRow>& rows, const std::string& precision);

}  // namespace rayproof::verify
