#!/usr/bin/env bash
# tincdt's LAZ decoder beside laz-perf (its npm WASM build, ../shared/bench/node) on the same
# files in one session. ROUNDS rounds, round-robin: laz-perf, tincdt on one thread, tincdt on
# every core; each run decodes every point REPEAT times and reports its best time. Per file it
# prints the median rates and the median of the per-round rate ratios (tincdt / laz-perf), and
# fails if the checksums (the sum of the raw X, Y, Z integers) disagree.
#
#   tests/bench/compare_lazperf.sh                       # autzen_trim.laz and a 4.4M-point copy
#   BIG_COPIES=0 ROUNDS=3 tests/bench/compare_lazperf.sh FILE.laz ...
#
# Environment: TINCDT_SHARED (default ../shared beside the repo), TINCDT_BENCH_BUILD
# (build/test), ROUNDS (5), REPEAT (5), THREADS (all cores: nproc), BIG_COPIES (20: tiles of
# autzen_trim's full chunks in a larger file made by make_big_laz, 0 = none), BIG_DIR
# (/tmp/tincdt_laz).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
bench_defaults ROUNDS=5 REPEAT=5 THREADS="$(nproc)" BIG_COPIES=20 BIG_DIR=/tmp/tincdt_laz
LAZPERF="$SHARED/bench/node/lazperf_decode.mjs"

[[ -d $SHARED/bench/node/node_modules/laz-perf ]] || npm install --prefix "$SHARED/bench/node"
build_test_targets laz_bench make_big_laz
BENCH="$BUILD/tests/bench/laz_bench"

files=("$@")
if ((${#files[@]} == 0)); then
  files=("$SHARED/data/laz/autzen_trim.laz")
  if ((BIG_COPIES > 0)); then
    mkdir -p "$BIG_DIR"
    big="$BIG_DIR/autzen_x$BIG_COPIES.laz"
    [[ -f $big ]] || "$BUILD/tests/bench/make_big_laz" "$SHARED/data/laz/autzen_trim.laz" \
      "$BIG_COPIES" "$big" "$SHARED/data/las/autzen_trim.las" "${big%.laz}.las"
    files+=("$big")
  fi
fi

results="$(mktemp /tmp/tincdt_lazperf.XXXXXX)"
trap 'rm -f "$results"' EXIT
for ((round = 1; round <= ROUNDS; ++round)); do
  for f in "${files[@]}"; do
    echo "round $round: $(basename "$f")" >&2
    printf '%s\tlaz-perf\t%s\n' "$f" "$(node "$LAZPERF" "$f" "$REPEAT" | grep '^RESULT')" >>"$results"
    printf '%s\ttincdt-1\t%s\n' "$f" "$("$BENCH" "$f" --threads 1 --repeat "$REPEAT" 2>/dev/null)" >>"$results"
    printf '%s\ttincdt-%s\t%s\n' "$f" "$THREADS" \
      "$("$BENCH" "$f" --threads "$THREADS" --repeat "$REPEAT" 2>/dev/null)" >>"$results"
  done
done

/usr/bin/python3 - "$results" <<'EOF'
import collections, os, statistics, sys

runs = collections.defaultdict(list)  # (file, tool) -> [fields per round]
for line in open(sys.argv[1]):
    path, tool, result = line.rstrip("\n").split("\t")
    fields = dict(kv.split("=", 1) for kv in result.split()[1:])
    runs[(path, tool)].append(fields)

status = 0
print("| file | points | laz-perf pts/s | tincdt | tincdt pts/s | ratio (median of rounds) |")
print("|---|---|---|---|---|---|")
for path in dict.fromkeys(p for p, _ in runs):
    peer = runs[(path, "laz-perf")]
    for tool in sorted(t for p, t in runs if p == path and t != "laz-perf"):
        mine = runs[(path, tool)]
        if {r["checksum"] for r in mine} != {r["checksum"] for r in peer}:
            print("CHECKSUM MISMATCH on %s: %s vs laz-perf %s" % (
                path, mine[0]["checksum"], peer[0]["checksum"]), file=sys.stderr)
            status = 1
        ratios = [float(m["points_per_s"]) / float(p["points_per_s"]) for m, p in zip(mine, peer)]
        print("| %s | %s | %.0f | %s threads | %.0f | %.2f (%s) |" % (
            os.path.basename(path), mine[0]["points"],
            statistics.median(float(p["points_per_s"]) for p in peer), tool.split("-")[1],
            statistics.median(float(m["points_per_s"]) for m in mine),
            statistics.median(ratios), " ".join("%.2f" % r for r in ratios)))
sys.exit(status)
EOF
