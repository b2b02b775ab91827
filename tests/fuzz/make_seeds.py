#!/usr/bin/env python3
"""Writes the seed corpora of the fuzz targets (tests/fuzz/seeds/<target>/) from data/sample.*
and, when present, ../shared/data (see its PROVENANCE.md): small valid inputs of every kind the
readers know, which the fuzzers then mutate. The seeds are committed; run this again after
adding a kind of input.

Usage: tests/fuzz/make_seeds.py [OUT_DIR]   (default: tests/fuzz/seeds; needs ogr2ogr)
"""
import json
import os
import struct
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "data")
OUT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "tests", "fuzz", "seeds")
LAS_BUDGET = 1024  # bytes of point records kept per LAS seed


def write(target, name, data):
    d = os.path.join(OUT, target)
    os.makedirs(d, exist_ok=True)
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)


def las_seed(path):
    """The header, VLRs, the first points and the EVLRs of a LAS file, counts patched."""
    b = open(path, "rb").read()
    minor, header_size = b[25], struct.unpack_from("<H", b, 94)[0]
    offset, record = struct.unpack_from("<I", b, 96)[0], struct.unpack_from("<H", b, 105)[0]
    count = struct.unpack_from("<I", b, 107)[0]
    if minor >= 4 and header_size >= 375 and struct.unpack_from("<Q", b, 247)[0]:
        count = struct.unpack_from("<Q", b, 247)[0]
    keep = max(3, min(count, LAS_BUDGET // record))
    head = bytearray(b[:offset])
    points = b[offset:offset + keep * record]
    struct.pack_into("<I", head, 107, keep if count < 2**32 else 0)
    evlrs = b""
    if minor >= 4 and header_size >= 375:
        struct.pack_into("<Q", head, 247, keep)
        start, n = struct.unpack_from("<QI", b, 235)
        if n and start and len(b) - start <= 16 * 1024:
            evlrs = b[start:]
            struct.pack_into("<Q", head, 235, offset + len(points))
        else:
            struct.pack_into("<QI", head, 235, 0, 0)
    return bytes(head) + points + evlrs


def xyz_seeds():
    yield "plain.xyz", b"0 0 1\n10 0 2\n0 10 3\n10 10 4\n5 5 2.5\n"
    yield "header_csv.csv", b"x,y,z,intensity\n1.5,2.5,3.5,10\n4,5,6,11\n-7e2,+8,0.5,12\n"
    yield "semicolon_header.txt", b'"Z";"Y";"X"\n1;2;3\n4;5;6\n'
    yield "comments_crlf.xyz", b"\xef\xbb\xbf# survey\r\n\r\nX Y Z\r\n1 2 3 # end\r\n4\t5\t6\r\n"
    yield "signed_zero.xyz", b"5 5 1\n-0 -0 2\n0 0 3\n5 0 0\n"
    for name in ("Topography_ground.xyz", "autzen-bmx-largersample.csv"):
        path = os.path.join(SHARED, "xyz", name)
        if os.path.exists(path):
            with open(path, "rb") as f:
                yield name, b"".join(f.readline() for _ in range(40))


def ogr_geojson(path, limit):
    """The first LIMIT features of a vector file as GeoJSON text, coordinates to 2 decimals."""
    cmd = ["ogr2ogr", "-f", "GeoJSON", "/vsistdout/", path, "-limit", str(limit),
           "-lco", "COORDINATE_PRECISION=2", "-lco", "RFC7946=NO"]
    return subprocess.run(cmd, check=True, capture_output=True).stdout


def collection(geometries):
    features = [{"type": "Feature", "properties": {"elev": 10.0 + i}, "geometry": g}
                for i, g in enumerate(geometries)]
    return json.dumps({"type": "FeatureCollection", "features": features}).encode()


def polygon(*rings, z=None):
    def ring(r):
        pts = [list(p) + ([z] if z is not None else []) for p in r]
        return pts + [pts[0]]
    return {"type": "Polygon", "coordinates": [ring(r) for r in rings]}


def line(*pts):
    return {"type": "LineString", "coordinates": [list(p) for p in pts]}


# Byte 0 of a vector_fuzz input: bits 0-2 the role (0 contours, 1 hard lines, 2 soft lines,
# 3 clip, 4 erase, 5 replace, 6 contours + clip, 7 hard lines + erase), bits 3-4 the restoration
# (0 Delaunay, 1 aspect, 2 none), bit 5 --on-crossing error, bit 6 lines without points,
# bit 7 --fix-flats (with contours) or --max-edge.
def vector_seeds():
    box = [(0, 0), (100, 0), (100, 100), (0, 100)]
    bowtie = [(10, 10), (90, 90), (90, 10), (10, 90)]
    hole = [(30, 30), (30, 60), (60, 60), (60, 30)]
    shapes = {
        "box": collection([polygon(box)]),
        "box_3d": collection([polygon(box, z=800)]),
        "bowtie": collection([polygon(bowtie)]),
        "bowtie_3d": collection([polygon(bowtie, z=12.5)]),
        "hole": collection([polygon(box, hole)]),
        "overlap": collection([polygon([(0, 0), (60, 0), (60, 60), (0, 60)], z=5),
                               polygon([(40, 40), (100, 40), (100, 100), (40, 100)], z=7)]),
        "spike": collection([polygon([(20, 20), (80, 20), (80, 80), (200, 80), (80, 80), (20, 80)])]),
        "multi": json.dumps({"type": "Feature", "properties": {}, "geometry": {
            "type": "MultiPolygon", "coordinates": [
                polygon(box)["coordinates"], polygon(hole, z=None)["coordinates"]]}}).encode(),
    }
    for name, doc in shapes.items():
        for role in (3, 4, 5, 6, 7):
            yield f"{name}_role{role}", bytes([role]) + doc
    lines = collection([line((0, 0, 10), (100, 100, 10)), line((0, 100, 20), (100, 0, 20)),
                        line((10, 50, 15), (50, 50, 15), (50, 50, 15), (90, 51, 15)),
                        line((20, 20, 5), (80, 20, 5), (80, 80, 5), (20, 80, 5), (20, 20, 5))])
    for mode in (0, 1, 2, 0x08, 0x10, 0x20, 0x40, 0x80, 0x48):
        yield f"crossing_lines_mode{mode:02x}", bytes([mode]) + lines
    bow_line = collection([line((10, 10, 1), (90, 90, 1), (90, 10, 1), (10, 90, 1), (10, 10, 1))])
    yield "bowtie_contour_aspect", bytes([0x08]) + bow_line
    sources = [os.path.join(ROOT, "data", "sample_contours.shp")]
    for name in ("contours/elev_lux_contours_25m.shp",
                 "pair_topography/Topography_contours_1m_3d.shp"):
        if os.path.exists(os.path.join(SHARED, name)):
            sources.append(os.path.join(SHARED, name))
    for path in sources:
        doc = ogr_geojson(path, 2)
        stem = os.path.splitext(os.path.basename(path))[0]
        for mode in (0, 0x88):
            yield f"{stem}_mode{mode:02x}", bytes([mode]) + doc


def copc_seed(path, max_level=2):
    """A COPC file of at most 32 KiB (run.sh's -max_len) from a real one: its header and VLRs,
    the chunks of the nodes down to MAX_LEVEL, no chunk table (the whole read walks the chunks),
    and the hierarchy split into a root page and one child page per level-1 node."""
    b = open(path, "rb").read()
    offset_to_points = struct.unpack_from("<I", b, 96)[0]
    info = 375 + 54  # the COPC info VLR's payload comes first
    root_offset, root_size = struct.unpack_from("<QQ", b, info + 40)
    entries = [struct.unpack_from("<4iQii", b, root_offset + 32 * i) for i in range(root_size // 32)]
    nodes = sorted((e for e in entries if 0 < e[6] and e[0] <= max_level), key=lambda e: e[4])
    out = bytearray(b[:offset_to_points]) + struct.pack("<q", 0)
    moved = {}
    for e in nodes:
        moved[e[:4]] = len(out)
        out += b[e[4]:e[4] + e[5]]
    def entry(e, offset=None, size=None, count=None):
        return struct.pack("<4iQii", *e[:4], moved[e[:4]] if offset is None else offset,
                           e[5] if size is None else size, e[6] if count is None else count)
    evlr = len(out)
    out += struct.pack("<H16sHQ32s", 0, b"copc", 1000, 0, b"")
    pages = bytearray()
    children = []
    for top in (e for e in nodes if e[0] == 1):
        page = b"".join(entry(e) for e in nodes
                        if e[0] >= 1 and (e[1] >> (e[0] - 1), e[2] >> (e[0] - 1),
                                          e[3] >> (e[0] - 1)) == top[1:4])
        children.append((top, len(out) + len(pages), len(page)))
        pages += page
    root = b"".join(entry(e) for e in nodes if e[0] == 0)
    root += b"".join(entry(t, offset, size, -1) for t, offset, size in children)
    root_at = len(out) + len(pages)
    pages += root
    out += pages
    struct.pack_into("<Q", out, evlr + 20, len(pages))
    struct.pack_into("<QQ", out, info + 40, root_at, len(root))
    struct.pack_into("<QI", out, 235, evlr, 1)
    struct.pack_into("<Q", out, 247, sum(e[6] for e in nodes))
    assert len(out) <= 32768, len(out)
    return bytes(out)


def main():
    write_las = [os.path.join(ROOT, "data", "sample.las")]
    las_dir = os.path.join(SHARED, "las")
    if os.path.isdir(las_dir):
        write_las += sorted(os.path.join(las_dir, n) for n in os.listdir(las_dir)
                            if n.endswith(".las"))
    for path in write_las:
        write("las_fuzz", os.path.basename(path), las_seed(path))
    copc = os.path.join(SHARED, "laz", "simple.copc.laz")
    if os.path.exists(copc):
        write("laz_fuzz", "simple_levels_0_2.copc.laz", copc_seed(copc))
    for name, data in xyz_seeds():
        write("xyz_fuzz", name, data)
    for name, data in vector_seeds():
        write("vector_fuzz", name + ".bin", data)


if __name__ == "__main__":
    main()
