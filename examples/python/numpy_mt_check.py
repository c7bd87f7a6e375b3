"""A numpy Möller–Trumbore triangle test, checked against exact arithmetic by rayproof."""
import numpy as np
import rayproof

def moller_trumbore(O, D, P0, P1, P2):  # (n, 3) float32 arrays -> (hit, t)
    e1, e2 = P1 - P0, P2 - P0
    p = np.cross(D, e2); det = np.einsum("ij,ij->i", e1, p)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1 / det; s = O - P0; u = np.einsum("ij,ij->i", s, p) * inv
        q = np.cross(s, e1); v = np.einsum("ij,ij->i", D, q) * inv; t = np.einsum("ij,ij->i", e2, q) * inv
    return (det != 0) & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0), t

result = rayproof.check(moller_trumbore, kind="triangle", vectorized=True, count=500, seed=1, precision="float")
print(result["table"])
for r in result["reproducers"][:3]: print(r["verdict"], r["family"], r["case"], "->", r["got"], "exact:", r["want"])
