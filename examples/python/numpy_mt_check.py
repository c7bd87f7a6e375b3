"""A numpy Möller–Trumbore triangle test, checked against exact arithmetic by rayproof."""
import numpy as np
import rayproof

def moller_trumbore(O, D, P0, P1, P2):  # (n, 3) float32 arrays -> (hit, t), n rays at once
    with np.errstate(all="ignore"):
        dot = lambda a, b: np.einsum("ij,ij->i", a, b)
        e1, e2, s = P1 - P0, P2 - P0, O - P0
        p, q = np.cross(D, e2), np.cross(s, e1)
        det = dot(e1, p); u, v, t = dot(s, p) / det, dot(D, q) / det, dot(e2, q) / det
        return (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0), t

result = rayproof.check(moller_trumbore, kind="triangle", vectorized=True, precision="float", watertight=True)
print(result["table"], result["promises"])
for r in result["reproducers"]:
    if r["verdict"] == "false-miss" and r["family"] in ("tri_edge", "tri_vertex"):
        print(r["case"], "->", r["got"], "; exact:", r["want"])
