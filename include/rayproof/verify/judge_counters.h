#pragma once
/// The counters every judge of a whole function (caster_check.h, contains_check.h,
/// distance_check.h) declares the same way: one table per judge, one row per
/// count, in which a count's name, meaning and use are written down once. The summary text, the
/// CLI's JSON, the reports' columns and Python's dicts are made from the table, in its order.
/// Header-only, no dependencies.
///
///   struct MyCounts { std::uint64_t judged = 0, wrong = 0; constexpr std::uint64_t findings() const; };
///   inline constexpr JudgeCounter<MyCounts> kMyCounters[] = {
///       {.key = "judged", .member = &MyCounts::judged},
///       {.key = "wrong", .member = &MyCounts::wrong, .finding = true},
///       {.key = "findings"}};
///   constexpr std::uint64_t MyCounts::findings() const { return sum_of_findings(kMyCounters, *this); }
///   static_assert(every_counter_once(kMyCounters));
#include <cstddef>
#include <cstdint>
#include <string_view>
#include <type_traits>

namespace rayproof::verify {

/// One counter of a judge's counts (a struct of std::uint64_t members only).
template <class Counts>
struct JudgeCounter {
  std::string_view key;  ///< the JSON and Python key; the text and report label unless given below
  std::uint64_t Counts::*member = nullptr;  ///< null for `findings` (the sum of the findings)
  bool finding = false;       ///< added into findings()
  bool maximum = false;       ///< merged as the largest value (else added up)
  bool occlusion = false;     ///< caster: a count of occlusion answers, shown only when any were asked
  bool report_column = true;  ///< a column of the `--out` report
  std::string_view text_label = {};    ///< the summary text's label, when not the key
  std::string_view column_label = {};  ///< the report's column header, when not the key
  std::string_view meaning = {};       ///< per item judged: the answer that is counted
};

/// The sum of the counters marked `finding`.
template <class Counts, std::size_t N>
[[nodiscard]] constexpr std::uint64_t sum_of_findings(const JudgeCounter<Counts> (&table)[N],
                                                         const std::type_identity_t<Counts>& counts) {
  std::uint64_t sum = 0;
  for (const JudgeCounter<Counts>& counter : table)
    if (counter.finding) sum += counts.*counter.member;
  return sum;
}

/// Every member of Counts is in the table once, and `findings` (no member) once: a counter added to
/// the struct and not to the table fails the static_assert that calls this.
template <class Counts, std::size_t N>
[[nodiscard]] constexpr bool every_counter_once(const JudgeCounter<Counts> (&table)[N]) {
  std::size_t derived = 0;
  for (std::size_t i = 0; i < N; ++i) {
    if (!table[i].member) ++derived;
    for (std::size_t j = 0; j < i; ++j)
      if (table[i].key == table[j].key || (table[i].member && table[i].member == table[j].member)) return false;
  }
  return derived == 1 && (N - 1) * sizeof(std::uint64_t) == sizeof(Counts);
}

/// The value of a counter in `counts`.
template <class Counts>
[[nodiscard]] constexpr std::uint64_t count_of(const std::type_identity_t<Counts>& counts,
                                                     const JudgeCounter<Counts>& counter) {
  return counter.member ? counts.*counter.member : counts.findings();
}
/// The counter's label in the summary text, and in the report's header.
template <class Counts>
[[nodiscard]] constexpr std::string_view text_label(const JudgeCounter<Counts>& counter) {
  return counter.text_label.empty() ? counter.key : counter.text_label;
}
template <class Counts>
[[nodiscard]] constexpr std::string_view column_label(const JudgeCounter<Counts>& counter) {
  return counter.column_label.empty() ? counter.key : counter.column_label;
}

/// The counts merged: maxima as the largest, the others added up.
template <class Counts, std::size_t N>
constexpr void add_counts(std::type_identity_t<Counts>& into, const std::type_identity_t<Counts>& from,
                          const JudgeCounter<Counts> (&table)[N]) {
  for (const JudgeCounter<Counts>& counter : table) {
    if (!counter.member) continue;
    std::uint64_t& to = into.*counter.member;
    const std::uint64_t x = from.*counter.member;
    to = counter.maximum ? (x > to ? x : to) : to + x;
  }
}

}  // namespace rayproof::verify
