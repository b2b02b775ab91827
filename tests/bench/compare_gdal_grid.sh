#!/usr/bin/env bash
# tincdt's products (DEM, contours) against GDAL (gdal_grid -a linear, gdal_contour) on the same
# data in one session, plus the pairs' RMSE against their reference DTMs, a gdalinfo of the COG
# and a 4M-point job writing every product. Prints markdown tables; see compare_gdal_grid.py.
#
#   tests/bench/compare_gdal_grid.sh                 # every section
#   REPEAT=3 tests/bench/compare_gdal_grid.sh dem    # dem rmse contours cog job
#
# Environment: TINCDT_SHARED (default ../shared beside the repo), TINBENCH_DATA (/tmp/tinbench),
# TINCDT_BENCH_BUILD (build/bench), OUT (/tmp/tincdt_gdal_grid), REPEAT (1), CASES (the dem
# section's data: uniform_1M pair_topography pair_autzen).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
OUT="${OUT:-/tmp/tincdt_gdal_grid}"

"$ROOT/cmake/setup.sh" python3-numpy python3-gdal gdal-bin time
build_bench_targets tincdt
/usr/bin/python3 "$SHARED/bench/gen.py" "$DATA" uniform_1M uniform_4M >/dev/null
/usr/bin/python3 "$ROOT/tests/bench/compare_gdal_grid.py" "$BUILD/tincdt" "$SHARED" "$DATA" "$OUT" "$@"
