#!/usr/bin/env python3
"""Reads bench_run.py's markdown table and prints, per dataset, tincdt / CGAL time ratios and
nanoseconds per point per core (CORES in the environment: the cores tincdt ran on; CGAL's
triangulation runs on one)."""
import os
import sys

cores = int(os.environ.get("CORES", "1"))
rows = {}
for line in open(sys.argv[1]):
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) < 9 or cells[0] in ("dataset", "---") or not cells[3][:1].isdigit():
        continue
    rows[(cells[0], cells[1])] = cells


def per_core(cells, n):
    """ns a point per core: the table's ns/pt times the cores used."""
    return "%d" % (float(cells[7]) * n) if cells[7][:1].isdigit() else "-"


print("| dataset | tincdt | CGAL | time ratio (tincdt / CGAL) | ns/pt/core tincdt (%d cores) "
      "| ns/pt/core CGAL | tincdt B/pt |" % cores)
print("|---|---|---|---|---|---|---|")
for (ds, tool), c in rows.items():
    if not tool.startswith("tincdt"):
        continue
    peer = [v for (d, t), v in rows.items() if d == ds and t.startswith("cgal")]
    if not peer:
        print("| %s | %s %s s | - | - | %s | - | %s |" % (ds, tool, c[3], per_core(c, cores), c[8]))
        continue
    p = peer[0]
    print("| %s | %s %s s | %s %s s | %.2f | %s | %s | %s |" % (
        ds, tool, c[3], p[1], p[3], float(c[3]) / float(p[3]), per_core(c, cores),
        per_core(p, 1), c[8]))
