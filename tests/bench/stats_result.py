#!/usr/bin/env python3
"""Prints a tincdt --stats JSON file as bench_run.py's RESULT line (tri_s = Delaunay stage)."""
import json
import sys

s = json.load(open(sys.argv[1]))
t = s["timings_s"]
print("RESULT tool=tincdt-job tri_s=%s triangles=%s n=%s total_s=%s read_s=%s write_s=%s" % (
    t["delaunay"], s["triangles"], s["points_read"], t["total"], t["read"], t["write"]))
