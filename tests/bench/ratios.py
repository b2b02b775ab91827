#!/usr/bin/env python3
"""Reads bench_run.py's markdown table and prints tincdt / CGAL time ratios per dataset."""
import sys

rows = {}
for line in open(sys.argv[1]):
    cells = [c.strip() for c in line.strip().strip("|").split("|")]
    if len(cells) < 9 or cells[0] in ("dataset", "---") or not cells[3][:1].isdigit():
        continue
    rows[(cells[0], cells[1])] = cells

print("| dataset | tincdt | CGAL | time ratio (tincdt / CGAL) | tincdt B/pt |")
print("|---|---|---|---|---|")
for (ds, tool), c in rows.items():
    if not tool.startswith("tincdt"):
        continue
    peer = [v for (d, t), v in rows.items() if d == ds and t.startswith("cgal")]
    if not peer:
        print("| %s | %s %s s | - | - | %s |" % (ds, tool, c[3], c[8]))
        continue
    p = peer[0]
    print("| %s | %s %s s | %s %s s | %.2f | %s |" % (
        ds, tool, c[3], p[1], p[3], float(c[3]) / float(p[3]), c[8]))
