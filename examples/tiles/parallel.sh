#!/usr/bin/env bash
# Builds every tile of a tincdt plan with GNU parallel, on this machine or across hosts, then
# joins the tiles into one TIN.
#
#   examples/tiles/parallel.sh PLAN.json OUT_DIR [TINCDT_OPTION...]
#
# Writes OUT_DIR/tile_N.ply for each tile N, OUT_DIR/joblog.tsv (GNU parallel's job log: rerun
# with RESUME=1 to build only the tiles that failed or never ran), then OUT_DIR/merged.ply.
# TINCDT_OPTIONs go to every tile job (e.g. --stats, --offset auto; not the inputs: those are in
# the plan).
#
# Environment:
#   TINCDT    the tincdt binary (default: tincdt on PATH)
#   JOBS      jobs at once per host (parallel -j; default: one per core)
#   SSHLOGIN  run on other hosts too, e.g. "8/node1,8/node2,:" (":" is this one); every host must
#             see tincdt, the plan, its inputs and OUT_DIR at the same paths (shared storage)
#   MERGE     "whole" (default: merge into OUT_DIR/merged.ply), "check" (check the seams only,
#             for tiles too large to merge in one piece) or "none"
#   RESUME    1: skip the tiles the job log records as done
set -euo pipefail

if (($# < 2)); then
  sed -n '2,20p' "$0" >&2
  exit 2
fi
plan=$1
out=$2
shift 2
tincdt=${TINCDT:-tincdt}
command -v parallel >/dev/null || { echo "parallel.sh: GNU parallel is not installed" >&2; exit 1; }
# The plan writes its tile count on a line of its own.
count=$(sed -n 's/^  "tile_count": \([0-9]*\),$/\1/p' "$plan")
[[ -n $count ]] || { echo "parallel.sh: $plan: not a tincdt plan" >&2; exit 1; }
mkdir -p "$out"

hosts=()
[[ -n ${SSHLOGIN:-} ]] && hosts=(--sshlogin "$SSHLOGIN" --workdir "$PWD")
resume=()
[[ ${RESUME:-0} == 1 ]] && resume=(--resume-failed)
# -q: the command's words stay words (paths with blanks); --halt soon,fail=1: stop starting
# tiles after a failure, let the running ones finish.
seq 0 $((count - 1)) |
  parallel -q --halt soon,fail=1 --joblog "$out/joblog.tsv" "${resume[@]}" "${hosts[@]}" \
    -j "${JOBS:-100%}" \
    "$tincdt" --plan "$plan" --tile {} -o "$out/tile_{}.ply" --overwrite -q "$@"

tiles=()
for ((i = 0; i < count; ++i)); do tiles+=("$out/tile_$i.ply"); done
case ${MERGE:-whole} in
  whole) "$tincdt" merge "${tiles[@]}" -o "$out/merged.ply" --overwrite ;;
  check) "$tincdt" merge "${tiles[@]}" --check ;;
  none) ;;
  *) echo "parallel.sh: MERGE must be whole, check or none" >&2; exit 2 ;;
esac
