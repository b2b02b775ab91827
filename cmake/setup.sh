#!/usr/bin/env bash
# Installs what tincdt needs to build, test and format, from Debian 12 (bookworm) packages.
# Idempotent: when everything is installed it only checks, quickly, and changes nothing.
# Runs apt-get as root, or through sudo otherwise.
# Usage: cmake/setup.sh [EXTRA_PACKAGE...]   (the benchmark script adds CGAL and friends; the
# fuzz step of .ci/run adds clang libclang-rt-14-dev)
set -euo pipefail

# Keep in step with README.md ("Dependencies").
packages=(
  cmake g++ ninja-build pkg-config      # build tools
  libgdal-dev gdal-bin                  # GDAL/OGR/OSR (readers, writers, CRS); ogrinfo, gdalinfo
  libcli11-dev libspdlog-dev            # command line, logging
  libgtest-dev libgmock-dev             # tests
  libbenchmark-dev                      # benchmarks
  clang-format                          # format check
  libxml2-utils                         # xmllint: the LandXML test validates against the schema
  parallel                              # GNU parallel: the tiled-jobs recipe and its CI test
)
packages+=("$@")

say() { printf 'setup.sh: %s\n' "$*"; }
die() { printf 'setup.sh: error: %s\n' "$*" >&2; exit 1; }

if ! command -v dpkg-query >/dev/null 2>&1 || ! command -v apt-get >/dev/null 2>&1; then
  die "apt-get/dpkg-query not found: this script is for Debian 12 (or a close relative).
  Install these packages (or their equivalents) by hand: ${packages[*]}"
fi

missing=()
for pkg in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ $status == "install ok installed" ]] || missing+=("$pkg")
done

if ((${#missing[@]} == 0)); then
  say "all ${#packages[@]} packages are installed"
  exit 0
fi

if ((EUID == 0)); then
  as_root=()
elif command -v sudo >/dev/null 2>&1; then
  as_root=(sudo)
  # Without a terminal sudo cannot ask for a password: fail at once rather than hang.
  [[ -t 0 ]] || as_root=(sudo -n)
else
  die "missing: ${missing[*]}
  Installing needs root, and sudo is not available. As root, run:
    apt-get update && apt-get install -y --no-install-recommends ${missing[*]}"
fi

say "installing: ${missing[*]}"
apt=("${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get -q -o DPkg::Lock::Timeout=300)
"${apt[@]}" update ||
  die "apt-get update failed (network? sudo password? see above)"
"${apt[@]}" install -y --no-install-recommends "${missing[@]}" ||
  die "apt-get install failed for: ${missing[*]}"

# Check again: a package that apt-get skipped silently must not pass for installed.
still=()
for pkg in "${missing[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null || true)
  [[ $status == "install ok installed" ]] || still+=("$pkg")
done
((${#still[@]} == 0)) || die "still not installed: ${still[*]}"
say "installed: ${missing[*]}"
