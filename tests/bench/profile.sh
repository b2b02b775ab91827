#!/usr/bin/env bash
# Where a tincdt job spends its time: the stage timings of --stats beside a perf profile of the
# same run (sampled call stacks, functions by their own share of the samples), so that work on
# speed starts from a measurement.
#
#   tests/bench/profile.sh                          # uniform_4M's points.xyz -> PLY
#   tests/bench/profile.sh IN.las -o /tmp/x.ply     # any tincdt arguments (--stats is added)
#   TOP=60 THREADS=1 tests/bench/profile.sh ...
#
# Environment: TINBENCH_DATA (/tmp/tinbench), TINCDT_PROFILE_BUILD (build/profile: RelWithDebInfo
# with frame pointers, so that perf unwinds the stacks), OUT (/tmp/tincdt_profile: perf.data, the
# stats and the reports), TOP (40 rows), THREADS (tincdt's --threads; 0 = every core).
# Needs perf (Debian linux-perf); perf_event_paranoid <= 2 lets a user profile their own runs.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
BUILD="${TINCDT_PROFILE_BUILD:-$ROOT/build/profile}"
OUT="${OUT:-/tmp/tincdt_profile}"
TOP="${TOP:-40}"
THREADS="${THREADS:-0}"

"$ROOT/cmake/setup.sh" linux-perf
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTINCDT_BUILD_TESTS=OFF \
  -DTINCDT_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS="-fno-omit-frame-pointer" >/dev/null
cmake --build "$BUILD" -j"$(nproc)" --target tincdt >/dev/null

mkdir -p "$OUT"
if [ $# -eq 0 ]; then
  [ -s "$DATA/uniform_4M/points.xyz" ] || /usr/bin/python3 "$SHARED/bench/gen.py" "$DATA" uniform_4M
  set -- "$DATA/uniform_4M/points.xyz" -o "$OUT/job.ply"
fi

perf record -F 999 -g -o "$OUT/perf.data" -- \
  "$BUILD/tincdt" "$@" --threads "$THREADS" --overwrite -q --stats "$OUT/stats.json" 2>"$OUT/perf.log"

echo "## stage timings (s), from --stats"
/usr/bin/python3 -c '
import json, sys
t = json.load(open(sys.argv[1]))["timings_s"]
for k, v in t.items(): print("%-16s %8.3f" % (k, v))' "$OUT/stats.json"
echo
echo "## functions by their own share of the samples (top $TOP; all: $OUT/self.txt)"
perf report -i "$OUT/perf.data" --no-children -F overhead,sym --stdio 2>/dev/null |
  grep -v '^#' | grep -v '^$' >"$OUT/self.txt"
grep -E '^ +[0-9.]+%' "$OUT/self.txt" | head -n "$TOP"
echo
echo "## call chains (callers included): $OUT/children.txt"
perf report -i "$OUT/perf.data" --children -F overhead,sym --stdio 2>/dev/null >"$OUT/children.txt"
