#!/usr/bin/env python3
"""An icosphere as a Wavefront OBJ (scenes/ball.obj: the render mesh of scenes/ball.json).

    make-icosphere.py SUBDIVISIONS RADIUS CX CY CZ > FILE.obj

The icosahedron's triangles split in four SUBDIVISIONS times, every vertex pushed onto the
sphere; triangles counter-clockwise seen from outside, coordinates to 5 decimals.
"""
import math
import sys

levels, radius, cx, cy, cz = int(sys.argv[1]), *map(float, sys.argv[2:6])
t = (1 + 5 ** 0.5) / 2
points = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
          (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
points = [tuple(c / math.sqrt(sum(d * d for d in p)) for c in p) for p in points]
for _ in range(levels):
    middles, split = {}, []

    def middle(a, b):
        key = (min(a, b), max(a, b))
        if key not in middles:
            m = [(p + q) / 2 for p, q in zip(points[a], points[b])]
            length = math.sqrt(sum(c * c for c in m))
            points.append(tuple(c / length for c in m))
            middles[key] = len(points) - 1
        return middles[key]

    for a, b, c in faces:
        ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
        split += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    faces = split
print(f"# icosphere: {levels} subdivisions, radius {radius:g} around ({cx:g}, {cy:g}, {cz:g}),"
      f" {len(points)} vertices, {len(faces)} triangles (scripts/make-icosphere.py)")
for x, y, z in points:
    print(f"v {cx + radius * x:.5f} {cy + radius * y:.5f} {cz + radius * z:.5f}")
for a, b, c in faces:
    print(f"f {a + 1} {b + 1} {c + 1}")
