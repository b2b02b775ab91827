#!/usr/bin/env bash
# tincdt against CGAL 5.5 on the ../shared/bench data, in one session: every job runs REPEAT
# times round-robin under /usr/bin/time (../shared/bench/bench_run.py), medians reported, then
# the tincdt/CGAL time ratios and tincdt's peak memory per point.
#
#   tests/bench/compare_cgal.sh            # DT: uniform_1M uniform_4M grid_4M; CDT: pslg; job
#   DATASETS="uniform_1M" NO_PSLG=1 REPEAT=1 tests/bench/compare_cgal.sh
#
# Environment: TINCDT_SHARED (default ../shared beside the repo), TINBENCH_DATA (/tmp/tinbench),
# TINCDT_BENCH_BUILD (build/bench), REPEAT (3), DATASETS, NO_PSLG=1, NO_JOB=1.
# Installs the benchmark-only packages (CGAL, numpy, GDAL's Python bindings, GNU time).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
export REPEAT="${REPEAT:-3}"
export DATASETS="${DATASETS:-uniform_1M uniform_4M grid_4M}"
export TINBENCH_DATA="$DATA"

"$ROOT/cmake/setup.sh" libcgal-dev python3-numpy python3-gdal gdal-bin time
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DTINCDT_BUILD_TESTS=ON \
  -DTINCDT_BUILD_BENCH=ON >/dev/null
cmake --build "$BUILD" -j"$(nproc)" --target tincdt tincdt_tin_driver >/dev/null
DRIVER="$BUILD/tests/bench/tincdt_tin_driver"
TINCDT="$BUILD/tincdt"

spec="$(mktemp /tmp/tincdt_bench_spec.XXXXXX)"
out="$(mktemp /tmp/tincdt_bench_out.XXXXXX)"
trap 'rm -f "$spec" "$out" /tmp/tincdt_bench_job.ply /tmp/tincdt_bench_job.json' EXIT
for d in $DATASETS; do
  printf 'tincdt DT\t%s\t%s dt %s\n' "$d" "$DRIVER" "$DATA/$d/points.bin" >>"$spec"
done
if [ "${NO_PSLG:-0}" != 1 ]; then
  printf 'tincdt CDT\tpslg\t%s cdt %s\n' "$DRIVER" "$DATA/contours/pslg.txt" >>"$spec"
fi
if [ "${NO_JOB:-0}" != 1 ]; then
  # The whole job, text in and binary PLY out; its RESULT line comes from the --stats file.
  job_ds="${JOB_DATASET:-uniform_4M}"
  printf 'tincdt job xyz->ply\t%s\t%s %s -o /tmp/tincdt_bench_job.ply --overwrite -q --stats /tmp/tincdt_bench_job.json --overwrite && /usr/bin/python3 %s /tmp/tincdt_bench_job.json\n' \
    "$job_ds" "$TINCDT" "$DATA/$job_ds/points.xyz" "$ROOT/tests/bench/stats_result.py" >>"$spec"
fi

EXTRA_SPEC="$spec" EI=0 "$SHARED/bench/run_cgal.sh" | tee "$out"
echo
/usr/bin/python3 "$ROOT/tests/bench/ratios.py" "$out"
