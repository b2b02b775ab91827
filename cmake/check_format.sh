#!/usr/bin/env bash
# Checks that every *.cpp / *.hpp under src/ apps/ tests/ follows .clang-format.
#   cmake/check_format.sh          check; lists the files that differ and fails
#   cmake/check_format.sh --fix    reformat those files in place
# CLANG_FORMAT=clang-format-14 picks another binary.
# C++ files only, on purpose: never Markdown or any other prose. A formatter run over README.md
# once tore its commands apart (`cmake / setup.sh`); CI now runs those commands from it.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

fix=0
case "${1:-}" in
  "") ;;
  --fix) fix=1 ;;
  -h | --help) sed -n '2,5p' "${BASH_SOURCE[0]}"; exit 0 ;;
  *) echo "check_format.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac

clang_format=${CLANG_FORMAT:-clang-format}
command -v "$clang_format" >/dev/null 2>&1 ||
  { echo "check_format.sh: $clang_format not found; run cmake/setup.sh" >&2; exit 1; }

dirs=()
for d in src apps tests; do [[ -d $d ]] && dirs+=("$d"); done
files=()
if ((${#dirs[@]})); then
  mapfile -t files < <(find "${dirs[@]}" -type f \( -name '*.cpp' -o -name '*.hpp' \) | LC_ALL=C sort)
fi
if ((${#files[@]} == 0)); then
  echo "check_format.sh: no *.cpp/*.hpp files under src apps tests"
  exit 0
fi

bad=()
for f in "${files[@]}"; do
  if ((fix)); then
    "$clang_format" -i --style=file "$f"
  elif ! out=$("$clang_format" --dry-run --Werror --style=file "$f" 2>&1); then
    bad+=("$f")
    # The first few diagnostics show what differs; clang-format -i shows the rest.
    printf '%s\n' "$out" | head -n 6 || true
  fi
done

if ((fix)); then
  echo "check_format.sh: formatted ${#files[@]} files"
elif ((${#bad[@]})); then
  echo
  echo "check_format.sh: ${#bad[@]} of ${#files[@]} files do not follow .clang-format:"
  printf '  %s\n' "${bad[@]}"
  echo "fix with: cmake/check_format.sh --fix   (or clang-format -i FILE...)"
  exit 1
else
  echo "check_format.sh: all ${#files[@]} files follow .clang-format ($("$clang_format" --version | head -n 1))"
fi
