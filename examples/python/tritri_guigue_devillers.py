#!/usr/bin/env python3
"""Guigue and Devillers' triangle/triangle test (P. Guigue, O. Devillers, "Fast and Robust
Triangle-Triangle Overlap Test Using Orientation Predicates", JGT 2003) as a kernel of the line
protocol (docs/kernel_protocol.md), written plainly in double (Python floats): the signs of
orientation determinants computed in floating point. It answers `hit` (the closed triangles meet)
or `miss` for each `tritri` case. rayproof finds the contacts it misses: a rounded determinant of
a vertex that lies exactly on the other triangle's plane is rarely exactly 0.

Run:
    rayproof check --exec 'gd-python=python3 examples/python/tritri_guigue_devillers.py' \\
        --expect no-false-negative
"""
import sys


def orient(a, b, c, d):
    """((b - a) x (c - a)) . (d - a): > 0 when d is on the side of plane abc its normal points to."""
    ux, uy, uz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
    vx, vy, vz = c[0] - a[0], c[1] - a[1], c[2] - a[2]
    wx, wy, wz = d[0] - a[0], d[1] - a[1], d[2] - a[2]
    return (uy * vz - uz * vy) * wx + (uz * vx - ux * vz) * wy + (ux * vy - uy * vx) * wz


def sign(x):
    return (x > 0) - (x < 0)


def lone(s):
    """A rotation r and a flip f that put a vertex alone first: f * s[r] >= 0 and the other two
    f * s <= 0, a strictly positive lone vertex preferred. None when all three signs are 0."""
    for strict in (True, False):
        for r in range(3):
            for f in (1, -1):
                head, rest = f * s[r], (f * s[(r + 1) % 3], f * s[(r + 2) % 3])
                if (head > 0 if strict else head == 0 and rest[0] < 0 and rest[1] < 0) and max(rest) <= 0:
                    return r, f
    return None


def rotate(t, r):
    return t[r:] + t[:r]


def turn(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def on_segment(a, b, c):
    return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])


def segments_meet(a, b, c, d):
    s1, s2, s3, s4 = turn(c, d, a), turn(c, d, b), turn(a, b, c), turn(a, b, d)
    if s1 * s2 < 0 and s3 * s4 < 0:
        return True
    return ((s1 == 0 and on_segment(c, d, a)) or (s2 == 0 and on_segment(c, d, b))
            or (s3 == 0 and on_segment(a, b, c)) or (s4 == 0 and on_segment(a, b, d)))


def inside(p, t):
    u, v, w = turn(t[0], t[1], p), turn(t[1], t[2], p), turn(t[2], t[0], p)
    return (u >= 0 and v >= 0 and w >= 0) or (u <= 0 and v <= 0 and w <= 0)


def coplanar(a, b):
    """Both in one plane: project along the normal's largest axis, test the edges and one vertex."""
    e, f = [a[1][i] - a[0][i] for i in range(3)], [a[2][i] - a[0][i] for i in range(3)]
    n = (abs(e[1] * f[2] - e[2] * f[1]), abs(e[2] * f[0] - e[0] * f[2]), abs(e[0] * f[1] - e[1] * f[0]))
    drop = n.index(max(n))
    keep = [i for i in range(3) if i != drop]
    pa = [(p[keep[0]], p[keep[1]]) for p in a]
    pb = [(q[keep[0]], q[keep[1]]) for q in b]
    for i in range(3):
        for j in range(3):
            if segments_meet(pa[i], pa[(i + 1) % 3], pb[j], pb[(j + 1) % 3]):
                return True
    return inside(pa[0], pb) or inside(pb[0], pa)


def meets(a, b):
    sa = [sign(orient(b[0], b[1], b[2], p)) for p in a]  # a's vertices against b's plane
    if sa[0] == sa[1] == sa[2] != 0:
        return False
    sb = [sign(orient(a[0], a[1], a[2], q)) for q in b]
    if sb[0] == sb[1] == sb[2] != 0:
        return False
    if sa == [0, 0, 0]:
        return coplanar(a, b)
    if sb == [0, 0, 0]:  # rounding: b looks flat against a's plane, a not against b's
        return coplanar(a, b)
    ra, fa = lone(sa)
    rb, fb = lone(sb)
    a, b = rotate(list(a), ra), rotate(list(b), rb)
    if fa < 0:  # turning b over puts a's lone vertex on its positive side
        b[1], b[2] = b[2], b[1]
    if fb < 0:
        a[1], a[2] = a[2], a[1]
    # Both lone vertices now on the positive side of the other plane: the chords on the line
    # of the two planes overlap exactly when these two orientations are both <= 0.
    return orient(a[0], a[1], b[0], b[1]) <= 0 and orient(a[0], a[2], b[2], b[0]) <= 0


def main():
    out = sys.stdout
    out.write("rayproof-kernel 1 double tritri\n")
    out.flush()
    for line in sys.stdin:
        fields = line.split()
        if not fields or fields[0].startswith("#"):  # rayproof sends none; a case file has them
            continue
        v = [float(x) for x in fields[1:19]]
        a = [tuple(v[0:3]), tuple(v[3:6]), tuple(v[6:9])]
        b = [tuple(v[9:12]), tuple(v[12:15]), tuple(v[15:18])]
        out.write("hit\n" if meets(a, b) else "miss\n")
    out.flush()


if __name__ == "__main__":
    main()
