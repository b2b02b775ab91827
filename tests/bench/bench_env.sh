# Sourced by the comparison scripts: where the repository, the shared data, the generated
# benchmark data and the tincdt build are, each overridable from the environment.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SHARED="${TINCDT_SHARED:-$ROOT/../shared}"
DATA="${TINBENCH_DATA:-/tmp/tinbench}"
BUILD="${TINCDT_BENCH_BUILD:-$ROOT/build/bench}"

# bench_defaults NAME=VALUE...: each NAME as the environment gives it, else VALUE.
bench_defaults() {
  local setting
  for setting in "$@"; do
    local name=${setting%%=*}
    [[ -n ${!name:-} ]] || printf -v "$name" '%s' "${setting#*=}"
  done
}

# build_test_targets TARGET...: BUILD becomes the test tree ($TINCDT_BENCH_BUILD, default
# build/test, configured by the test preset when it is not yet), where TARGET... are built.
build_test_targets() {
  BUILD="${TINCDT_BENCH_BUILD:-$ROOT/build/test}"
  if [[ ! -f $BUILD/build.ninja ]]; then cmake --preset test -S "$ROOT" >/dev/null; fi
  cmake --build "$BUILD" --target "$@" >/dev/null
}

# build_bench_targets TARGET...: configures BUILD as a Release tree with the tests and the bench
# programs (one configuration for every script that shares BUILD, so none rebuilds the others'
# targets by flipping an option) and builds TARGET... on every core.
build_bench_targets() {
  cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DTINCDT_BUILD_TESTS=ON \
    -DTINCDT_BUILD_BENCH=ON >/dev/null
  cmake --build "$BUILD" -j"$(nproc)" --target "$@" >/dev/null
}
