#!/usr/bin/env bash
# Fuzzes each target (or the ones named) for SECONDS, one after the other, starting from its
# seeds, its regression inputs and the corpus earlier runs grew (build/fuzz/corpus/<target>,
# kept between runs). A crash, a hang (> 10 s), a sanitizer report or more than 2 GB of memory
# stops that target, leaves the input in build/fuzz/artifacts/<target>/ and fails the script:
# fix it, and keep the input as tests/fuzz/regressions/<target>/<name> (replayed by CTest).
# Usage, after `cmake --workflow --preset fuzz`:  tests/fuzz/run.sh SECONDS [TARGET...]
# FUZZ_TIMEOUT=S raises the hang limit (wall clock) when several targets share the cores.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
seconds=${1:?usage: tests/fuzz/run.sh SECONDS [TARGET...]}
shift
bin=build/fuzz/tests/fuzz
targets=("$@")
if ((${#targets[@]} == 0)); then
  for exe in "$bin"/*_fuzz; do targets+=("$(basename "$exe")"); done
fi
((${#targets[@]} > 0)) || { echo "run.sh: no fuzz targets in $bin (build the fuzz preset)" >&2; exit 1; }

failed=()
for t in "${targets[@]}"; do
  corpus=build/fuzz/corpus/$t
  artifacts=build/fuzz/artifacts/$t/
  mkdir -p "$corpus" "$artifacts"
  printf '\n== %s: %s s\n' "$t" "$seconds"
  shared=()  # seeds the project may not copy (see tests/fuzz/CMakeLists.txt)
  [[ $t == laz_fuzz && -d ../shared/data/laz ]] && shared=(../shared/data/laz)
  # New inputs go to the first directory; seeds and regressions are only read.
  if ! "$bin/$t" -max_total_time="$seconds" -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb=2048 -max_len=32768 \
      -print_final_stats=1 -artifact_prefix="$artifacts" \
      "$corpus" "tests/fuzz/seeds/$t" "tests/fuzz/regressions/$t" "${shared[@]}"; then
    failed+=("$t")
  fi
done
if ((${#failed[@]} > 0)); then
  echo "run.sh: findings in: ${failed[*]} (inputs in build/fuzz/artifacts/)" >&2
  exit 1
fi
