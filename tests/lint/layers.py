#!/usr/bin/env python3
"""Fails when a source includes a header of a layer above its own (the layer rule of README.md's
Layout). Layers, bottom to top:
  0  include/rayproof          the public headers (their folder names the library to link)
  1  src/io src/mesh src/gen src/methods src/scene
  2  verify/
  3  src/registry
  4  src/light src/report
  5  src/cli
python/, bench/, fuzz/ use the libraries and never the CLI (rank 4 for them); tests/ and examples/
may include anything. Also fails when a public header includes a project-internal one, or a
header-only core header (include/rayproof/*.h) includes a compiled component's front header.
usage: layers.py SOURCE_DIR"""
import os
import re
import sys

RANK = {"io": 1, "mesh": 1, "gen": 1, "methods": 1, "scene": 1, "verify": 2, "registry": 3, "light": 4, "report": 4,
        "cli": 5}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def layer_of(rel):
    parts = rel.split("/")
    if parts[0] == "include":
        return 0
    if parts[0] == "src" and len(parts) > 2:
        return RANK.get(parts[1])
    if parts[0] == "verify":
        return 2
    if parts[0] in ("python", "bench", "fuzz"):
        return 4
    return None


def main(root):
    bad = []
    for top in ("include", "src", "verify", "python", "bench", "fuzz"):
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in files:
                if not f.endswith((".h", ".hpp", ".cpp", ".cc")):
                    continue
                path = os.path.join(d, f)
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                mine = layer_of(rel)
                if mine is None:
                    continue
                text = open(path, encoding="utf-8", errors="replace").read()
                for inc in INCLUDE.findall(text):
                    head = inc.split("/")[0]
                    if head == "rayproof":
                        sub = inc.split("/")
                        if rel.startswith("include/rayproof/") and rel.count("/") == 2 and len(sub) > 2:
                            bad.append(f"{rel}: the header-only core includes {inc}, a compiled component's header")
                        continue
                    theirs = RANK.get(head)
                    if theirs is None:
                        continue
                    if mine == 0:
                        bad.append(f"{rel}: a public header includes the internal {inc}")
                    elif theirs > mine:
                        bad.append(f"{rel} (layer {mine}) includes {inc} (layer {theirs})")
    if bad:
        print("includes against the layer rule (README.md, Layout):")
        print("\n".join(sorted(bad)))
        return 1
    print("every include keeps the layer rule")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
