#!/usr/bin/env bash
# The README's quick start is what CI runs. README.md has one fenced block under "## Quick start"
# holding exactly two commands: 1 installs the dependencies, builds the release preset and runs
# tincdt on the sample; 2 builds and runs the whole test suite. This script takes them from there,
# so the README cannot drift from what CI does, and fails loudly when the block is missing or
# mangled (a code formatter once turned `cmake/setup.sh` into `cmake / setup.sh`).
#   cmake/readme_commands.sh check      check README.md (exit 0) and print the two commands
#   cmake/readme_commands.sh print N    print command N (1 or 2)
#   cmake/readme_commands.sh run N      run command N with bash from the repository root
#   --readme FILE (before the action)   read FILE instead of README.md (the tests do)
# On any problem: one line "readme_commands.sh: FILE:LINE: what is wrong" on stderr, exit 1
# (2 for a usage error).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
me=readme_commands.sh

usage() {
  echo "$me: $1 (try --help)" >&2
  exit 2
}

readme="$root/README.md"
while (($#)); do
  case "$1" in
    --readme) (($# >= 2)) || usage "--readme needs a file"; readme=$2; shift 2 ;;
    -h | --help) sed -n '2,11p' "${BASH_SOURCE[0]}"; exit 0 ;;
    *) break ;;
  esac
done
action=${1:-}
case "$action" in
  check) (($# == 1)) || usage "check takes no argument" ;;
  print | run)
    (($# == 2)) || usage "$action needs the command's number, 1 or 2"
    [[ $2 == 1 || $2 == 2 ]] || usage "no command '$2': the quick start has commands 1 and 2"
    ;;
  "") usage "no action: check, print N or run N" ;;
  *) usage "unknown action '$action'" ;;
esac

fail() {  # fail LINE "what is wrong"
  echo "$me: $readme:$1: $2" >&2
  exit 1
}

[[ -f $readme ]] || fail 0 "no such file"
mapfile -t lines <"$readme"

# ---- find the block: the one fence under "## Quick start", before the next "## " heading ----
heading=-1
in_fence=0
for ((i = 0; i < ${#lines[@]}; ++i)); do
  line=${lines[i]%$'\r'}
  if [[ $line =~ ^[[:space:]]*(\`\`\`|~~~) ]]; then
    in_fence=$((!in_fence))
  elif ((!in_fence)) && [[ $line =~ ^#{1,6}[^#[:space:]] ]]; then
    # "#tincdt": Markdown needs a space after the #s; what a code formatter leaves behind.
    fail $((i + 1)) "heading without a space after '#': '$line' (was a code formatter run over it?)"
  elif ((!in_fence)) && [[ $line =~ ^##[[:space:]]+Quick\ start[[:space:]]*$ ]]; then
    heading=$i
  fi
done
((heading >= 0)) || fail 0 "no '## Quick start' heading"

open=-1
close=-1
for ((i = heading + 1; i < ${#lines[@]}; ++i)); do
  line=${lines[i]%$'\r'}
  if ((open < 0)); then
    [[ $line =~ ^#{1,2}[[:space:]] ]] && break  # the next section: no block in this one
    [[ $line =~ ^[[:space:]]*(\`\`\`|~~~) ]] || continue
    [[ $line =~ ^(\`\`\`|~~~)(sh|bash|shell|console)?[[:space:]]*$ ]] ||
      fail $((i + 1)) "the quick-start fence must open alone on its line as \`\`\`sh, not '$line'"
    open=$i
  elif [[ $line =~ ^[[:space:]]*(\`\`\`|~~~)[[:space:]]*$ ]]; then
    close=$i
    break
  elif [[ $line =~ ^[[:space:]]*(\`\`\`|~~~). || $line =~ ^##[[:space:]] ]]; then
    fail $((open + 1)) "the quick-start block is never closed (line $((i + 1)) starts something else: '$line')"
  fi
done
((open >= 0)) || fail $((heading + 1)) "no fenced block under '## Quick start'"
((close >= 0)) || fail $((open + 1)) "the quick-start block is never closed"
for ((i = close + 1; i < ${#lines[@]}; ++i)); do
  line=${lines[i]%$'\r'}
  [[ $line =~ ^#{1,2}[[:space:]] ]] && break
  [[ $line =~ ^[[:space:]]*(\`\`\`|~~~) ]] &&
    fail $((i + 1)) "a second fenced block under '## Quick start': the quick start is one block"
done

# ---- the commands: non-blank, non-comment lines, with backslash continuations joined ----
commands=()
starts=()
pending=""
for ((i = open + 1; i < close; ++i)); do
  line=${lines[i]%$'\r'}
  if [[ -z $pending ]]; then
    [[ $line =~ ^[[:space:]]*(#.*)?$ ]] && continue
    starts+=($((i + 1)))
  fi
  if [[ $line == *\\ ]]; then
    pending+="${line%\\} "
    continue
  fi
  commands+=("$pending$line")
  pending=""
done
[[ -z $pending ]] || fail $close "the last command ends in a backslash"
((${#commands[@]} == 2)) ||
  fail $((open + 1)) "the quick-start block holds ${#commands[@]} commands, not 2 (1: install, build, run the sample; 2: build and run the tests)"

# ---- each command: plain shell, not the marks of a formatter ----
for n in 1 2; do
  cmd=${commands[n - 1]}
  at=${starts[n - 1]}
  if ! err=$(bash -n -c "$cmd" 2>&1); then
    fail "$at" "command $n does not parse as shell: ${err//$'\n'/ }"
  fi
  if [[ $cmd =~ (^|[^-])--[[:space:]]+[[:alnum:]] ]]; then
    fail "$at" "command $n has '-- word' (an option torn apart, as in 'cmake-- workflow'): $cmd"
  fi
  if [[ $cmd =~ [[:alnum:]_.][[:space:]]+-[[:space:]]+[[:alnum:]] ]]; then
    fail "$at" "command $n has 'word - word' (an option torn apart, as in '- o'): $cmd"
  fi
  if [[ $cmd =~ [[:alnum:]_.][[:space:]]+/[[:space:]]*[[:alnum:]_.] ||
    $cmd =~ [[:alnum:]_.][[:space:]]*/[[:space:]]+[[:alnum:]_.] ]]; then
    fail "$at" "command $n has a path torn apart at a '/' (as in 'cmake / setup.sh'): $cmd"
  fi
done

case "$action" in
  check) printf '%s\n' "${commands[@]}" ;;
  print) printf '%s\n' "${commands[$2 - 1]}" ;;
  run)
    printf '+ %s\n' "${commands[$2 - 1]}" >&2
    cd "$root"
    exec bash -e -o pipefail -c "${commands[$2 - 1]}"
    ;;
esac
