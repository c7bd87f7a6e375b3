// Batches of points or rays over TBB's threads: the one definition behind every batch query of the
// scene libraries (containment, winding numbers, closest points, crossings, the BVH queries' ray
// batches), so that what `threads` means is decided in one place.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <cstddef>

namespace rayproof::scene::detail {

/// Calls body(begin, end) on ranges that cover [0, n) once each: on the calling thread, in one
/// call, when threads == 1 or n < serial_below; else in ranges of about `grain` items on a TBB
/// arena of `threads` threads (0 or less: TBB's default, every core the process may use).
template <class Body>
void for_each_batch_range(std::size_t n, int threads, std::size_t serial_below, std::size_t grain, Body&& body) {
  if (n == 0) return;
  if (threads == 1 || n < serial_below) return static_cast<void>(body(std::size_t{0}, n));
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, grain),
                      [&](const tbb::blocked_range<std::size_t>& r) { body(r.begin(), r.end()); });
  });
}

}  // namespace rayproof::scene::detail
