"""The line protocols of `rayproof check --caster`, `--contains` and `--distance`
(docs/check.md), read and written for the example programs beside this file: the mesh once, then
batches of rays or points until `end`. A program that reads stdin to its end exits quietly."""
import os
import sys
import tempfile

import numpy as np


def read_line(f=sys.stdin):
    """The next line's words; exits when rayproof has closed the pipe."""
    line = f.readline()
    if not line:
        sys.exit(0)
    return line.split()


def read_mesh_words(protocol, f=sys.stdin):
    """The first line (`PROTOCOL 1`, checked), then the vertices' and triangles' words as sent."""
    head = read_line(f)
    if head[:2] != [protocol, "1"]:
        sys.exit("not the %s protocol: %r" % (protocol, head))
    vertices = [read_line(f) for _ in range(int(read_line(f)[1]))]
    triangles = [read_line(f) for _ in range(int(read_line(f)[1]))]
    return vertices, triangles


def read_mesh(protocol, dtype=np.float64, index_dtype=np.int64, f=sys.stdin):
    """The mesh as arrays: vertices (V, 3) of `dtype`, triangles (T, 3) of `index_dtype`."""
    vertices, triangles = read_mesh_words(protocol, f)
    V = np.array([[float(x) for x in v] for v in vertices], dtype=dtype).reshape(len(vertices), 3)
    T = np.array([[int(x) for x in t] for t in triangles], dtype=index_dtype).reshape(len(triangles), 3)
    return V, T


def batch_words(f=sys.stdin):
    """Each batch's lines as lists of words, until `end`."""
    while True:
        words = read_line(f)
        if words[0] == "end":
            return
        yield [read_line(f) for _ in range(int(words[1]))]


def batches(width, dtype=np.float64, f=sys.stdin):
    """Each batch as an (n, width) array: rays (width 6: origin, direction) or points (3)."""
    for lines in batch_words(f):
        yield np.array([[float(x) for x in words] for words in lines], dtype=dtype).reshape(len(lines), width)


def answer(lines):
    """Writes a batch's answer lines (each ending in a newline) at once."""
    sys.stdout.write("".join(lines))
    sys.stdout.flush()


class OffMesh:
    """The mesh written once as an OFF file (its decimals as sent), and a points file beside it, for
    programs that pass each batch to the `rayproof` tool."""

    def __init__(self, protocol):
        vertices, triangles = read_mesh_words(protocol)
        self.tmp = tempfile.TemporaryDirectory()
        self.mesh = os.path.join(self.tmp.name, "mesh.off")
        self.points = os.path.join(self.tmp.name, "points.txt")
        with open(self.mesh, "w") as m:
            m.write("OFF\n%d %d 0\n" % (len(vertices), len(triangles)))
            m.write("".join(" ".join(v) + "\n" for v in vertices))
            m.write("".join("3 " + " ".join(t) + "\n" for t in triangles))

    def write_points(self, rows):
        with open(self.points, "w") as pf:
            pf.write("".join(" ".join(r) + "\n" for r in rows))
