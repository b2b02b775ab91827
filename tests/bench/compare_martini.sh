#!/usr/bin/env bash
# The finest tiles of tincdt's web-terrain pyramid beside martini (npm @mapbox/martini, a regular
# grid's RTIN) on the same surface at the same maximum error, by vertex count.
#
# tincdt builds the pyramid of pair_topography (Topography.las ground + the 1 m 3D contours, the
# run of terrain_cli_test's PairTopographyLevels0To19) with --terrain-levels LEVELS and writes
# the full TIN beside it. Every tile of the finest level is decoded by
# @here/quantized-mesh-decoder (tests/cli/decode_pyramid.mjs) for its vertex count; the full TIN
# is sampled on the tile's rectangle as a SIZE x SIZE grid (terrain_tile_grids: the TIN's linear
# interpolation in longitude/latitude, the fill height 0 beyond the data, as the tiles have it),
# and martini meshes that grid at the level's geometric error (the error the tiles are built to,
# from the tincdt log). Prints a table a tile: tincdt's and martini's vertices, their ratio, each
# one's vertices on the tile's sides, the fraction of the tile inside the data, and both meshes'
# largest difference from the grid over its samples (martini_tiles.mjs: martini's own measure;
# tincdt builds its tiles to the error at the full TIN's vertices, so its figure on the grid may
# differ a little); then the median and largest ratio over all tiles and over the tiles wholly
# inside the data.
#
#   tests/bench/compare_martini.sh
#
# Environment: TINCDT_SHARED (default ../shared beside the repo: data/las/Topography.las,
# data/pair_topography, bench/node), TINCDT_BENCH_BUILD (build/test: tincdt and
# terrain_tile_grids), LEVELS (0-19), SIZE (257), CONTOURS (1; 0 builds from the ground points
# alone, to see what the contours cost the tiles). Needs node; the npm peers are installed into
# $TINCDT_SHARED/bench/node when missing.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/bench_env.sh"
bench_defaults LEVELS=0-19 SIZE=257 CONTOURS=1
NODE_MODULES="$SHARED/bench/node/node_modules"
level=${LEVELS#*-}

[[ -d $NODE_MODULES/@mapbox/martini && -d $NODE_MODULES/@here/quantized-mesh-decoder ]] ||
  npm install --prefix "$SHARED/bench/node" >&2
build_test_targets tincdt terrain_tile_grids

work=$(mktemp -d /tmp/compare_martini.XXXXXX)
trap 'rm -rf "$work"' EXIT
mkdir "$work/grids"
lines=()
contours="$SHARED/data/pair_topography/Topography_contours_1m_3d.shp"
[[ $CONTOURS == 0 ]] || lines=(--contours "$contours")

"$BUILD/tincdt" "$SHARED/data/las/Topography.las" --keep-class 2 "${lines[@]}" \
  -o "$work/full.ply" --terrain "$work/t" --terrain-levels "$LEVELS" 2> "$work/log"
allowed=$(sed -n "s/.*terrain level $level: .*(allowed \([0-9.e-]*\)).*/\1/p" "$work/log")
[[ -n $allowed ]] || { cat "$work/log" >&2; echo "no level $level in tincdt's log" >&2; exit 1; }
grep "terrain level $level:" "$work/log" >&2

node "$ROOT/tests/cli/decode_pyramid.mjs" "$NODE_MODULES" "$work/t" | grep "^$level/" \
  > "$work/tincdt.txt"
mapfile -t tiles < <(cut -d' ' -f1 "$work/tincdt.txt")
"$BUILD/tests/bench/terrain_tile_grids" "$work/full.ply" "$work/full.prj" 0 "$SIZE" \
  "$work/grids" "${tiles[@]}" > "$work/grids.txt"
grids=()
for t in "${tiles[@]}"; do grids+=("$work/grids/${t//\//_}.f32=$work/t/$t.terrain"); done
node "$ROOT/tests/bench/martini_tiles.mjs" "$NODE_MODULES" "$SIZE" "$allowed" "${grids[@]}" \
  > "$work/martini.txt"

echo "pair_topography level $level: $((${#tiles[@]})) tiles, max error $allowed m, martini on" \
  "${SIZE}x$SIZE grids"
/usr/bin/python3 - "$work/tincdt.txt" "$work/grids.txt" "$work/martini.txt" <<'EOF'
import re, statistics, sys
tincdt = {}
for line in open(sys.argv[1]):
    f = line.split()
    # Z/X/Y vertices triangles west south east north ...: the corners are on two sides each.
    tincdt[f[0]] = (int(f[1]), int(f[3]) + int(f[4]) + int(f[5]) + int(f[6]) - 4)
fields = lambda line: dict(re.findall(r"(\w+)=(\S+)", line))
inside = {g["tile"]: float(g["inside"]) for g in map(fields, open(sys.argv[2]))}
martini = [fields(line) for line in open(sys.argv[3])]
print("| tile | tincdt vertices | martini vertices | ratio | tincdt on sides | martini on sides "
      "| inside data | martini error | tincdt error |")
print("|---|---|---|---|---|---|---|---|---|")
ratios, interior, errors = [], [], []
for m in martini:
    tile = m["grid"].replace("_", "/")
    (tv, ts), mv = tincdt[tile], int(m["vertices"])
    r = tv / mv
    ratios.append(r)
    if inside[tile] == 1:
        interior.append(r)
        errors.append((float(m["max_error"]), float(m["tile_error"])))
    print(f"| {tile} | {tv} | {mv} | {r:.3f} | {ts} | {m['border']} | {inside[tile]:.2f} "
          f"| {float(m['max_error']):.3f} | {float(m['tile_error']):.3f} |")
tv = sum(tincdt[m["grid"].replace("_", "/")][0] for m in martini)
mv = sum(int(m["vertices"]) for m in martini)
print(f"\nall {len(ratios)} tiles: ratio median {statistics.median(ratios):.3f}, "
      f"max {max(ratios):.3f}, total {tv} / {mv} = {tv / mv:.3f}")
if interior:
    print(f"{len(interior)} tiles wholly inside the data: ratio median "
          f"{statistics.median(interior):.3f}, max {max(interior):.3f}; error on the grid, "
          f"median / max: martini {statistics.median(e[0] for e in errors):.3f} / "
          f"{max(e[0] for e in errors):.3f} m, tincdt {statistics.median(e[1] for e in errors):.3f}"
          f" / {max(e[1] for e in errors):.3f} m")
EOF
