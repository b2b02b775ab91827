#!/usr/bin/env bash
# Checks the module layering of src/ (docs/design.md, "One-way data flow").
#
# Every #include "X/..." in src/M/ must name a module X upstream of M or M itself, in the order
#   core < predicates < mesh < delaunay < constraints < terrain < simplify < products < io
#   < web_terrain < pipeline < tiles
# except that io may include only core, mesh and products (and io). apps/ and tests/ may
# include anything.
# Also from docs/design.md: GDAL headers only in src/io, no CLI11 anywhere in src/ (only apps/
# sees it), no spdlog in core or the algorithm modules, and no "../" includes that dodge the rules.
# Prints every offending line as FILE:LINE: ... and fails if there is one.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

order=(core predicates mesh delaunay constraints terrain simplify products io web_terrain pipeline
  tiles)
declare -A allowed
for ((i = 0; i < ${#order[@]}; ++i)); do
  allowed[${order[i]}]="${order[*]:0:i+1}"  # upstream of or equal to
done
allowed[io]="core mesh products io"
allowed[products]="core predicates mesh products"
no_spdlog="core predicates mesh delaunay constraints terrain simplify products"

is_in() {  # is_in WORD "LIST"
  [[ " $2 " == *" $1 "* ]]
}

[[ -d src ]] || { echo "check_layering.sh: no src/ directory"; exit 0; }

violations=0
report() {  # report "FILE:LINE: TEXT -- REASON"
  printf '%s\n' "$1"
  violations=$((violations + 1))
}

files=0
for dir in src/*/; do
  module=$(basename "$dir")
  if [[ -z ${allowed[$module]+set} ]]; then
    report "$dir: module '$module' is not in the layering order (${order[*]}); add it to cmake/check_layering.sh"
    continue
  fi
  while IFS= read -r -d '' file; do
    files=$((files + 1))
    # FILE:LINE:#include "path" (or <path>)
    while IFS= read -r hit; do
      [[ -n $hit ]] || continue
      lineno=${hit%%:*}
      text=${hit#*:}
      if [[ $text =~ \#[[:space:]]*include[[:space:]]*[\"\<]([^\"\>]+)[\"\>] ]]; then
        path=${BASH_REMATCH[1]}
      else
        continue
      fi
      where="$file:$lineno: $(printf '%s' "$text" | sed 's/^[[:space:]]*//')"
      first=${path%%/*}
      if [[ $path == ../* || $path == */../* ]]; then
        report "$where -- relative include; name the module: \"module/file.hpp\""
      elif [[ $path == */* && -n ${allowed[$first]+set} ]]; then
        if ! is_in "$first" "${allowed[$module]}"; then
          report "$where -- $module may include only: ${allowed[$module]}"
        fi
      elif [[ $path =~ ^(gdal|ogr|cpl_|gnm|ogrsf_frmts) ]]; then
        if [[ $module != io ]]; then report "$where -- GDAL headers belong in src/io only"; fi
      elif [[ $path == CLI/* ]]; then
        report "$where -- CLI11 belongs in apps/ only"
      elif [[ $path == spdlog/* ]]; then
        if is_in "$module" "$no_spdlog"; then
          report "$where -- no spdlog in $module (report through Progress / return values)"
        fi
      fi
    done < <(grep -nE '^[[:space:]]*#[[:space:]]*include[[:space:]]*["<]' "$file" || true)
  done < <(find "$dir" -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.cc' \) -print0 | LC_ALL=C sort -z)
done

if ((violations)); then
  echo
  echo "check_layering.sh: $violations violation(s) in src/ (order: ${order[*]}; io: core mesh products)"
  exit 1
fi
echo "check_layering.sh: $files files in src/ follow the layering (${order[*]})"
