#!/usr/bin/env bash
# The tiled-job scale run: a synthetic LAS tiling made by make_tiles, planned and
# built tile by tile with GNU parallel, every seam checked from the tiles' outlines, a 2 x 2 block
# of tiles also checked from its PLY files, and a table of the figures.
#
#   tests/bench/tiles_run.sh BUILD_DIR WORK_DIR COLS ROWS POINTS SIDE [BUFFER]
#   e.g. tests/bench/tiles_run.sh build/release /data/run 10 10 10000000 1000 25   (1e9 points)
#
# Writes WORK_DIR/las (the input: POINTS * 20 bytes per file), WORK_DIR/plan.json, and per tile
# WORK_DIR/out/tile_N.outline.ply, tile_N.tif (its DEM, kept: RESOLUTION, default 1, must divide
# SIDE) and tile_N.time (wall seconds, peak RSS KiB); the DEM tiles are joined by
# WORK_DIR/out/dem.vrt (gdalbuildvrt). Each tile's PLY is deleted once its outline is written
# (keep them with KEEP_TILES=1), except the four tiles of the sample block. JOBS (default 2) tile
# jobs at once, THREADS (default 1) threads each; TILE_OPTIONS (split on spaces) go to every tile
# job, e.g. TILE_OPTIONS="--max-error 0.1 --clip /data/area.gpkg". The input is reused when
# present; delete WORK_DIR when done.
set -euo pipefail
(($# >= 6)) || { sed -n '2,16p' "$0" >&2; exit 2; }
build=$(cd "$1" && pwd)
work=$2 cols=$3 rows=$4 points=$5 side=$6 buffer=${7:-25}
tincdt=$build/tincdt
make_tiles=$build/tests/bench/make_tiles
jobs=${JOBS:-2} threads=${THREADS:-1} resolution=${RESOLUTION:-1}
mkdir -p "$work/las" "$work/out"
cd "$work"
count=$((cols * rows))
say() { printf '%s  %s\n' "$(date +%T)" "$*"; }

if (($(find las -name 'tile_*.las' | wc -l) != count)); then
  say "generating $count tiles of $points points"
  seq 0 $((count - 1)) | parallel -j "$jobs" "$make_tiles" "$cols" "$rows" "$points" "$side" las {} {}
fi
say "input: $(du -sh las | cut -f1); load: $(uptime | sed 's/.*load average: //')"

start=$(date +%s.%N)
/usr/bin/time -f '%e %M' -o plan.time "$tincdt" plan las/tile_*.las --tile-size "$side" \
  --buffer "$buffer" -o plan.json --overwrite
n=$(sed -n 's/^  "tile_count": \([0-9]*\),$/\1/p' plan.json)
say "plan: $n tiles, $(cut -d' ' -f1 plan.time) s, rim $(wc -l < plan.rim.xyz) points"

# The sample block: the 2 x 2 tiles around the middle of the plan (rows north to south).
mid_row=$((rows / 2 - 1)) mid_col=$((cols / 2 - 1))
block=()
for r in $mid_row $((mid_row + 1)); do
  for c in $mid_col $((mid_col + 1)); do block+=($((r * cols + c))); done
done
keep=" ${block[*]} "

tile_job() {  # tile_job N: build tile N, keep its outline and DEM, delete its PLY unless kept
  local t=$1
  /usr/bin/time -f '%e %M' -o "out/tile_$t.time" "$tincdt" --plan plan.json --tile "$t" \
    -o "out/tile_$t.ply" --outline "out/tile_$t.outline.ply" \
    --dem "out/tile_$t.tif" --resolution "$resolution" --threads "$threads" --overwrite -q \
    ${TILE_OPTIONS:-}
  du -k "out/tile_$t.ply" | cut -f1 >"out/tile_$t.kib"
  if [[ ${KEEP_TILES:-0} != 1 && $keep != *" $t "* ]]; then rm -f "out/tile_$t.ply" "out/tile_$t.prj"; fi
}
export -f tile_job
export tincdt threads keep resolution TILE_OPTIONS
( while sleep 60; do
    du -sk . | cut -f1 >>out/disk.log
    say "running: $(ls out/*.time 2>/dev/null | wc -l)/$n done; disk $(du -sh . | cut -f1); load $(uptime | sed 's/.*load average: //')"
  done ) &
watcher=$!
seq 0 $((n - 1)) | parallel -j "$jobs" --halt now,fail=1 --joblog out/joblog.tsv tile_job {}
# Stop the watcher by ending its sleep (its loop then ends): a sleep left behind would hold the
# script's output open for up to a minute.
pkill -P "$watcher" sleep || true
wait "$watcher" || true
du -sk . | cut -f1 >>out/disk.log  # a run shorter than a minute has one sample
built=$(date +%s.%N)
say "tiles built in $(echo "$built - $start" | bc) s (plan included)"

# The DEM tiles joined: each covers its tile exactly on one lattice of cells, so the VRT is the
# whole area's DEM; gdalinfo -stats reads every cell of it.
/usr/bin/time -f '%e %M' -o vrt.time gdalbuildvrt -q -overwrite out/dem.vrt out/tile_*.tif
vrt_size=$(gdalinfo out/dem.vrt | sed -n 's/^Size is \([0-9]*\), \([0-9]*\)$/\1 x \2/p')
if gdalinfo -stats out/dem.vrt >out/dem.vrt.info 2>&1; then
  vrt_stats="ok ($(sed -n 's/^ *Minimum=\([^,]*\), Maximum=\([^,]*\),.*/z \1 to \2/p' out/dem.vrt.info | head -1), $(sed -n 's/^ *STATISTICS_VALID_PERCENT=//p' out/dem.vrt.info | head -1)% of cells with a value)"
else
  vrt_stats="FAILED (out/dem.vrt.info)"
fi
say "DEM: out/dem.vrt, $vrt_size cells, gdalinfo -stats $vrt_stats"

outlines=()
for ((t = 0; t < n; ++t)); do outlines+=("out/tile_$t.outline.ply"); done
/usr/bin/time -f '%e %M' -o check.time "$tincdt" merge "${outlines[@]}" --check
# The block again, from its PLY files this time, in place of its tiles' own outlines.
block_plys=() others=()
for t in "${block[@]}"; do block_plys+=("out/tile_$t.ply"); done
for ((t = 0; t < n; ++t)); do [[ $keep == *" $t "* ]] || others+=("out/tile_$t.outline.ply"); done
"$tincdt" merge "${block_plys[@]}" --outline -o out/block.outline.ply --overwrite
"$tincdt" merge out/block.outline.ply "${others[@]}" --check

walls=$(cat out/tile_*.time | cut -d' ' -f1 | sort -n)
rss=$(cat out/tile_*.time | cut -d' ' -f2 | sort -n)
echo
echo "| figure | value |"
echo "|---|---|"
echo "| points | $((count * points)) in $count LAS files ($(du -sh las | cut -f1)) |"
echo "| tiles | $n of $side m, buffer $buffer m, $jobs jobs at once, $threads thread(s) each${TILE_OPTIONS:+, $TILE_OPTIONS} |"
echo "| plan | $(cut -d' ' -f1 plan.time) s, peak RSS $(($(cut -d' ' -f2 plan.time) / 1024)) MiB |"
echo "| wall time, plan + all tiles | $(echo "$built - $start" | bc | cut -d. -f1) s |"
echo "| tile job wall (min / median / max) | $(echo "$walls" | head -1) / $(echo "$walls" | sed -n "$(( (n + 1) / 2 ))p") / $(echo "$walls" | tail -1) s |"
echo "| tile job peak RSS (min / max) | $(($(echo "$rss" | head -1) / 1024)) / $(($(echo "$rss" | tail -1) / 1024)) MiB |"
echo "| TIN tile size (sum) | $(($(cat out/tile_*.kib | paste -sd+ | bc) / 1024 / 1024)) GiB |"
echo "| DEM tiles joined (gdalbuildvrt out/dem.vrt) | $vrt_size cells of $resolution m from $n tiles ($(du -ch out/tile_*.tif | tail -1 | cut -f1)), gdalinfo -stats $vrt_stats |"
echo "| seam check (all outlines) | $(cut -d' ' -f1 check.time) s, peak RSS $(($(cut -d' ' -f2 check.time) / 1024)) MiB |"
echo "| disk used: peak (sampled each minute) / at the end | $(($(sort -n out/disk.log | tail -1) / 1024 / 1024)) GiB / $(du -sh . | cut -f1) |"
