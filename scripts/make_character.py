#!/usr/bin/env python3
"""Writes data/character.obj: a gingerbread-man-like character for prm/character.prm.

The outline is a simple polygon in the x-z plane (x to the right, z up, in
meters): legs apart with flat feet on z = 0, arms stretched out sideways and
a round head on top. It is extruded along y into a prism of depth DEPTH, so
the surface is closed and watertight: both caps are triangulated by ear
clipping and every outline edge carries one side quad (two triangles).
Triangles are oriented with outward normals.

The bounding box is x in [0.005, 0.475], y in [0, 0.12], z in [0, 0.64]: it
fits the 48 x 12 x 64 grid of 0.01 m voxels of prm/character.prm, whose
'Fit to grid = false' takes these coordinates as meters.

Usage: python3 scripts/make_character.py [output] (by default the
repository's data/character.obj)
Standard library only.
"""

import math
import os
import sys

DEPTH = 0.12  # extrusion along y (m)
CENTER = 0.24  # mirror line x = CENTER
HEAD_CENTER = (CENTER, 0.555)
HEAD_RADIUS = 0.085
HEAD_SEGMENTS = 24  # segments of the half circle from the neck to the top


def right_half():
    """Outline of the right half (x >= CENTER), counterclockwise, from the
    crotch up to (and without) the top of the head."""
    pts = [
        (0.240, 0.200),  # crotch
        (0.285, 0.000),  # inner edge of the right foot
        (0.400, 0.000),  # sole of the right foot
        (0.415, 0.010),
        (0.420, 0.030),
        (0.410, 0.050),  # toe
        (0.360, 0.240),  # hip
        (0.350, 0.300),  # waist
        (0.355, 0.360),  # armpit
        (0.420, 0.370),  # underside of the arm
        (0.450, 0.375),
        (0.468, 0.388),  # hand
        (0.475, 0.410),
        (0.470, 0.435),
        (0.450, 0.452),
        (0.400, 0.457),  # top of the arm
        (0.330, 0.470),  # shoulder
    ]
    # Head: circle from the neck (angle -70 degrees) up to the top (90).
    a0, a1 = math.radians(-70), math.radians(90)
    cx, cz = HEAD_CENTER
    for s in range(HEAD_SEGMENTS):
        a = a0 + (a1 - a0) * s / HEAD_SEGMENTS
        pts.append((cx + HEAD_RADIUS * math.cos(a), cz + HEAD_RADIUS * math.sin(a)))
    return pts


def outline():
    """Full counterclockwise outline: right half, head top, mirrored left half."""
    right = right_half()
    top = (CENTER, HEAD_CENTER[1] + HEAD_RADIUS)
    left = [(2 * CENTER - x, z) for (x, z) in reversed(right[1:])]
    return [right[0]] + right[1:] + [top] + left


def signed_area(poly):
    return 0.5 * sum(
        poly[i][0] * poly[(i + 1) % len(poly)][1]
        - poly[(i + 1) % len(poly)][0] * poly[i][1]
        for i in range(len(poly))
    )


def cross(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def segments_cross(p1, p2, p3, p4):
    """True if the open segments p1p2 and p3p4 properly intersect."""
    d1, d2 = cross(p3, p4, p1), cross(p3, p4, p2)
    d3, d4 = cross(p1, p2, p3), cross(p1, p2, p4)
    return d1 * d2 < 0 and d3 * d4 < 0


def check_simple(poly):
    n = len(poly)
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            if segments_cross(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]):
                raise SystemExit(f"outline edges {i} and {j} intersect")


def ear_clip(poly):
    """Triangulates a simple counterclockwise polygon; returns index triples
    (counterclockwise)."""
    idx = list(range(len(poly)))
    tris = []

    def inside(p, a, b, c):
        return cross(a, b, p) >= 0 and cross(b, c, p) >= 0 and cross(c, a, p) >= 0

    while len(idx) > 3:
        for k in range(len(idx)):
            i, j, l = idx[k - 1], idx[k], idx[(k + 1) % len(idx)]
            a, b, c = poly[i], poly[j], poly[l]
            if cross(a, b, c) <= 0:
                continue  # reflex or degenerate corner
            if any(inside(poly[m], a, b, c) for m in idx if m not in (i, j, l)):
                continue
            tris.append((i, j, l))
            del idx[k]
            break
        else:
            raise SystemExit("ear clipping failed: outline not simple?")
    tris.append(tuple(idx))
    return tris


def build():
    poly = outline()
    check_simple(poly)
    assert signed_area(poly) > 0, "outline must be counterclockwise in (x, z)"
    n = len(poly)
    # Vertices 0..n-1 on the front cap (y = 0), n..2n-1 on the back (y = DEPTH).
    vertices = [(x, 0.0, z) for (x, z) in poly] + [(x, DEPTH, z) for (x, z) in poly]
    faces = []
    for a, b, c in ear_clip(poly):
        # Counterclockwise in (x, z) has normal x^ cross z^ = -y^: outward
        # on the front cap, reversed on the back cap.
        faces.append((a, b, c))
        faces.append((n + c, n + b, n + a))
    for i in range(n):
        j = (i + 1) % n
        faces.append((i, n + i, n + j))
        faces.append((i, n + j, j))
    return vertices, faces


def check_closed(vertices, faces):
    """Every directed edge must appear once and its reverse once; the signed
    volume must be positive (outward normals)."""
    edges = {}
    for f in faces:
        for k in range(3):
            e = (f[k], f[(k + 1) % 3])
            edges[e] = edges.get(e, 0) + 1
    for (a, b), count in edges.items():
        if count != 1 or edges.get((b, a)) != 1:
            raise SystemExit(f"edge {a}-{b} is not shared by exactly two faces")
    volume = 0.0
    for a, b, c in faces:
        p, q, r = vertices[a], vertices[b], vertices[c]
        volume += (
            p[0] * (q[1] * r[2] - q[2] * r[1])
            - p[1] * (q[0] * r[2] - q[2] * r[0])
            + p[2] * (q[0] * r[1] - q[1] * r[0])
        ) / 6
    if volume <= 0:
        raise SystemExit("negative volume: faces are oriented inwards")
    return volume


def main():
    if len(sys.argv) > 2 or (len(sys.argv) == 2 and sys.argv[1].startswith("-")):
        raise SystemExit("Usage: python3 scripts/make_character.py [output]\n"
                         "Writes the character mesh to output, by default "
                         "data/character.obj of the repository.")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = (sys.argv[1] if len(sys.argv) > 1
           else os.path.join(root, "data", "character.obj"))
    vertices, faces = build()
    volume = check_closed(vertices, faces)
    # Written beside the output and renamed over it when complete: a run
    # that fails leaves the old mesh, not a truncated one.
    partial = out + ".partial"
    try:
        with open(partial, "w") as f:
            write_obj(f, vertices, faces, volume)
        os.replace(partial, out)
    except OSError as error:
        try:
            os.remove(partial)
        except OSError:
            pass
        raise SystemExit(f"Error: cannot write {out}: {error.strerror}")
    print(f"{out}: {len(vertices)} vertices, {len(faces)} triangles, volume {volume:.6f} m^3")


def write_obj(f, vertices, faces, volume):
    """Writes the mesh as Wavefront OBJ, with a header comment, to f."""
    f.write("# Gingerbread-man-like character for prm/character.prm, written by\n")
    f.write("# scripts/make_character.py: an outline in the x-z plane extruded\n")
    f.write(f"# along y by {DEPTH} m. Coordinates in meters. Closed and watertight.\n")
    f.write(f"# {len(vertices)} vertices, {len(faces)} triangles, volume {volume:.6f} m^3.\n")
    for v in vertices:
        f.write("v %.6f %.6f %.6f\n" % v)
    for a, b, c in faces:
        f.write(f"f {a + 1} {b + 1} {c + 1}\n")


if __name__ == "__main__":
    main()
