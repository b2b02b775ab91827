#!/usr/bin/env bash
# The determinism check at full size: one input built four ways — --threads 1, --threads 2,
# its points shuffled (as XYZ), and 16 tile jobs merged — must give the same triangle set
# (triangle_set.py: exact corner coordinates, any vertex or face order).
#
#   tests/bench/determinism_check.sh BUILD_DIR WORK_DIR NAME TILE_SIZE POINTS [LINE OPTIONS...]
#   e.g. tests/bench/determinism_check.sh build/release /tmp/det grid_4M 500 /tmp/tinbench/grid_4M/points.xyz
#
# POINTS is an XYZ or LAS file (LAS: point formats 0-5, class 2 kept with --keep-class 2 in
# LINE OPTIONS); TILE_SIZE is chosen by the caller so that the plan has 4 x 4 tiles (BUFFER: the
# plan's buffer, default 25). Prints one
# markdown row: name, triangles, the four digests, and whether they agree. Exit 1 if they do not.
set -euo pipefail
(($# >= 5)) || { sed -n '2,12p' "$0" >&2; exit 2; }
build=$(cd "$1" && pwd) work=$2 name=$3 side=$4 points=$(realpath "$5")
shift 5
opts=("$@")
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
tincdt=$build/tincdt
dir=$work/$name
rm -rf "$dir" && mkdir -p "$dir/out"
cd "$dir"

keep2=0
for o in "${opts[@]}"; do [[ $o == --keep-class ]] && keep2=1; done

"$tincdt" "$points" "${opts[@]}" --threads 1 -o t1.ply -q
"$tincdt" "$points" "${opts[@]}" --threads 2 -o t2.ply -q

# The same points as exact XYZ text, shuffled (a fixed seed: the run is repeatable).
/usr/bin/python3 - "$points" shuffled.xyz "$keep2" <<'EOF'
import sys
import numpy as np
src, dst, keep2 = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
if src.lower().endswith(".las"):
    b = open(src, "rb").read()
    offset = int.from_bytes(b[96:100], "little")
    fmt, length = b[104] & 0x3F, int.from_bytes(b[105:107], "little")
    count = int.from_bytes(b[107:111], "little")
    if count == 0 and b[25] >= 4:
        count = int.from_bytes(b[247:255], "little")
    if fmt > 5:
        sys.exit("determinism_check: LAS point formats 0-5 only")
    scale = np.frombuffer(b, "<f8", 3, 131)
    off = np.frombuffer(b, "<f8", 3, 155)
    rec = np.frombuffer(b, np.uint8, count * length, offset).reshape(count, length)
    xyz = rec[:, :12].copy().view("<i4").reshape(count, 3) * scale + off
    if keep2:
        xyz = xyz[(rec[:, 15] & 0x1F) == 2]
else:
    xyz = np.loadtxt(src, usecols=(0, 1, 2))
np.random.default_rng(13).shuffle(xyz)
with open(dst, "w") as f:
    for x, y, z in xyz.tolist():
        f.write(f"{x!r} {y!r} {z!r}\n")
EOF
line_opts=()  # the shuffled XYZ has no classes: drop the class filter, keep the lines and CRS
skip=0
for o in "${opts[@]}"; do
  if ((skip)); then skip=0; continue; fi
  if [[ $o == --keep-class ]]; then skip=1; continue; fi
  line_opts+=("$o")
done
"$tincdt" shuffled.xyz "${line_opts[@]}" -o shuffled.ply -q

"$tincdt" plan "$points" "${opts[@]}" --tile-size "$side" --buffer "${BUFFER:-25}" -o plan.json -q
n=$(sed -n 's/^  "tile_count": \([0-9]*\),$/\1/p' plan.json)
seq 0 $((n - 1)) | parallel -j 2 "$tincdt" --plan plan.json --tile {} -o out/tile_{}.ply -q --threads 1
"$tincdt" merge out/tile_*.ply -o tiled.ply -q

mapfile -t rows < <(/usr/bin/python3 "$here/triangle_set.py" t1.ply t2.ply shuffled.ply tiled.ply)
digests=() triangles=()
for r in "${rows[@]}"; do read -r t d _ <<<"$r"; triangles+=("$t"); digests+=("$d"); done
same=yes
for d in "${digests[@]}"; do [[ $d == "${digests[0]}" ]] || same=NO; done
echo "| $name | ${triangles[0]} | ${digests[0]} | ${digests[1]} | ${digests[2]} | ${digests[3]} ($n tiles) | $same |"
[[ $same == yes ]]
