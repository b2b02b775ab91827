#!/usr/bin/env bash
# tincdt against CGAL 5.5 on the ../shared/bench data, in one session: every job runs REPEAT
# times round-robin under /usr/bin/time (../shared/bench/bench_run.py), medians reported, then
# the tincdt/CGAL time ratios and tincdt's peak memory per point.
#
#   tests/bench/compare_cgal.sh            # DT: uniform_1M uniform_4M grid_4M and the realistic
#                                          # sets; CDT: pslg; job
#   DATASETS="uniform_1M" REAL_SETS= NO_PSLG=1 REPEAT=1 tests/bench/compare_cgal.sh
#   THREADS=1 tests/bench/compare_cgal.sh  # tincdt on one core against CGAL (always one)
#
# The realistic sets (make_real_points.cpp, made once into TINBENCH_DATA): lidar_4M, autzen_trim's
# points tiled to 4M (real LiDAR spacing and order); dem_4M, a real DEM resampled to 2048 x 2048
# cells, row by row (no-data cells left out); dups_4M, 1M sites written 4 times each.
#
# Environment: TINCDT_SHARED (default ../shared beside the repo), TINBENCH_DATA (/tmp/tinbench),
# TINCDT_BENCH_BUILD (build/bench), REPEAT (3), DATASETS, REAL_SETS, THREADS (tincdt's; 0 = every
# core), NO_PSLG=1, NO_JOB=1, CGAL_BUILD (/tmp/tinbench_cgal, where run_cgal.sh builds CGAL's
# driver).
# Installs the benchmark-only packages (CGAL, numpy, GDAL's Python bindings, GNU time).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
export REPEAT="${REPEAT:-3}"
export DATASETS="${DATASETS:-uniform_1M uniform_4M grid_4M}"
export TINBENCH_DATA="$DATA"
REAL_SETS="${REAL_SETS-lidar_4M dem_4M dups_4M}"
THREADS="${THREADS:-0}"
CGAL_TIN="${CGAL_BUILD:-/tmp/tinbench_cgal}/cgal_tin"  # built by run_cgal.sh before any job runs

"$ROOT/cmake/setup.sh" libcgal-dev python3-numpy python3-gdal gdal-bin time
build_bench_targets tincdt tincdt_tin_driver make_real_points
DRIVER="$BUILD/tests/bench/tincdt_tin_driver"
TINCDT="$BUILD/tincdt"

spec="$(mktemp /tmp/tincdt_bench_spec.XXXXXX)"
out="$(mktemp /tmp/tincdt_bench_out.XXXXXX)"
trap 'rm -f "$spec" "$out" /tmp/tincdt_bench_job.ply /tmp/tincdt_bench_job.json' EXIT
make_real() {  # make_real NAME: its points.bin, unless made before
  local dir="$DATA/$1"
  [ -s "$dir/points.bin" ] && return
  mkdir -p "$dir"
  case "$1" in
    lidar_4M) "$BUILD/tests/bench/make_real_points" lidar "$SHARED/data/laz/autzen_trim.laz" 4000000 "$dir/points.bin" ;;
    dem_4M) "$BUILD/tests/bench/make_real_points" dem "$SHARED/data/dem/Topography_lidR2016_dtm.tif" 4194304 "$dir/points.bin" ;;
    dups_4M) "$BUILD/tests/bench/make_real_points" duplicates 4000000 "$dir/points.bin" ;;
    *) echo "compare_cgal.sh: unknown realistic set $1" >&2; exit 2 ;;
  esac
}
for d in $REAL_SETS; do
  make_real "$d"
  printf 'cgal-5.5 DT2 Epick\t%s\t%s dt %s\n' "$d" "$CGAL_TIN" "$DATA/$d/points.bin" >>"$spec"
done
for d in $DATASETS $REAL_SETS; do
  printf 'tincdt DT\t%s\t%s dt %s --threads %s\n' "$d" "$DRIVER" "$DATA/$d/points.bin" "$THREADS" >>"$spec"
done
if [ "${NO_PSLG:-0}" != 1 ]; then
  printf 'tincdt CDT\tpslg\t%s cdt %s --threads %s\n' "$DRIVER" "$DATA/contours/pslg.txt" "$THREADS" >>"$spec"
fi
if [ "${NO_JOB:-0}" != 1 ]; then
  # The whole job, text in and binary PLY out; its RESULT line comes from the --stats file.
  job_ds="${JOB_DATASET:-uniform_4M}"
  printf 'tincdt job xyz->ply\t%s\t%s %s -o /tmp/tincdt_bench_job.ply --threads %s -q --stats /tmp/tincdt_bench_job.json --overwrite && /usr/bin/python3 %s /tmp/tincdt_bench_job.json\n' \
    "$job_ds" "$TINCDT" "$DATA/$job_ds/points.xyz" "$THREADS" "$ROOT/tests/bench/stats_result.py" >>"$spec"
fi

EXTRA_SPEC="$spec" EI=0 "$SHARED/bench/run_cgal.sh" | tee "$out"
echo
CORES="$([ "$THREADS" = 0 ] && nproc || echo "$THREADS")" /usr/bin/python3 "$ROOT/tests/bench/ratios.py" "$out"
