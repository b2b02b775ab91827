#!/usr/bin/env bash
# The Delaunay stage against CGAL 5.5, run after run: ROUNDS rounds, and in each, for every
# dataset and tincdt thread count, CGAL then tincdt (in-process triangulation time, the drivers'
# tri_s), each run preceded by touching WARM megabytes of memory (first_touch), so that neither
# tool pays for a virtual machine backing memory its guest gave back (docs/benchmarks.md). Prints
# every pair and, per dataset and thread count, the medians and the median of the ratios.
#
#   tests/bench/alternate_cgal.sh
#   ROUNDS=3 DATASETS=grid_4M THREADS_LIST=1 WARM=0 tests/bench/alternate_cgal.sh
#
# Environment: ROUNDS (5), DATASETS ("uniform_4M grid_4M"), THREADS_LIST ("0 1": tincdt's
# --threads, 0 = every core), WARM (2000; 0: no warming), TINBENCH_DATA, CGAL_BUILD
# (/tmp/tinbench_cgal), TINCDT_SHARED. Installs CGAL (libcgal-dev) and generates the data it misses.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
bench_defaults ROUNDS=5 DATASETS="uniform_4M grid_4M" THREADS_LIST="0 1" WARM=2000 \
  CGAL_BUILD=/tmp/tinbench_cgal
"$ROOT/cmake/setup.sh" libcgal-dev python3-numpy
# shellcheck disable=SC2086
/usr/bin/python3 "$SHARED/bench/gen.py" "$DATA" $DATASETS >/dev/null
cmake -S "$SHARED/bench/cgal" -B "$CGAL_BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$CGAL_BUILD" -j"$(nproc)" >/dev/null
build_bench_targets tincdt_tin_driver first_touch

tri_seconds() {  # tri_seconds COMMAND...: the RESULT line's tri_s, after warming the memory
  [[ $WARM == 0 ]] || "$BUILD/tests/bench/first_touch" "$WARM" 2 1 0 >/dev/null
  "$@" | sed -n 's/^RESULT .*tri_s=\([0-9.]*\).*/\1/p'
}
results="$(mktemp /tmp/tincdt_alternate.XXXXXX)"
trap 'rm -f "$results"' EXIT
for round in $(seq "$ROUNDS"); do
  for d in $DATASETS; do
    for t in $THREADS_LIST; do
      cgal="$(tri_seconds "$CGAL_BUILD/cgal_tin" dt "$DATA/$d/points.bin")"
      tin="$(tri_seconds "$BUILD/tests/bench/tincdt_tin_driver" dt "$DATA/$d/points.bin" --threads "$t")"
      echo "$round $d $t $cgal $tin" | tee -a "$results"
    done
  done
done
/usr/bin/python3 - "$results" <<'PY'
import collections, statistics, sys
runs = collections.defaultdict(list)
for line in open(sys.argv[1]):
    _, dataset, threads, cgal, tin = line.split()
    runs[(dataset, threads)].append((float(cgal), float(tin)))
print("| dataset | tincdt --threads | CGAL s (median) | tincdt s (median) | median of the ratios |")
print("| --- | --- | --- | --- | --- |")
for (dataset, threads), pairs in runs.items():
    ratio = statistics.median(t / c for c, t in pairs)
    print("| %s | %s | %.3f | %.3f | %.2f |" % (dataset, threads, statistics.median(c for c, _ in pairs),
                                               statistics.median(t for _, t in pairs), ratio))
PY
