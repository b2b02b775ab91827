# Sourced by the comparison scripts: where the repository, the shared data, the generated
# benchmark data and the tincdt build are, each overridable from the environment.
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
SHARED="${TINCDT_SHARED:-$ROOT/../shared}"
DATA="${TINBENCH_DATA:-/tmp/tinbench}"
BUILD="${TINCDT_BENCH_BUILD:-$ROOT/build/bench}"
