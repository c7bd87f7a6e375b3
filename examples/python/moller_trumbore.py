#!/usr/bin/env python3
"""The worked problems' Möller–Trumbore ray/triangle test as a kernel of the line protocol
(docs/kernel_protocol.md), written the naive textbook way in double (Python floats). rayproof
catches it with false misses on rays that hit an edge or a vertex exactly.

Run:
    rayproof gen tri_edge -n 1000 > edge.txt
    rayproof verify --methods double --exec 'mt-python=python3 examples/python/moller_trumbore.py' edge.txt
"""
import sys


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def triangle(v):
    """v: o(3) d(3) p0(3) p1(3) p2(3). Returns the answer line."""
    o, d, p0, p1, p2 = v[0:3], v[3:6], v[6:9], v[9:12], v[12:15]
    e1, e2, s = sub(p1, p0), sub(p2, p0), sub(o, p0)
    s1 = cross(d, e2)
    det = dot(s1, e1)
    if det == 0.0:  # parallel to the plane, or in it: the naive test calls it a miss
        return "miss"
    s2 = cross(s, e1)
    inv = 1.0 / det
    t, b1, b2 = dot(s2, e2) * inv, dot(s1, s) * inv, dot(s2, d) * inv
    if not (b1 >= 0.0 and b2 >= 0.0 and 1.0 - b1 - b2 >= 0.0 and t >= 0.0):
        return "miss"
    return f"hit {t!r} {b1!r} {b2!r}"


def main():
    out = sys.stdout
    out.write("rayproof-kernel 1 double triangle\n")
    out.flush()
    for line in sys.stdin:
        fields = line.split()
        if not fields:
            continue
        # float() reads inf, -inf and nan; they make the comparisons false: a miss.
        out.write(triangle([float(x) for x in fields[1:16]]) + "\n")
    out.flush()


if __name__ == "__main__":
    main()
