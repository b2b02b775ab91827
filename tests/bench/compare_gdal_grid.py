#!/usr/bin/env python3
"""tincdt's products against GDAL on the same data, in one session (see compare_gdal_grid.sh).

  dem       tincdt --dem vs gdal_grid -a linear on the same points and grid: both timed as a
            user runs them (the whole command, Float32, tincdt's COG and gdal_grid's GTiff;
            round-robin, REPEAT times, medians of wall and CPU time); then both again in
            Float64, cells compared where both have a value: cells that differ by more than
            1e-6 are counted, then counted again against gdal_grid on the points shifted to the
            origin (qhull's roundoff at map coordinates is not a tie; what remains is a
            cocircular tie: the Delaunay triangulation is not unique there).
  rmse      the pairs: tincdt's DEM of the ground points, without and with the pair's contours as
            hard lines, against the pair's reference DTM (RMSE, max |diff|).
  contours  pair_topography at 1 m: tincdt --contour-lines vs gdal_contour on tincdt's own 0.5 m
            DEM of the same TIN (lines, closed, total length).
  cog       gdalinfo of a tincdt DEM: the COG layout, the CRS, tiles, overviews.
  job       one uniform_4M job writing DEM + contours + LandXML + GeoPackage: time, peak memory,
            each stage's share (from --stats).
Usage: compare_gdal_grid.py TINCDT SHARED DATA OUT [SECTION...]   (default: all)
"""
import json
import os
import statistics
import subprocess
import sys

import numpy as np
from osgeo import gdal, ogr

gdal.UseExceptions()
TINCDT, SHARED, DATA, OUT = sys.argv[1:5]
SECTIONS = sys.argv[5:] or ["dem", "rmse", "contours", "cog", "job"]
REPEAT = int(os.environ.get("REPEAT", "1"))
os.makedirs(OUT, exist_ok=True)

# name: points, CRS, extent (xmin ymin xmax ymax), cell size; the pairs' grids are those of
# their reference DTMs (../shared/data/PROVENANCE.md).
CASES = {
    "uniform_1M": (f"{DATA}/uniform_1M/points.xyz", "EPSG:32611",
                   (500000, 4000000, 510000, 4010000), 1.0),
    "pair_topography": (f"{SHARED}/data/xyz/Topography_ground.xyz", "EPSG:2949",
                        (273358, 5274358, 273642, 5274642), 2.0),
    "pair_autzen": (f"{SHARED}/data/xyz/autzen_trim_ground.xyz", "EPSG:2994",
                    (636002, 848938, 637178, 849496), 6.0),
}
PAIRS = {
    "pair_topography": (f"{SHARED}/data/pair_topography/Topography_ground_dtm_2m.tif",
                        f"{SHARED}/data/pair_topography/Topography_contours_1m_3d.shp"),
    "pair_autzen": (f"{SHARED}/data/pair_autzen/autzen_trim_ground_dtm_6ft.tif",
                    f"{SHARED}/data/pair_autzen/autzen_trim_contours_2ft_3d.shp"),
}
NODATA = -9999.0
if os.environ.get("CASES"):  # e.g. CASES="pair_topography pair_autzen"
    CASES = {k: v for k, v in CASES.items() if k in os.environ["CASES"].split()}


def timed(cmd, with_cpu=False):
    """Runs CMD under /usr/bin/time: (wall seconds, peak KiB[, CPU seconds])."""
    r = subprocess.run(["/usr/bin/time", "-f", "TIME %e %M %U %S"] + cmd, capture_output=True,
                       text=True)
    if r.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), r.stderr))
    last = [l for l in r.stderr.splitlines() if l.startswith("TIME ")][-1].split()
    if with_cpu:
        return float(last[1]), int(last[2]), float(last[3]) + float(last[4])
    return float(last[1]), int(last[2])


def vrt_for(points, name, shift=(0.0, 0.0)):
    """A CSV + VRT that gdal_grid reads the XYZ points from (shifted by -SHIFT)."""
    csv = f"{OUT}/{name}.csv"
    with open(points) as src, open(csv, "w") as dst:
        dst.write("x,y,z\n")
        for line in src:
            x, y, z = line.split()[:3]
            if shift == (0.0, 0.0):
                dst.write(f"{x},{y},{z}\n")
            else:
                dst.write("%.17g,%.17g,%s\n" % (float(x) - shift[0], float(y) - shift[1], z))
    vrt = f"{OUT}/{name}.vrt"
    with open(vrt, "w") as f:
        f.write(f'<OGRVRTDataSource><OGRVRTLayer name="{name}"><SrcDataSource>{csv}'
                '</SrcDataSource><GeometryType>wkbPoint25D</GeometryType><GeometryField '
                'encoding="PointFromColumns" x="x" y="y" z="z"/></OGRVRTLayer></OGRVRTDataSource>')
    return vrt


def gdal_grid_cmd(vrt, extent, cell, out, srs=None, shift=(0.0, 0.0), cell_type="Float64"):
    x0, y0, x1, y1 = extent
    w, h = int(round((x1 - x0) / cell)), int(round((y1 - y0) / cell))
    cmd = ["gdal_grid", "-q", "-zfield", "z", "-a", "linear:radius=0:nodata=%g" % NODATA,
           "-txe", repr(x0 - shift[0]), repr(x1 - shift[0]),
           "-tye", repr(y1 - shift[1]), repr(y0 - shift[1]),
           "-outsize", str(w), str(h), "-ot", cell_type, "-of", "GTiff"]
    if srs:
        cmd += ["-a_srs", srs]
    return cmd + [vrt, out]


def tincdt_dem_cmd(points, srs, extent, cell, dem, extra=(), cell_type="Float64"):
    return [TINCDT, points, "--a-srs", srs, "-o", f"{OUT}/tin.ply", "--overwrite", "-q",
            "--dem", dem, "--resolution", repr(cell), "--dem-extent"] + \
        [repr(v) for v in extent] + ["--dem-type", cell_type] + list(extra)


def read(path):
    ds = gdal.Open(path)
    return ds.GetGeoTransform(), ds.GetRasterBand(1).ReadAsArray().astype(np.float64)


def compare(a_path, b_path, a_nodata=NODATA, b_nodata=NODATA):
    ga, a = read(a_path)
    gb, b = read(b_path)
    assert all(abs(p - q) < 1e-9 for p, q in zip(ga, gb)), (ga, gb)
    va, vb = a != a_nodata, b != b_nodata
    both = va & vb
    d = np.abs(a - b)[both]
    return {"both": int(both.sum()), "only_a": int((va & ~vb).sum()),
            "only_b": int((vb & ~va).sum()), "max": float(d.max()) if d.size else 0.0,
            "over_1e-6": int((d > 1e-6).sum()), "rmse": float(np.sqrt(np.mean(d * d)))}


def section_dem():
    print("## DEM: tincdt --dem vs gdal_grid -a linear (same points, same grid)\n")
    print("Timed: the whole command as a user runs it, Float32 (tincdt: COG, DEFLATE, overviews; "
          "gdal_grid: plain GTiff). Compared: both again in Float64.\n")
    print("| data | cells | tincdt s (CPU s) | gdal_grid s (CPU s) | speed-up wall (CPU) "
          "| tincdt MiB | gdal_grid MiB | both valued | max diff | > 1e-6 "
          "| > 1e-6 vs gdal_grid at origin (ties) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for name, (points, srs, extent, cell) in CASES.items():
        if not os.path.exists(points):
            print(f"| {name} | missing {points} |")
            continue
        vrt = vrt_for(points, name)
        t_runs, g_runs = [], []
        for _ in range(REPEAT):  # round-robin, so both see the same machine
            td, gg = f"{OUT}/{name}_tincdt32.tif", f"{OUT}/{name}_gdal_grid32.tif"
            t_runs.append(timed(tincdt_dem_cmd(points, srs, extent, cell, td, (), "Float32"),
                                True))
            if os.path.exists(gg):
                os.remove(gg)
            g_runs.append(timed(gdal_grid_cmd(vrt, extent, cell, gg, srs, (0.0, 0.0), "Float32"),
                                True))
        td, gg = f"{OUT}/{name}_tincdt.tif", f"{OUT}/{name}_gdal_grid.tif"
        subprocess.run(tincdt_dem_cmd(points, srs, extent, cell, td), check=True)
        if os.path.exists(gg):
            os.remove(gg)
        subprocess.run(gdal_grid_cmd(vrt, extent, cell, gg, srs), check=True)
        c = compare(td, gg)
        # gdal_grid again on the points moved to the origin: what still differs is a tie.
        shift = (float(extent[0]) // 1000 * 1000, float(extent[1]) // 1000 * 1000)
        vrt_s = vrt_for(points, name + "_origin", shift)
        gg_s = f"{OUT}/{name}_gdal_grid_origin.tif"
        if os.path.exists(gg_s):
            os.remove(gg_s)
        subprocess.run(gdal_grid_cmd(vrt_s, extent, cell, gg_s, None, shift), check=True)
        ds = gdal.Open(gg_s, gdal.GA_Update)  # put it back at map coordinates to compare
        gt = list(ds.GetGeoTransform())
        gt[0] += shift[0]
        gt[3] += shift[1]
        ds.SetGeoTransform(gt)
        ds = None
        cs = compare(td, gg_s)
        ts = statistics.median(r[0] for r in t_runs)
        gs = statistics.median(r[0] for r in g_runs)
        tc = statistics.median(r[2] for r in t_runs)
        gc = statistics.median(r[2] for r in g_runs)
        tm = max(r[1] for r in t_runs) / 1024
        gm = max(r[1] for r in g_runs) / 1024
        x0, y0, x1, y1 = extent
        cells = int(round((x1 - x0) / cell)) * int(round((y1 - y0) / cell))
        print(f"| {name} | {cells:,} | {ts:.2f} ({tc:.2f}) | {gs:.2f} ({gc:.2f}) "
              f"| {gs / ts:.1f}x ({gc / tc:.1f}x) | {tm:.0f} | {gm:.0f} "
              f"| {c['both']:,} (+{c['only_a']}/{c['only_b']} one side) | {c['max']:.3g} "
              f"| {c['over_1e-6']:,} | {cs['over_1e-6']:,} (max {cs['max']:.3g}) |")
        sys.stdout.flush()
    print()


def section_rmse():
    print("## DEM vs the pairs' reference DTM, without and with the pair's contours as hard "
          "lines\n")
    print("| pair | cells | RMSE without | max without | RMSE with contours | max with |")
    print("|---|---|---|---|---|---|")
    # name: the points as tincdt arguments, the DEM grid, the reference DTM and its nodata, the
    # contours. The derived pairs' DTMs are the linear grid of the same ground points, and their
    # contours are traced on that grid: without contours tincdt is all but the reference itself.
    # The lidR pair's DTM was made independently (by lidR's authors); its contours come from it.
    pairs = {name: ([CASES[name][0], "--a-srs", CASES[name][1]], CASES[name][2], CASES[name][3],
                    dtm, NODATA, contours) for name, (dtm, contours) in PAIRS.items()}
    pairs["Topography_lidR2016 (independent DTM)"] = (
        [f"{SHARED}/data/laz/Topography_lidR2016.laz", "--keep-class", "2"],
        (684800.5, 5018000.5, 685150.5, 5018300.5), 1.0,
        f"{SHARED}/data/dem/Topography_lidR2016_dtm.tif", -32768.0,
        f"{SHARED}/data/contours/Topography_lidR2016_contours_2m_3d.shp")
    for k, (name, (points, extent, cell, dtm, dtm_nodata, contours)) in enumerate(pairs.items()):
        rows = []
        for extra in ([], ["--hard-lines", contours]):
            dem = f"{OUT}/pair{k}_rmse_{len(extra)}.tif"
            cmd = [TINCDT] + points + ["-o", f"{OUT}/tin.ply", "--overwrite", "-q", "--dem", dem,
                                       "--resolution", repr(cell), "--dem-extent"] + \
                [repr(v) for v in extent] + ["--dem-type", "Float64"] + extra
            subprocess.run(cmd, check=True)
            rows.append(compare(dem, dtm, b_nodata=dtm_nodata))
        a, b = rows
        print(f"| {name} | {a['both']:,} | {a['rmse']:.4f} | {a['max']:.3f} | {b['rmse']:.4f} "
              f"| {b['max']:.3f} |")
    print()


def line_stats(path, box=None):
    """Lines, closed lines, total length, and the length inside BOX (x0, y0, x1, y1)."""
    clip = None
    if box:
        ring = ogr.Geometry(ogr.wkbLinearRing)
        for x, y in ((box[0], box[1]), (box[2], box[1]), (box[2], box[3]), (box[0], box[3]),
                     (box[0], box[1])):
            ring.AddPoint_2D(x, y)
        clip = ogr.Geometry(ogr.wkbPolygon)
        clip.AddGeometry(ring)
    ds = ogr.Open(path)
    n = closed = 0
    length = inside = 0.0
    for f in ds.GetLayer(0):
        g = f.GetGeometryRef().Clone()
        g.FlattenTo2D()
        n += 1
        closed += 1 if g.GetPointCount() > 2 and g.GetPoint(0) == g.GetPoint(
            g.GetPointCount() - 1) else 0
        length += g.Length()
        if clip is not None:
            c = g.Intersection(clip)
            inside += 0.0 if c is None or c.IsEmpty() else c.Length()
    return n, closed, length, inside


def section_contours():
    print("## Contours at 1 m on pair_topography: traced on the TIN vs gdal_contour on tincdt's "
          "0.5 m DEM of the same TIN\n")
    points, srs, extent, _ = CASES["pair_topography"]
    lines, dem = f"{OUT}/topo_contours.gpkg", f"{OUT}/topo_dem_05.tif"
    t = timed([TINCDT, points, "--a-srs", srs, "-o", f"{OUT}/tin.ply", "--overwrite", "-q",
               "--contour-lines", lines, "--interval", "1", "--dem", dem, "--resolution", "0.5",
               "--dem-extent"] + [repr(v) for v in extent] +
              ["--dem-type", "Float64"])[0]
    gc = f"{OUT}/topo_gdal_contour.gpkg"
    if os.path.exists(gc):
        os.remove(gc)
    g = timed(["gdal_contour", "-q", "-a", "elev", "-i", "1", "-f", "GPKG", dem, gc])[0]
    # The raster's contours can only reach its outer cell centres; the TIN's also run through
    # the thin hull triangles beyond them.
    box = (extent[0] + 0.25, extent[1] + 0.25, extent[2] - 0.25, extent[3] - 0.25)
    print("| | lines | closed | total length (m) | length within the DEM's cell centres (m) "
          "| time s |")
    print("|---|---|---|---|---|---|")
    for label, path, s in (("tincdt --contour-lines (on the TIN)", lines, t),
                           ("gdal_contour on tincdt's 0.5 m DEM", gc, g)):
        n, closed, length, inside = line_stats(path, box)
        print(f"| {label} | {n:,} | {closed:,} | {length:,.1f} | {inside:,.1f} | {s:.2f} |")
    print("\n(tincdt's time includes reading, triangulating and the 0.5 m DEM)\n")


def section_cog():
    print("## gdalinfo of tincdt's DEM (pair_topography, default Float32)\n")
    points, srs, extent, cell = CASES["pair_topography"]
    dem = f"{OUT}/topo_cog.tif"
    subprocess.run([TINCDT, points, "--a-srs", srs, "-o", f"{OUT}/tin.ply", "--overwrite", "-q",
                    "--dem", dem, "--resolution", "0.25", "--tap"], check=True)
    info = subprocess.run(["gdalinfo", dem], capture_output=True, text=True).stdout
    keep = [l for l in info.splitlines()
            if any(k in l for k in ("Size is", "LAYOUT", "COMPRESSION", "Block=", "Overviews",
                                    "NoData", 'ID["EPSG"', "PROJCRS["))]
    print("```\n" + "\n".join(keep) + "\n```\n")


def section_job():
    print("## One job on uniform_4M: DEM (1 m) + contours (10 m) + LandXML + GeoPackage\n")
    points = f"{DATA}/uniform_4M/points.xyz"
    if not os.path.exists(points):
        print(f"missing {points}\n")
        return
    stats = f"{OUT}/job.json"
    base = [TINCDT, points, "--a-srs", "EPSG:32611", "--overwrite", "-q", "--dem",
            f"{OUT}/job_dem.tif", "--resolution", "1", "--tap", "--contour-lines",
            f"{OUT}/job_contours.gpkg", "--interval", "10", "--stats", stats]
    rows = []
    for out in ("job.xml", "job.gpkg"):  # -o takes one TIN: LandXML, then GeoPackage
        s, kib = timed(base + ["-o", f"{OUT}/{out}"])
        rows.append((out, s, kib, json.load(open(stats))))
    for out, s, kib, j in rows:
        print(f"-o {out}: {s:.1f} s, peak {kib / 1024:.0f} MiB; stages: " +
              ", ".join("%s %.1f s (%.0f%%)" % (st["name"], st["seconds"],
                                                100 * st["seconds"] / s)
                        for st in j["stages"]))
        sizes = {o["kind"]: o["bytes"] for o in j["outputs"]}
        print("  sizes: " + ", ".join("%s %.0f MiB" % (k, v / 2**20) for k, v in sizes.items()))
    print()


for section in SECTIONS:
    globals()["section_" + section]()
