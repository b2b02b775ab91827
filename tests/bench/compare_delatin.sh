#!/usr/bin/env bash
# tincdt's simplification next to delatin (../shared/bench/node/delatin_run.mjs) on the same
# heights and tolerances, run round-robin in one session; prints every run and a table of
# medians: vertex counts, their ratio, time ratio (delatin / tincdt) and peak RSS. The time is
# each tool's own timing of the simplification (wall clock); the CPU time is the whole process's
# (user + system, reading the grid included, and with MODE=stage the untimed triangulation too),
# which a busy machine disturbs less.
#   tests/bench/compare_delatin.sh [BUILD_DIR] [ROUNDS]
# Grids: ../shared/bench gen.py's contours/dem.tif (1000 x 1000, made if missing) at 0.1, 0.5
# and 1 m, and a 4096 x 4096 synthetic terrain this script writes (smooth hills and four octaves
# of detail) at BIG_ERRORS (default 0.5). Environment: TINBENCH (default /tmp/tinbench), BIG_N,
# BIG_ERRORS, DEM_ERRORS, THREADS (tincdt's; default 0 = all cores), MODE (simplify_bench's:
# "points", the default, or "stage", what the pipeline's stage runs on the Delaunay TIN).
# Needs gdal-bin, python3-numpy, python3-gdal (cmake/setup.sh python3-numpy python3-gdal
# gdal-bin), node, and /usr/bin/time.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
build=${1:-$here/build/test}
rounds=${2:-3}
shared=$here/../shared/bench
data=${TINBENCH:-/tmp/tinbench}
big_n=${BIG_N:-4096}
dem_errors=${DEM_ERRORS:-"0.1 0.5 1"}
big_errors=${BIG_ERRORS:-0.5}
threads=${THREADS:-0}
mode=${MODE:-points}
bench=$build/tests/bench/simplify_bench
[[ -x $bench ]] || { echo "no $bench: cmake --build --preset test --target simplify_bench" >&2; exit 1; }

work=$(mktemp -d /tmp/compare_delatin.XXXXXX)
trap 'rm -rf "$work"' EXIT

if [[ ! -f $data/contours/dem.tif ]]; then
  /usr/bin/python3 "$shared/gen.py" "$data" contours >&2
fi
gdal_translate -q -of ENVI -ot Float32 "$data/contours/dem.tif" "$work/dem.f32"

big=$data/synthetic_${big_n}.f32
if [[ ! -f $big ]]; then
  /usr/bin/python3 - "$big" "$big_n" <<'EOF'
import sys
import numpy as np
path, n = sys.argv[1], int(sys.argv[2])
rng = np.random.default_rng([20261123, n])
u = np.linspace(0.0, 1.0, n)
z = 300 + 150 * np.sin(8.2 * u)[None, :] * np.cos(5.7 * u)[:, None]
z = z + 80 * np.sin(19.5 * u[None, :] + 14.5 * u[:, None])

def octave(cell, amplitude):
    # Random heights on a coarse lattice, bilinear between its nodes: detail at that scale.
    m = n // cell + 2
    coarse = rng.uniform(-amplitude, amplitude, (m, m))
    t = np.arange(n) / cell
    i = t.astype(int)
    f = t - i
    rows = coarse[:, i] * (1 - f) + coarse[:, i + 1] * f
    return rows[i, :] * (1 - f)[:, None] + rows[i + 1, :] * f[:, None]

for cell, amplitude in ((1024, 25.0), (256, 6.0), (64, 1.5), (16, 0.4)):
    z = z + octave(cell, amplitude)
z.astype("<f4").tofile(path)
EOF
fi

runs=$work/runs.txt
: > "$runs"
# run TAG GRID W H E: both tools once, each under /usr/bin/time -v, in alternating order.
run() {
  local tag=$1 grid=$2 w=$3 h=$4 e=$5 round=$6 order
  order="tincdt delatin"
  ((round % 2)) && order="delatin tincdt"
  for tool in $order; do
    if [[ $tool == tincdt ]]; then
      /usr/bin/time -v "$bench" "$grid" "$w" "$h" "$e" "$threads" "$mode" > "$work/out" 2> "$work/time"
    else
      /usr/bin/time -v node "$shared/node/delatin_run.mjs" "$grid" "$w" "$h" "$e" > "$work/out" \
        2> "$work/time"
    fi
    local line rss cpu
    line=$(grep '^RESULT' "$work/out")
    rss=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$work/time")
    cpu=$(awk -F: '/(User|System) time \(seconds\)/ {s += $2} END {printf "%.3f", s}' "$work/time")
    echo "$tag e=$e $tool $line peak_rss_kb=$rss process_cpu_s=$cpu" | tee -a "$runs"
  done
}
for ((round = 0; round < rounds; ++round)); do
  for e in $dem_errors; do run dem1000 "$work/dem.f32" 1000 1000 "$e" "$round"; done
  for e in $big_errors; do run "synthetic$big_n" "$big" "$big_n" "$big_n" "$e" "$round"; done
done

echo
/usr/bin/python3 - "$runs" <<'EOF'
import re, statistics, sys
rows = {}
for line in open(sys.argv[1]):
    tag, e, tool = line.split()[:3]
    f = dict(re.findall(r"(\w+)=([\d.]+)", line))
    r = rows.setdefault((tag, float(e[2:])), {}).setdefault(tool, [])
    r.append((float(f["run_s"]), int(f["vertices"]), float(f["achieved_max_error"]),
              int(f["peak_rss_kb"]), float(f["process_cpu_s"])))
print("| grid | max error | delatin vertices | tincdt vertices | ratio | delatin s | tincdt s "
      "| speed-up | CPU-time ratio | delatin peak MB | tincdt peak MB |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for (tag, e), tools in rows.items():
    d, t = tools["delatin"], tools["tincdt"]
    med = lambda xs, k: statistics.median(x[k] for x in xs)
    # The speed-up is the median of the per-round ratios (each round runs both back to back).
    speed = statistics.median(a[0] / b[0] for a, b in zip(d, t))
    cpu = statistics.median(a[4] / b[4] for a, b in zip(d, t))
    print(f"| {tag} | {e:g} | {d[0][1]} | {t[0][1]} | {t[0][1] / d[0][1]:.3f} | "
          f"{med(d, 0):.3f} | {med(t, 0):.3f} | {speed:.2f}x | {cpu:.2f}x | "
          f"{med(d, 3) / 1024:.0f} | {med(t, 3) / 1024:.0f} |")
EOF
