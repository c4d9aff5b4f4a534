#!/usr/bin/env python3
"""Write a finely tessellated object for load and scale checks (docs/security.md, docs/model.md).

usage: bench/superellipsoid.py N DIR

A superellipsoid |x/a|^6 + |y/b|^6 + |z/c|^6 = 1 (a, b, c = 30, 20, 15 mm), every vertex on its
convex hull, as an N x N latitude-longitude grid: 2 N (N - 1) triangles (N = 1000: 1 998 000) in
DIR/meshes/superellipsoid_N.stl (binary), and DIR/superellipsoid_N.urdf, 2650 kg/m^3, its centre
of mass moved to (2, -1, -3) mm (uneven density), a box-like inertia. Plain Python, no packages;
about 10 s for N = 1000. Benchmarks only: no build or test uses it.
"""
import math
import os
import struct
import sys


def main():
    if len(sys.argv) != 3 or not sys.argv[1].isdigit() or int(sys.argv[1]) < 4:
        sys.exit(__doc__.strip().splitlines()[2])
    n, out = int(sys.argv[1]), sys.argv[2]
    a, b, c, e = 0.03, 0.02, 0.015, 2.0 / 6.0
    name = "superellipsoid_%d" % n
    os.makedirs(os.path.join(out, "meshes"), exist_ok=True)

    def spow(v):
        return math.copysign(abs(v) ** e, v)

    rows = []
    for i in range(n + 1):
        if i in (0, n):  # the poles: one point each, exactly
            rows.append([(0.0, 0.0, c if i == n else -c)] * n)
            continue
        th = -math.pi / 2 + math.pi * i / n
        ct, st = spow(math.cos(th)), spow(math.sin(th))
        rows.append([(a * ct * spow(math.cos(2 * math.pi * j / n)),
                      b * ct * spow(math.sin(2 * math.pi * j / n)), c * st) for j in range(n)])
    tris = []
    for i in range(n):
        for j in range(n):
            k = (j + 1) % n
            if i > 0:
                tris.append((rows[i][j], rows[i][k], rows[i + 1][k]))
            if i < n - 1:
                tris.append((rows[i][j], rows[i + 1][k], rows[i + 1][j]))
    volume = 0.0
    with open(os.path.join(out, "meshes", name + ".stl"), "wb") as f:
        f.write(b"\0" * 80 + struct.pack("<I", len(tris)))
        pack = struct.Struct("<12fH").pack
        for p, q, r in tris:
            volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                       p[2] * (q[0] * r[1] - q[1] * r[0])) / 6.0
            f.write(pack(0, 0, 0, *p, *q, *r, 0))
    m = 2650.0 * volume
    ixx, iyy, izz = m * (b * b + c * c) / 4, m * (a * a + c * c) / 4, m * (a * a + b * b) / 4
    with open(os.path.join(out, name + ".urdf"), "w") as f:
        f.write('<?xml version="1.0"?>\n<!-- bench/superellipsoid.py %d: %d triangles -->\n'
                '<robot name="%s"><link name="%s"><inertial>'
                '<origin xyz="0.002 -0.001 -0.003" rpy="0 0 0"/><mass value="%.9g"/>'
                '<inertia ixx="%.9g" ixy="0" ixz="0" iyy="%.9g" iyz="0" izz="%.9g"/></inertial>'
                '<collision><geometry><mesh filename="meshes/%s.stl"/></geometry></collision>'
                '</link></robot>\n' % (n, len(tris), name, name, m, ixx, iyy, izz, name))
    print("%s: %d triangles, %.6g kg" % (os.path.join(out, name + ".urdf"), len(tris), m))


if __name__ == "__main__":
    main()
