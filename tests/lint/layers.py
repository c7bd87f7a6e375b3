#!/usr/bin/env python3
"""Fails when code uses a layer above its own or beside it (the layer rule of docs/layout.md),
by its quoted #includes and by the link graph of its CMake targets. Layers, bottom to top:
   0  include/rayproof          the public headers (their folder names the library to link)
   1  src/io                    case files
   2  src/mesh src/gen src/methods
   3  src/exact                 exact and certified arithmetic (rayproof::certified: GMP, MPFR)
   4  src/scene                 BVHs, mesh casters, containment, crossings, winding, distance
   5  src/scene/compare         the peers (CGAL, Embree) side by side with src/scene
   6  verify/                   judging: the ground truth, differential checks, campaigns
   7  src/registry
   8  src/light
   9  src/report
  10  python/ bench/ fuzz/      use the libraries, never the CLI
  11  src/cli
tests/ and examples/ may use anything. A folder may use its own layer's code only when it is the
same folder: two folders that share a rank never use each other (else one of them belongs higher).
Rules:
  - an #include "FOLDER/..." of a source must name a lower layer or its own folder;
  - a CMake target (its layer: that of its sources' folder, one folder per target) may link only
    targets of lower layers or of its own folder, read from the graph that tests/lint/link_graph.cmake
    writes at configure time (every direct link item, PUBLIC, PRIVATE and INTERFACE);
  - CGAL, GMP and MPFR are linked directly only by the layers of exact arithmetic and judging
    (src/exact, src/scene/compare, verify/; tests, examples, bench, python, fuzz as they need), and
    <CGAL/...> is included only by src/scene/compare and verify/ (and those consumers);
  - a public header includes no project-internal header, and a header-only core header
    (include/rayproof/*.h) no compiled component's front header, except a forwarding header of a
    moved path (it carries RAYPROOF_NO_MOVED_HEADER_MESSAGE and includes only the new path).
usage: layers.py SOURCE_DIR [LINK_GRAPH]  (LINK_GRAPH: BUILD/lint_link_graph.txt; without it, the
include rules only)"""
import os
import re
import sys

RANK = {"io": 1, "mesh": 2, "gen": 2, "methods": 2, "exact": 3, "scene": 4, "scene/compare": 5, "verify": 6,
        "registry": 7, "light": 8, "report": 9, "python": 10, "bench": 10, "fuzz": 10, "cli": 11}
# Folders whose targets may link CGAL, GMP or MPFR directly; None: tests and examples.
EXACT_LINKERS = {"exact", "scene/compare", "verify", "python", "bench", "fuzz", None}
CGAL_INCLUDERS = {"scene/compare", "verify", "python", "bench", "fuzz", None}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
SYSTEM_CGAL = re.compile(r'^\s*#\s*include\s+<CGAL/', re.M)
EXTERNAL = {"CGAL": re.compile(r"CGAL"), "GMP": re.compile(r"(^|/)libgmp(xx)?\.|^gmp(xx)?$"),
            "MPFR": re.compile(r"(^|/)libmpfr\.|^mpfr$")}


def folder_of(rel):
    """The layer folder of a path relative to the source root: "include", "scene/compare", "verify",
    "python", ...; None for tests/, examples/ and anything else."""
    parts = rel.split("/")
    if parts[0] == "include":
        return "include"
    if parts[0] == "src" and len(parts) > 2:
        if parts[1] == "scene" and len(parts) > 3 and parts[2] == "compare":
            return "scene/compare"
        return parts[1] if parts[1] in RANK else None
    if parts[0] in ("verify", "python", "bench", "fuzz"):
        return parts[0]
    return None


def rank_of(folder):
    return 0 if folder == "include" else RANK.get(folder)


def include_folder(inc):
    """The layer folder an include "x/y.h" names (relative to src/ or the root), or None."""
    parts = inc.split("/")
    if parts[0] == "scene" and len(parts) > 2 and parts[1] == "compare":
        return "scene/compare"
    return parts[0] if parts[0] in RANK else None


def above(mine, theirs):
    """Why folder `mine` may not use folder `theirs`, or None when it may."""
    if mine == theirs or mine is None:
        return None
    rm, rt = rank_of(mine), rank_of(theirs)
    if rt is None or rm is None:
        return None
    if rt > rm:
        return f"layer {rt}, above {mine}'s {rm}"
    if rt == rm:
        return f"layer {rt}, the same as {mine}'s: two folders of one rank never use each other"
    return None


def is_forwarding_header(text, includes):
    return "RAYPROOF_NO_MOVED_HEADER_MESSAGE" in text and len(includes) == 1


def check_includes(root, bad):
    for top in ("include", "src", "verify", "python", "bench", "fuzz"):
        for d, _, files in os.walk(os.path.join(root, top)):
            for f in files:
                if not f.endswith((".h", ".hpp", ".cpp", ".cc")):
                    continue
                path = os.path.join(d, f)
                rel = os.path.relpath(path, root).replace(os.sep, "/")
                mine = folder_of(rel)
                if mine is None:
                    continue
                text = open(path, encoding="utf-8", errors="replace").read()
                includes = INCLUDE.findall(text)
                if SYSTEM_CGAL.search(text) and mine not in CGAL_INCLUDERS:
                    bad.append(f"{rel} ({mine}) includes CGAL: only exact judging and the peers use CGAL")
                for inc in includes:
                    if inc.split("/")[0] == "rayproof":
                        core = rel.startswith("include/rayproof/") and rel.count("/") == 2
                        if core and inc.count("/") > 1 and not is_forwarding_header(text, includes):
                            bad.append(f"{rel}: the header-only core includes {inc}, a compiled component's header")
                        continue
                    theirs = include_folder(inc)
                    if theirs is None:
                        continue
                    if mine == "include":
                        bad.append(f"{rel}: a public header includes the internal {inc}")
                        continue
                    why = above(mine, theirs)
                    if why:
                        bad.append(f"{rel} includes {inc} ({theirs}: {why})")


def read_graph(path):
    targets = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            fields = line.rstrip("\n").split("\t")
            if len(fields) != 5:
                continue
            name, kind, srcdir, sources, links = fields
            targets[name] = (kind, srcdir, [s for s in sources.split(";") if s], [l for l in links.split(";") if l])
    return targets


def target_folder(root, name, srcdir, sources, bad):
    """The layer folder of a target's sources; a target whose sources span folders is reported."""
    folders = set()
    for s in sources:
        if s.startswith("$<"):
            continue
        path = s if os.path.isabs(s) else os.path.join(srcdir, s)
        rel = os.path.relpath(os.path.normpath(path), root).replace(os.sep, "/")
        if rel.startswith(".."):
            continue  # generated in the build tree
        folders.add(folder_of(rel))
    if not folders:  # an interface or imported-only target: by where it is defined
        rel = os.path.relpath(srcdir, root).replace(os.sep, "/")
        return folder_of(rel + "/x") if rel != "." else "include"
    if len(folders) > 1:
        bad.append(f"target {name} has sources in several layers: {sorted(str(x) for x in folders)}")
    return max(folders, key=lambda x: -1 if x is None else rank_of(x))


def check_links(root, graph_path, bad):
    targets = read_graph(graph_path)
    if not targets:
        bad.append(f"{graph_path}: no targets (configure the build first)")
        return
    folder = {n: target_folder(root, n, t[1], t[2], bad) for n, t in targets.items()}
    for name, (_, _, _, links) in sorted(targets.items()):
        mine = folder[name]
        for item in links:
            if item in targets:
                why = above(mine, folder[item])
                if why:
                    bad.append(f"target {name} ({mine}) links {item} ({folder[item]}: {why})")
                continue
            for lib, pattern in EXTERNAL.items():
                if pattern.search(item) and mine not in EXACT_LINKERS:
                    bad.append(f"target {name} ({mine}) links {lib} ({item}): only exact arithmetic and judging do")


def main(argv):
    if len(argv) < 2:
        print(__doc__)
        return 2
    root = os.path.abspath(argv[1])
    bad = []
    check_includes(root, bad)
    checked = "every include"
    if len(argv) > 2:
        if not os.path.exists(argv[2]):
            print(f"{argv[2]}: no link graph (it is written when the build is configured)")
            return 2
        check_links(root, argv[2], bad)
        checked = "every include and every link"
    if bad:
        print("uses against the layer rule (docs/layout.md):")
        print("\n".join(sorted(set(bad))))
        return 1
    print(f"{checked} keeps the layer rule")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
