#!/usr/bin/env bash
# The web-terrain pyramid's cost beside the plain TIN job on a large synthetic LAS: make_big_las
# writes N points, then ROUNDS rounds (the order alternating) of
#   tincdt big.las -o x.ply           (the TIN to a binary PLY)
#   tincdt big.las --terrain DIR      (the pyramid alone, its default levels)
# each under /usr/bin/time -v. Prints every run (wall seconds, CPU seconds (user + system: a
# shared machine disturbs them less), peak RSS, bytes a point) and the levels the pyramid chose,
# then the per-round ratios terrain / PLY; removes the big files at the end (KEEP=1 keeps them).
#
#   tests/bench/terrain_bench.sh
#
# Environment: TINCDT (the tincdt to time; default build/release's), TINCDT_BENCH_BUILD
# (build/test: make_big_las), N (20000000), ROUNDS (2), BIG_DIR (/tmp/tincdt_terrain_bench),
# KEEP (0).
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
bench_defaults TINCDT="$ROOT/build/release/tincdt" N=20000000 ROUNDS=2 \
  BIG_DIR=/tmp/tincdt_terrain_bench KEEP=0

if [[ ! -x $TINCDT ]]; then
  echo "no $TINCDT: cmake --preset release && cmake --build build/release" >&2
  exit 1
fi
build_test_targets make_big_las

mkdir -p "$BIG_DIR"
[[ $KEEP == 1 ]] || trap 'rm -rf "$BIG_DIR"' EXIT
big="$BIG_DIR/big_$N.las"
[[ -f $big ]] || "$BUILD/tests/bench/make_big_las" "$N" "$big"

runs="$BIG_DIR/runs.txt"
: > "$runs"
# run ROUND JOB: one tincdt job under /usr/bin/time -v, its PLY removed after. The pyramids stay
# until the end: ext4 creates files slowly for minutes after many were deleted (it skips inodes
# deleted recently), which would charge one round's removal to the next round's pyramid.
run() {
  local round=$1 job=$2 out args
  if [[ $job == ply ]]; then
    out="$BIG_DIR/x.ply"
    args=(-o "$out")
  else
    out="$BIG_DIR/terrain_$round"
    rm -rf "$out"
    args=(--terrain "$out")
  fi
  /usr/bin/time -v "$TINCDT" "$big" "${args[@]}" > "$BIG_DIR/log" 2>&1
  local wall rss cpu
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ {n = split($2, p, ":"); s = 0;
    for (i = 1; i <= n; ++i) s = s * 60 + p[i]; print s}' "$BIG_DIR/log")
  rss=$(awk -F': ' '/Maximum resident set size/ {print $2}' "$BIG_DIR/log")
  cpu=$(awk -F': ' '/(User|System) time \(seconds\)/ {s += $2} END {printf "%.1f", s}' \
    "$BIG_DIR/log")
  echo "round=$round job=$job wall_s=$wall cpu_s=$cpu peak_rss_kb=$rss" \
    "bytes_per_point=$(awk -v r="$rss" -v n="$N" 'BEGIN {printf "%.1f", r * 1024 / n}')" |
    tee -a "$runs"
  if [[ $job == terrain ]]; then
    grep -E "terrain: levels|terrain level" "$BIG_DIR/log" || true
  else
    rm -f "$out" "${out%.ply}.prj"
  fi
}
for ((round = 0; round < ROUNDS; ++round)); do
  if ((round % 2 == 0)); then run "$round" ply; run "$round" terrain; else
    run "$round" terrain; run "$round" ply; fi
done

rm -rf "$BIG_DIR"/terrain_*

echo
awk '{for (i = 1; i <= NF; ++i) {split($i, kv, "="); f[kv[1]] = kv[2]}
      key = f["round"]; if (f["job"] == "ply") {pw[key] = f["wall_s"]} else {tw[key] = f["wall_s"]}}
     END {for (r in pw) if (r in tw)
            printf "round %s: terrain / ply wall = %.2f\n", r, tw[r] / pw[r]}' \
  "$runs"
