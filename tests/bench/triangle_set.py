#!/usr/bin/env python3
"""Prints the triangle count and a digest of the triangle set of binary PLY TINs written by tincdt:
each triangle as its three corners' exact (x, y, z), rotated to start at its lowest (x, y) corner
(orientation kept), the whole set sorted. Two TINs with the same digest have the same triangles,
whatever their vertex and face order.

Usage: triangle_set.py TIN.ply...     (one line per file: triangles, digest, name)
"""
import hashlib
import sys

import numpy as np


def read_ply(path):
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        body = f.read()
    if "format binary_little_endian 1.0" not in header:
        sys.exit(f"{path}: not a binary little-endian PLY")
    n_vertex = n_face = 0
    props = []
    element = None
    for line in header:
        w = line.split()
        if w[:1] == ["element"]:
            element = w[1]
            if element == "vertex":
                n_vertex = int(w[2])
            elif element == "face":
                n_face = int(w[2])
        elif w[:1] == ["property"] and element == "vertex":
            props.append((w[2], w[1]))
    if [p for p in props[:3]] != [("x", "double"), ("y", "double"), ("z", "double")]:
        sys.exit(f"{path}: expected double x, y, z")
    sizes = {"double": 8, "float": 4, "uchar": 1, "int": 4, "uint": 4, "ushort": 2, "short": 2}
    stride = sum(sizes[t] for _, t in props)
    raw = np.frombuffer(body, dtype=np.uint8, count=n_vertex * stride).reshape(n_vertex, stride)
    xyz = raw[:, :24].copy().view("<f8").reshape(n_vertex, 3)
    faces = np.frombuffer(body, dtype=np.uint8, offset=n_vertex * stride, count=n_face * 13)
    faces = faces.reshape(n_face, 13)
    if not (faces[:, 0] == 3).all():
        sys.exit(f"{path}: a face that is not a triangle")
    idx = faces[:, 1:].copy().view("<u4").reshape(n_face, 3)
    return xyz, idx


def digest(path):
    xyz, idx = read_ply(path)
    # Rank vertices by (x, y, z) so that comparing ranks compares coordinates.
    order = np.lexsort((xyz[:, 2], xyz[:, 1], xyz[:, 0]))
    rank = np.empty(len(order), dtype=np.int64)
    rank[order] = np.arange(len(order))
    r = rank[idx]
    first = np.argmin(r, axis=1)
    rows = np.arange(len(r))
    rot = np.stack([r[rows, first], r[rows, (first + 1) % 3], r[rows, (first + 2) % 3]], axis=1)
    rot = rot[np.lexsort((rot[:, 2], rot[:, 1], rot[:, 0]))]
    h = hashlib.sha256(xyz[order].tobytes())  # the vertices, sorted, then the triangles
    h.update(rot.tobytes())
    return len(idx), h.hexdigest()[:16]


for p in sys.argv[1:]:
    n, d = digest(p)
    print(f"{n} {d} {p}")
