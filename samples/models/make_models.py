#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Writes the sample mesh models (OBJ, model frame: x forward, y to port, z up, metres; triangles
wound counter-clockwise seen from outside; docs/scene-format.md "mesh"):

  wreck.obj  a 24 m coaster lying on the seabed with an 8 degree list: a lofted hull (material
             `hull`) with a flat deck (`deck`), a bridge house (`house`) and a mast (`house`)
  mine.obj   a cylindrical ground mine, 2.0 m long and 0.53 m across, with rounded ends (`body`)
             and four tail fins (`fin`)

  make_models.py [--out DIR] [--stations N --ring M] [--only-wreck] [--name FILE]
  (N x M sets the wreck's resolution: the defaults give 3,662 triangles, --stations 400
  --ring 120 112,316)
"""
import argparse
import math
import os


class Model:
    def __init__(self):
        self.v = []
        self.faces = []  # (material, i, j, k), 0-based

    def vertex(self, p):
        self.v.append(tuple(float(c) for c in p))
        return len(self.v) - 1

    def tri(self, mat, i, j, k, inside):
        """Adds triangle i j k wound so that its normal points away from `inside`."""
        a, b, c = self.v[i], self.v[j], self.v[k]
        u = [b[n] - a[n] for n in range(3)]
        w = [c[n] - a[n] for n in range(3)]
        nrm = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        centre = [(a[n] + b[n] + c[n]) / 3.0 - inside[n] for n in range(3)]
        if sum(nrm[n] * centre[n] for n in range(3)) < 0.0:
            j, k = k, j
        self.faces.append((mat, i, j, k))

    def box(self, mat, lo, hi):
        """A closed box (12 triangles), its own vertices."""
        idx = [self.vertex((hi[0] if q & 1 else lo[0], hi[1] if q & 2 else lo[1],
                            hi[2] if q & 4 else lo[2])) for q in range(8)]
        mid = [(lo[n] + hi[n]) / 2.0 for n in range(3)]
        for f in ((0, 1, 3, 2), (4, 5, 7, 6), (0, 1, 5, 4), (2, 3, 7, 6), (0, 2, 6, 4),
                  (1, 3, 7, 5)):
            self.tri(mat, idx[f[0]], idx[f[1]], idx[f[2]], mid)
            self.tri(mat, idx[f[0]], idx[f[2]], idx[f[3]], mid)

    def transform(self, f):
        self.v = [f(p) for p in self.v]

    def write(self, path, header):
        with open(path, "w") as out:
            out.write("# " + header + "\n# Written by samples/models/make_models.py.\n")
            for p in self.v:
                out.write("v %.6f %.6f %.6f\n" % p)
            current = None
            for mat, i, j, k in sorted(self.faces, key=lambda f: f[0]):
                if mat != current:
                    out.write("usemtl %s\n" % mat)
                    current = mat
                out.write("f %d %d %d\n" % (i + 1, j + 1, k + 1))
        print("%s: %d vertices, %d triangles" % (path, len(self.v), len(self.faces)))


def loft(m, stations, ring, length, beam, depth, deck_points):
    """A closed hull: at each station a U-shaped section (half-ellipse below, flat deck on top),
    joined station to station, with flat end caps."""
    rings = []
    for s in range(stations + 1):
        x = -length / 2 + length * s / stations
        q = 2.0 * x / length
        half = beam / 2 * max(0.12, math.sqrt(max(0.0, 1.0 - q ** 6)) * (1.0 - 0.35 * max(0.0, q) ** 2))
        keel = depth * (1.0 - 0.25 * max(0.0, q) ** 2)
        pts, mats = [], []
        for k in range(ring + 1):  # port deck edge, down to the keel, up to starboard
            phi = math.pi * k / ring
            pts.append((x, half * math.cos(phi), depth - keel * math.sin(phi)))
            mats.append("hull")
        for k in range(1, deck_points):  # the deck from starboard back to port
            pts.append((x, -half + 2 * half * k / deck_points, depth))
            mats.append("deck")
        mats[-1] = "deck"
        mats[ring] = "deck"
        rings.append(([m.vertex(p) for p in pts], mats))
    n = len(rings[0][0])
    for s in range(stations):
        (a, mats), (b, _) = rings[s], rings[s + 1]
        x_mid = (m.v[a[0]][0] + m.v[b[0]][0]) / 2
        for k in range(n):
            k2 = (k + 1) % n
            inside = (x_mid, 0.0, depth * 0.6)
            m.tri(mats[k], a[k], a[k2], b[k], inside)
            m.tri(mats[k], a[k2], b[k2], b[k], inside)
    for end, sign in ((rings[0][0], -1.0), (rings[-1][0], 1.0)):
        c = m.vertex((m.v[end[0]][0], 0.0, depth * 0.6))
        for k in range(n):
            m.tri("hull", end[k], end[(k + 1) % n], c, (m.v[end[0]][0] - sign, 0.0, depth * 0.6))


def wreck(stations, ring):
    m = Model()
    loft(m, stations, ring, length=24.0, beam=6.0, depth=3.0, deck_points=max(4, ring // 6))
    m.box("house", (-9.0, -2.2, 2.99), (-5.0, 2.2, 5.4))  # bridge house aft
    m.box("house", (-8.6, -2.0, 5.39), (-5.4, 2.0, 5.9))  # its roof
    m.box("house", (1.8, -0.15, 2.99), (2.1, 0.15, 9.0))  # mast
    roll = math.radians(8.0)  # a list to port
    m.transform(lambda p: (p[0], p[1] * math.cos(roll) - p[2] * math.sin(roll),
                           p[1] * math.sin(roll) + p[2] * math.cos(roll)))
    return m


def mine():
    m = Model()
    radius, half_len, ring, caps = 0.265, 0.735, 32, 8
    # A capsule along x: rings of the cylinder and of the two hemispherical ends, closed by poles.
    profile = []  # (x, r)
    for k in range(caps, 0, -1):
        a = math.pi / 2 * k / caps
        profile.append((-half_len - radius * math.sin(a), radius * math.cos(a)))
    profile += [(-half_len, radius), (half_len, radius)]
    for k in range(1, caps + 1):
        a = math.pi / 2 * k / caps
        profile.append((half_len + radius * math.sin(a), radius * math.cos(a)))
    tip0 = m.vertex((-half_len - radius, 0.0, radius))
    rings = []
    for x, r in profile[1:-1]:
        rings.append([m.vertex((x, r * math.cos(2 * math.pi * k / ring),
                                radius + r * math.sin(2 * math.pi * k / ring)))
                      for k in range(ring)])
    tip1 = m.vertex((half_len + radius, 0.0, radius))
    axis = lambda i: (m.v[i][0], 0.0, radius)  # noqa: E731
    for k in range(ring):
        k2 = (k + 1) % ring
        m.tri("body", tip0, rings[0][k], rings[0][k2], (m.v[tip0][0] + 0.1, 0.0, radius))
        m.tri("body", tip1, rings[-1][k], rings[-1][k2], (m.v[tip1][0] - 0.1, 0.0, radius))
        for a, b in zip(rings, rings[1:]):
            inside = ((m.v[a[k]][0] + m.v[b[k]][0]) / 2, 0.0, radius)
            m.tri("body", a[k], a[k2], b[k], inside)
            m.tri("body", a[k2], b[k2], b[k], inside)
    del axis
    # Four tail fins (thin closed boxes) at the aft end, in the + pattern.
    x0, x1 = -half_len - 0.05, -half_len + 0.25
    m.box("fin", (x0, -0.01, radius), (x1, 0.01, 2 * radius + 0.12))
    m.box("fin", (x0, -0.01, -0.0), (x1, 0.01, radius))
    m.box("fin", (x0, -radius - 0.12, radius - 0.01), (x1, 0.0, radius + 0.01))
    m.box("fin", (x0, 0.0, radius - 0.01), (x1, radius + 0.12, radius + 0.01))
    # The lower fin reaches z = 0; everything else is above: the model rests on it and its body.
    return m


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--stations", type=int, default=48)
    ap.add_argument("--ring", type=int, default=32)
    ap.add_argument("--only-wreck", action="store_true")
    ap.add_argument("--name", default="wreck.obj", help="file name of the wreck")
    a = ap.parse_args()
    wreck(a.stations, a.ring).write(os.path.join(a.out, a.name),
                                   "A 24 m coaster wreck (sonarsynth sample model).")
    if not a.only_wreck:
        mine().write(os.path.join(a.out, "mine.obj"),
                     "A cylindrical ground mine (sonarsynth sample model).")


if __name__ == "__main__":
    main()
