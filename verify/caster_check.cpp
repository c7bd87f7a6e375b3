// The judgement of a whole caster on a mesh (rayproof/verify/caster_check.h): the certified
// MeshCaster gives each ray's first crossing; exact per-triangle tests settle the caster's triangle,
// ties and the correctly rounded t. Only the disagreements and the t errors cost exact arithmetic.
// The ray sets are made in caster_rays.cpp; a caster is run on them, and the summary written, in
// caster_run.cpp.
#include "rayproof/verify/caster_check.h"

#include <fmt/core.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include "rayproof/certified/intersect.h"
#include "rayproof/certified_expansion.h"
#include "rayproof/certified_filter.h"
#include "rayproof/float_util.h"
#include "rayproof/scene/contains.h"
#include "rayproof/scene/mesh_caster.h"
#include "rayproof/verify/exact.h"
#include "verify/judge_frame.h"
#include "verify/rounded_t.h"

namespace rayproof::verify {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
const TRange kPositive{std::numeric_limits<double>::denorm_min(), kInf};  // crossings at t > 0

std::string num(double x) { return exact_number(x); }

std::string ray_text(const Ray<double>& r) { return exact_point(r.o) + " " + exact_point(r.d); }

/// What an exact triangle result means for a caster judged at t > 0.
struct ForwardContact {
  enum Kind : std::uint8_t { none, origin, point, coplanar } kind = none;
  double t = kInf;  ///< t of the contact (a coplanar range: its start)
};

ForwardContact forward_contact(const TriangleHit<double>& h) {
  switch (h.contact) {
    case Contact::interior: case Contact::edge: case Contact::vertex:
      if (h.t > 0) return {ForwardContact::point, h.t};
      if (h.t == 0) return {ForwardContact::origin, 0};
      return {};
    case Contact::coplanar:
      if (std::isnan(h.t)) return {};
      if (h.t > 0) return {ForwardContact::coplanar, h.t};
      if (h.t == 0) return {ForwardContact::origin, 0};  // the origin lies in the triangle
      return {};
    default: return {};
  }
}

/// The exact contact of a ray with one triangle: the class from the certified filter (exact; GMP
/// where it cannot decide), t correctly rounded by round_t, exact::intersect for what is left
/// (coplanar ranges, extreme magnitudes).
struct ExactContact {
  ForwardContact forward;
  Contact contact = Contact::miss;
};
ExactContact exact_contact(const Ray<double>& r, const Triangle<double>& tri) {
  const TriangleHit<double> h = certified::intersect(r, tri);
  switch (h.contact) {
    case Contact::interior: case Contact::edge: case Contact::vertex:
      if (h.t > 0) {
        if (const auto rounded = round_t(r, tri, h.t)) return {{ForwardContact::point, *rounded}, h.contact};
      }
      break;
    case Contact::coplanar: break;
    default: return {{}, h.contact};
  }
  const TriangleHit<double> exact_hit = exact::intersect(r, tri);
  return {forward_contact(exact_hit), exact_hit.contact};
}

/// The mesh the judgement is exact on: a copy of the caller's arrays and the certified caster
/// over them.
struct ReferenceMesh {
  std::vector<Vec3<double>> vertices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::string name;
  MeshCaster<cast::Certified> caster;

  explicit ReferenceMesh(const CasterMesh& m)
      : vertices(m.vertices.begin(), m.vertices.end()), triangles(m.triangles.begin(), m.triangles.end()),
        name(m.name),
        caster(VertexArray(reinterpret_cast<const double*>(vertices.data()), vertices.size()),
               IndexArray{triangles.empty() ? nullptr : triangles.data()->data(), triangles.size()}) {}

  [[nodiscard]] Triangle<double> triangle(std::size_t i) const {
    return {vertices[triangles[i][0]], vertices[triangles[i][1]], vertices[triangles[i][2]]};
  }
};

/// What one chunk of rays (a range, in ray order) found. Chunks are judged on TBB threads, each into
/// its own ChunkTally, and merged in ray order.
struct ChunkTally {
  CasterCounts counts;
  std::vector<std::size_t> set_rays, set_findings, set_false_miss;  ///< indexed like CasterRays::names
  std::vector<CasterReproducer> reproducers;
  /// Reproducers kept per kind in this chunk: the first opt.reproducers of each kind over all chunks
  /// (in ray order) are among them; the rest are never formatted.
  std::vector<std::pair<std::string_view, std::size_t>> kept_per_kind;

  /// Whether the next reproducer of `kind` is kept (counts it).
  bool keep(std::string_view kind, std::size_t cap) {
    for (auto& [kept_kind, kept] : kept_per_kind)
      if (kept_kind == kind) return kept++ < cap;
    kept_per_kind.emplace_back(kind, 1);
    return cap > 0;
  }
};

/// What every ray of one judge() call shares.
struct JudgeInputs {
  const ReferenceMesh& mesh;
  const CasterRays& rays;
  std::span<const CasterAnswer> answers;
  const CasterCheckOptions& opt;
  bool float32 = false;  ///< t errors in float ulps
};

/// The distance in ulps of the caster's precision (double, or both rounded to float).
std::uint64_t caster_ulps(const JudgeInputs& in, double a, double b) {
  return in.float32 ? ulp_distance(static_cast<float>(a), static_cast<float>(b)) : ulp_distance(a, b);
}

/// The exact first crossing of a ray at t > 0, and the crossings near it. The vectors are reused
/// from ray to ray.
struct FirstCrossing {
  MeshHit certified;  ///< the certified caster's closest hit; none: the ray crosses nothing at t > 0
  std::uint32_t triangle = MeshHit::kNoTriangle;  ///< the exact first triangle (ties: the lowest number)
  bool coplanar = false;                          ///< its contact is a segment in the triangle's plane
  std::vector<MeshHit> near;    ///< the crossings within 4 ulps of certified.t
  std::vector<double> near_t;   ///< their correctly rounded t, when there are more than one
  std::optional<double> exact_t;  ///< the first crossing's correctly rounded t, once computed
  [[nodiscard]] bool hit() const { return certified.hit(); }
};

/// The judgement of one ray's answer into a chunk's tally, step by step in run()'s order. Only the
/// disagreements, the t errors and kept reproducers cost exact arithmetic.
class RayJudgement {
 public:
  RayJudgement(const JudgeInputs& in, std::size_t index, FirstCrossing& first, ChunkTally& tally)
      : in_(in), index_(index), ray_(in.rays.rays[index]), answer_(in.answers[index]), set_(in.rays.set[index]),
        first_(first), tally_(tally), counts_(tally.counts) {}

  void run() {
    ++tally_.set_rays[set_];
    ++counts_.rays;
    if (judge_invalid_or_failed()) return;
    find_first_crossing();
    if (first_.hit()) ++counts_.hits;
    if (answer_.any >= 0) judge_occlusion();
    if (judge_garbage()) return;
    judge_closest();
  }

 private:
  // The texts of a reproducer, as callables: called only when the reproducer is kept.
  static auto fixed(const char* text) {
    return [text] { return std::string(text); };
  }
  auto exact_text() {
    return [this] {
      if (!first_.hit()) return std::string("miss");
      return fmt::format("tri {} t {} {}", first_.triangle, num(first_t()), first_.coplanar ? "coplanar" : "crossing");
    };
  }
  auto caster_text() const {
    return [this] {
      if (answer_.failed) return std::string("failed");
      return fmt::format("tri {} t {}", answer_.triangle, num(answer_.t));
    };
  }
  std::string t_error_text(std::uint64_t ulps) const {
    return caster_text()() + fmt::format(" ({} ulps of {})", ulps, in_.float32 ? "float" : "double");
  }

  /// An invalid ray (no crossing: any answer but a miss is a finding), or an answer the caster
  /// failed to give. True when that is all there is to judge.
  bool judge_invalid_or_failed() {
    if (!ray_.valid()) {
      ++counts_.invalid_rays;
      if (answer_.failed)
        finding(&CasterCounts::invalid_failures, "invalid-ray-failure", fixed("invalid"), caster_text());
      else if (answer_.triangle != -1 || answer_.any == 1)
        finding(&CasterCounts::invalid_hit, "invalid-ray-hit", fixed("invalid"), caster_text());
      return true;
    }
    if (answer_.failed) {
      finding(&CasterCounts::caster_failures, "caster-failure", fixed("-"), fixed("failed"));
      return true;
    }
    return false;
  }

  /// Fills first_: the certified caster's closest hit, then every crossing whose certified t is
  /// within 4 ulps of it (certified t values are within 1 ulp of the rounded exact ones, so a
  /// triangle crossed first exactly, or tied, is among them). With one such crossing it is the
  /// first; with several, their correctly rounded t decide (ties to the lowest triangle number).
  void find_first_crossing() {
    first_.certified = in_.mesh.caster.closest(ray_, kPositive);
    first_.triangle = first_.certified.triangle;
    first_.coplanar = first_.certified.contact == Contact::coplanar;
    first_.exact_t.reset();
    first_.near.clear();
    first_.near_t.clear();
    if (!first_.hit()) return;
    double lo = first_.certified.t, hi = first_.certified.t;
    for (int k = 0; k < 4; ++k) lo = next_down(lo), hi = next_up(hi);
    first_.near = in_.mesh.caster.all(ray_, {std::max(lo, kPositive.tmin), hi});
    if (first_.near.size() <= 1) return;
    double best = kInf;
    for (const MeshHit& h : first_.near) {
      first_.near_t.push_back(rounded_t(h));
      if (first_.near_t.back() < best || (first_.near_t.back() == best && h.triangle < first_.triangle))
        best = first_.near_t.back(), first_.triangle = h.triangle, first_.coplanar = h.contact == Contact::coplanar;
    }
    first_.exact_t = best;
  }

  /// The occlusion answer: 0 where the ray crosses (a finding unless the first contact is
  /// coplanar); 1 where the ray touches nothing at t >= 0.
  void judge_occlusion() {
    ++counts_.any_rays;
    if (first_.hit() && answer_.any == 0) {
      if (first_.coplanar) ++counts_.any_coplanar_miss;
      else finding(&CasterCounts::any_false_miss, "any-false-miss", exact_text(), fixed("any 0"));
    } else if (!first_.hit() && answer_.any == 1) {
      if (!in_.mesh.caster.any(ray_, {0, kInf}))
        finding(&CasterCounts::any_false_hit, "any-false-hit", exact_text(), fixed("any 1"));
    }
  }

  /// An answer that is neither a miss (inf, -1) nor a hit (a triangle of the mesh, 0 <= t < inf).
  bool judge_garbage() {
    const double t = answer_.t;
    const std::int64_t tri = answer_.triangle;
    const auto triangle_count = static_cast<std::int64_t>(in_.mesh.triangles.size());
    const bool garbage = std::isnan(t) || tri < -1 || tri >= triangle_count || (tri == -1 && !(t == kInf)) ||
                         (tri >= 0 && !(t >= 0 && t < kInf));
    if (garbage) finding(&CasterCounts::garbage, "garbage", exact_text(), caster_text());
    return garbage;
  }

  /// The closest-hit answer (not garbage): a miss, the first crossing's triangle, or another one.
  void judge_closest() {
    const bool caster_hit = answer_.triangle >= 0;
    if (!first_.hit() && !caster_hit) return;
    if (!caster_hit) {
      if (first_.coplanar) {
        ++counts_.coplanar_miss;
      } else {
        finding(&CasterCounts::false_miss, "false-miss", exact_text(), caster_text());
        ++tally_.set_false_miss[set_];
      }
      return;
    }
    const auto claimed = static_cast<std::uint32_t>(answer_.triangle);
    if (claimed == first_.triangle && first_.hit()) judge_t_of_first();
    else judge_other_triangle(claimed);
  }

  /// The caster named the first crossing's triangle: its t is judged (unless the contact is
  /// coplanar) against the correctly rounded t, in the caster's precision. The reference comes from
  /// the certified t (within 1 ulp of the rounded exact t) where that decides the count, else from
  /// the rounded exact t: max_ulps and t_over_1ulp come out as from the exact t.
  void judge_t_of_first() {
    if (first_.coplanar) return;
    std::uint64_t ulps = 0;
    bool decided = false;
    const double certified_t = first_.near_t.empty() ? first_.certified.t : first_t();
    if (first_.exact_t) {
      decided = true;
      ulps = caster_ulps(in_, answer_.t, *first_.exact_t);
    } else if (in_.float32) {
      // The certified t and its neighbours round to one float: so does the exact t.
      const float as_float = static_cast<float>(certified_t);
      if (static_cast<float>(next_down(certified_t)) == as_float &&
          static_cast<float>(next_up(certified_t)) == as_float) {
        decided = true;
        ulps = ulp_distance(static_cast<float>(answer_.t), as_float);
      }
    } else {
      const std::uint64_t near_ulps = ulp_distance(answer_.t, certified_t);  // the true distance is within 1 of it
      if (near_ulps >= 3 && near_ulps + 1 <= counts_.max_ulps)  // over 1 ulp, and not a new maximum
        decided = true, ulps = near_ulps;
    }
    if (!decided) ulps = caster_ulps(in_, answer_.t, first_t());
    counts_.max_ulps = std::max(counts_.max_ulps, ulps);
    if (ulps > 1)
      finding(&CasterCounts::t_over_1ulp, "t-error", exact_text(),
              [this] { return t_error_text(caster_ulps(in_, answer_.t, first_t())); });
  }

  /// The caster named another triangle than the first crossing's: its contact (from the near
  /// crossings, or an exact test) decides between right (a tie, or the origin on the triangle with
  /// t = 0), a false hit (nothing crossed), and a wrong triangle; a tie's t is judged.
  void judge_other_triangle(std::uint32_t claimed) {
    ForwardContact claimed_contact;
    ExactContact tested;  // the exact test, when the triangle is not a near crossing
    std::size_t at = first_.near.size();
    for (std::size_t j = 0; j < first_.near.size(); ++j)
      if (first_.near[j].triangle == claimed) at = j;
    if (at < first_.near.size()) {
      const MeshHit& near = first_.near[at];
      claimed_contact = {near.contact == Contact::coplanar ? ForwardContact::coplanar : ForwardContact::point,
                         first_.near_t.empty() ? rounded_t(near) : first_.near_t[at]};
    } else {
      tested = exact_contact(ray_, in_.mesh.triangle(claimed));
      claimed_contact = tested.forward;
    }
    if (claimed_contact.kind == ForwardContact::origin && answer_.t == 0) return;  // the origin lies on it
    if (!first_.hit()) {
      finding(&CasterCounts::false_hit, "false-hit", exact_text(), caster_text());
      return;
    }
    if (claimed_contact.kind == ForwardContact::none || claimed_contact.kind == ForwardContact::origin) {
      finding(&CasterCounts::wrong_triangle, "wrong-triangle", exact_text(), [&] {
        return fmt::format("{} (not crossed at t > 0: {})", caster_text()(), to_string(tested.contact));
      });
      return;
    }
    const double exact_first_t = first_t();
    if (claimed_contact.t != exact_first_t) {
      if (caster_ulps(in_, claimed_contact.t, exact_first_t) <= 1) ++counts_.wrong_triangle_near;
      finding(&CasterCounts::wrong_triangle, "wrong-triangle", exact_text(),
              [&] { return fmt::format("{} (crossed at t {})", caster_text()(), num(claimed_contact.t)); });
      return;
    }
    // A triangle tied with the first crossing: t judged against the same exact t.
    if (claimed_contact.kind != ForwardContact::point || first_.coplanar) return;
    const std::uint64_t ulps = caster_ulps(in_, answer_.t, exact_first_t);
    counts_.max_ulps = std::max(counts_.max_ulps, ulps);
    if (ulps > 1) finding(&CasterCounts::t_over_1ulp, "t-error", exact_text(), [&] { return t_error_text(ulps); });
  }

  /// The correctly rounded t of a crossing (round_t from its certified t; an exact test for a
  /// coplanar one or where round_t cannot tell).
  [[nodiscard]] double rounded_t(const MeshHit& h) const {
    std::optional<double> t;
    if (h.contact != Contact::coplanar) t = round_t(ray_, in_.mesh.triangle(h.triangle), h.t);
    return t ? *t : exact_contact(ray_, in_.mesh.triangle(h.triangle)).forward.t;
  }
  /// The first crossing's correctly rounded t (computed once).
  double first_t() {
    if (!first_.exact_t) first_.exact_t = rounded_t(first_.certified);
    return *first_.exact_t;
  }

  /// Counts a finding of `kind` (in `counter` and the ray's set) and keeps its reproducer when it
  /// is among the first of its kind.
  template <class ExactText, class CasterText>
  void finding(std::uint64_t CasterCounts::*counter, const char* kind, ExactText&& exact, CasterText&& caster) {
    ++(counts_.*counter);
    ++tally_.set_findings[set_];
    if (!tally_.keep(kind, in_.opt.reproducers)) return;
    tally_.reproducers.push_back({kind, index_,
                                  fmt::format("{} set={} mesh={} ray {} exact: {} caster: {}", kind,
                                              in_.rays.names[set_], in_.mesh.name, ray_text(ray_), exact(), caster())});
  }

  const JudgeInputs& in_;
  const std::size_t index_;
  const Ray<double>& ray_;
  const CasterAnswer& answer_;
  const std::size_t set_;
  FirstCrossing& first_;
  ChunkTally& tally_;
  CasterCounts& counts_;
};

/// Judges rays [begin, end) into `tally`.
void judge_chunk(const JudgeInputs& in, std::size_t begin, std::size_t end, ChunkTally& tally) {
  const std::size_t set_count = in.rays.names.size();
  tally.set_rays.assign(set_count, 0);
  tally.set_findings.assign(set_count, 0);
  tally.set_false_miss.assign(set_count, 0);
  FirstCrossing first;
  for (std::size_t i = begin; i < end; ++i) RayJudgement(in, i, first, tally).run();
}

/// The chunks' tallies added up in ray order; of each kind of reproducer the first
/// opt.reproducers are kept.
CasterTally merge_chunks(std::vector<ChunkTally>& chunks, const CasterRays& rays, const CasterCheckOptions& opt) {
  const std::size_t set_count = rays.names.size();
  CasterTally out;
  std::vector<std::size_t> set_rays(set_count, 0), set_findings(set_count, 0), set_false_miss(set_count, 0);
  KindQuota quota(opt.reproducers);
  for (ChunkTally& chunk : chunks) {
    add_counts(out, chunk.counts, kCasterCounters);
    for (std::size_t k = 0; k < set_count && k < chunk.set_rays.size(); ++k) {
      set_rays[k] += chunk.set_rays[k];
      set_findings[k] += chunk.set_findings[k];
      set_false_miss[k] += chunk.set_false_miss[k];
    }
    for (CasterReproducer& reproducer : chunk.reproducers) {
      if (quota.keep(reproducer.kind)) out.reproducers.push_back(std::move(reproducer));
    }
  }
  for (std::size_t k = 0; k < set_count; ++k)
    out.sets.push_back({rays.names[k], set_rays[k], set_findings[k], set_false_miss[k]});
  out.notes = rays.notes;
  return out;
}

}  // namespace

struct CasterJudge::State : ReferenceMesh {
  using ReferenceMesh::ReferenceMesh;
};

CasterJudge::CasterJudge(const CasterMesh& mesh) : state_(std::make_unique<State>(mesh)) {}
CasterJudge::~CasterJudge() = default;
CasterJudge::CasterJudge(CasterJudge&&) noexcept = default;
CasterJudge& CasterJudge::operator=(CasterJudge&&) noexcept = default;

CasterTally CasterJudge::judge(const CasterRays& rays, std::span<const CasterAnswer> answers,
                               const CasterCheckOptions& opt) const {
  if (answers.size() != rays.rays.size() || rays.set.size() != rays.rays.size())
    throw std::invalid_argument(fmt::format("judge: {} answers for {} rays", answers.size(), rays.rays.size()));
  const JudgeInputs in{*state_, rays, answers, opt, opt.precision == CasterPrecision::float32};
  // Chunks in ray order; each its own tally, merged in order (deterministic reproducers).
  const std::size_t n = rays.rays.size(), chunk = 512;
  std::vector<ChunkTally> chunks((n + chunk - 1) / chunk);
  auto run = [&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, chunks.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& range) {
                        for (std::size_t k = range.begin(); k < range.end(); ++k)
                          judge_chunk(in, k * chunk, std::min(n, (k + 1) * chunk), chunks[k]);
                      });
  };
  if (opt.threads > 0) tbb::task_arena(opt.threads).execute(run);
  else run();
  return merge_chunks(chunks, rays, opt);
}

}  // namespace rayproof::verify
