#!/bin/bash
# What the README's first command's build costs in CPU, a figure a loaded machine does not inflate
# much (its wall time it does): a fresh clone of this checkout at REV, configured and built with
# that revision's first command exactly (its cmake lines: no compiler cache, -j2, the target
# `rayproof`), the build under /usr/bin/time -v. Prints the load average before and after, the
# build's user + sys CPU and wall time, the sum of the job times in build/.ninja_log and the longest
# jobs. The job times are wall times: on a loaded machine they grow with the load, the CPU less so.
# Not a test (minutes of CPU); apt is not run (the packages must be installed). docs/commands.md#first-run
# has what it measured.
#
#   bench/first_run/compile_cpu.sh [REV] [WORK]    (default HEAD and a new temporary directory)
set -euo pipefail
src=$(cd "$(dirname "$0")/../.." && pwd)
rev=${1:-HEAD}
work=${2:-$(mktemp -d)}
[ -e "$work/clone" ] && { echo "compile_cpu.sh: $work/clone exists" >&2; exit 2; }
git clone -q "$src" "$work/clone"
git -C "$work/clone" checkout -q "$rev"
cd "$work/clone"
line=$(grep -m1 '^P="g++ cmake make ninja-build pkgconf' README.md) ||
  { echo "compile_cpu.sh: no first command in $rev's README.md" >&2; exit 2; }
rest="cmake -S${line#*; cmake -S}"   # from the configure on, as bare_debian.sh cuts it
configure=${rest%% && cmake --build*}
build=${rest#* && }; build=${build%% && build/rayproof*}
unset CMAKE_CXX_COMPILER_LAUNCHER CMAKE_C_COMPILER_LAUNCHER  # no compiler cache, as on a bare machine
echo "compile_cpu.sh: $(git rev-parse --short HEAD) in $work/clone"
echo "load before: $(cut -d' ' -f1-3 /proc/loadavg)"
eval "$configure" > "$work/configure.log"
eval "/usr/bin/time -v -o $work/time.txt $build" > "$work/build.log" 2>&1
echo "load after:  $(cut -d' ' -f1-3 /proc/loadavg)"
awk -F': ' '/User time/ {u = $2} /System time/ {s = $2} /Elapsed/ {w = $2}
  END { printf "build: %.1f s CPU (user %.1f + sys %.1f), wall %s\n", u + s, u, s, w }' "$work/time.txt"
awk 'NR > 1 { t = ($2 - $1) / 1000; sum += t; n++ } END { printf "jobs: %d, sum of job times %.1f s\n", n, sum }' build/.ninja_log
echo "longest jobs (s):"
awk 'NR > 1 { printf "%8.1f  %s\n", ($2 - $1) / 1000, $4 }' build/.ninja_log | sort -rn | head -12
