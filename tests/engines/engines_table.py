#!/usr/bin/env python3
"""Reproduces docs/check.md's table of real engines under the judges ("Real engines under the
judges"): it reads the section's option lines (one per judge) and its table, runs `rayproof check
--json` with those options for every row whose engine is on this machine (Open3D and VTK through
/usr/bin/python3, CGAL and Embree as the programs built into build/examples/), and compares each
cell with the counts the judge printed. The crossings judge's float rows run on copies of the
meshes rounded to float. Rows whose engine is absent are skipped and named; with none at all the
test is skipped (exit 77). `--print` prints the measured cells as table rows instead of comparing.

    engines_table.py RAYPROOF EXAMPLES_BIN MESHES_DIR SOURCE_DIR [--print]"""
import json
import os
import re
import shlex
import struct
import subprocess
import sys
import tempfile
import time

SECTION = "## Real engines under the judges"
# Column heading -> the --mesh argument (a file in MESHES_DIR, or rayproof's generated mesh #0).
MESH_COLUMNS = {"bunny00": "bunny00.off", "refined_elephant": "refined_elephant.off",
                "elephant-with-holes": "elephant-with-holes.off", "generated #0": "generated"}
# The cells' labels and the judge's JSON keys they stand for ("events": the number of events).
CONTAINS_LABELS = [("in→out", "inside_called_outside"), ("out→in", "outside_called_inside"),
                   ("false surface", "false_surface"), ("garbage", "garbage"), ("failed", "failures"),
                   ("invalid failed", "invalid_failures"), ("events", "events")]
DISTANCE_LABELS = [("over tol", "over_tolerance"), ("random findings", "random_findings"),
                   ("wrong sign", "wrong_sign"), ("surface ≠ 0", "surface_nonzero"), ("off mesh", "closest_off_mesh"),
                   ("not nearest", "closest_not_nearest"), ("wrong triangle", "wrong_triangle"), ("garbage", "garbage"),
                   ("failed", "failures"), ("invalid number", "invalid_number"),
                   ("invalid failed", "invalid_failures"), ("events", "events"), ("max rel", "max_rel_error")]
CROSSINGS_LABELS = [("missing", "missing"), ("duplicates", "duplicates"), ("touch hits", "touch_hits"),
                    ("no contact", "no_contact"), ("garbage", "garbage"), ("wrong order", "wrong_order"),
                    ("t over tol", "t_over_tolerance"), ("failed", "failures"), ("invalid hit", "invalid_hit"),
                    ("invalid failed", "invalid_failures"), ("events", "events"), ("max ulps", "max_ulps")]
LABELS = {"contains": CONTAINS_LABELS, "distance": DISTANCE_LABELS, "crossings": CROSSINGS_LABELS}


def section(doc):
    start = doc.index(SECTION)
    end = doc.find("\n## ", start + len(SECTION))
    return doc[start:end if end >= 0 else len(doc)]


def option_lines(text):
    """The code block's `check --contains`, `check --distance` and `check --crossings` lines: their
    options."""
    block = re.search(r"```sh\n(.*?)```", text, re.S).group(1)
    out = {}
    for line in block.splitlines():
        words = shlex.split(line)
        for judge in LABELS:
            if "--" + judge in words:
                out[judge] = [w for w in words[2:] if w not in ("--" + judge, "NAME=COMMAND", "--mesh", "MESHES")]
    return out


def table(text):
    """The table's heading and rows, as lists of stripped cells."""
    lines = [l for l in text.splitlines() if l.startswith("|")]
    rows = [[c.strip() for c in l.strip().strip("|").split("|")] for l in lines]
    return rows[0], [r for r in rows[2:]]


def parse_cell(cell, labels):
    """'in→out 3, events 1' -> {'inside_called_outside': 3, 'events': 1}; absent labels are 0."""
    values = {key: 0 for _, key in labels}
    if cell in ("0", "—"):
        return values
    by_label = dict(labels)
    for part in cell.split(", "):
        label, _, number = part.rpartition(" ")
        if label not in by_label:
            raise ValueError("unknown label %r in cell %r" % (label, cell))
        values[by_label[label]] = float(number) if by_label[label] == "max_rel_error" else int(number)
    return values


def format_cell(values, labels):
    parts = []
    for label, key in labels:
        v = values[key]
        if v:
            parts.append("%s %s" % (label, ("%.2g" % v) if key == "max_rel_error" else v))
    return ", ".join(parts) or "0"


def engine_command(command, examples_bin, source_dir):
    """The row's command with the examples' paths made absolute: python3 scripts from the source
    tree, C++ programs from the build tree; None when the engine is not on this machine."""
    words = shlex.split(command)
    if words[0] == "python3":
        module = {"open3d": "open3d", "vtk": "vtkmodules"}[re.search(r"(open3d|vtk)", words[1]).group(1)]
        if subprocess.run(["/usr/bin/python3", "-c", "import " + module], capture_output=True).returncode != 0:
            return None
        words = ["/usr/bin/python3", os.path.join(source_dir, words[1])] + words[2:]
    else:
        program = os.path.join(examples_bin, os.path.basename(words[0]))
        if not os.access(program, os.X_OK):
            return None
        words = [program] + words[1:]
    return " ".join(shlex.quote(w) for w in words)


def float_meshes(meshes_dir, out_dir):
    """Copies of the table's OFF meshes with every coordinate rounded to float (written exactly, as
    shortest decimals): what a float engine holds, for the judges that round only the queries."""
    for mesh in MESH_COLUMNS.values():
        if mesh == "generated":
            continue
        with open(os.path.join(meshes_dir, mesh)) as f:
            words = f.read().split()
        if words[0] != "OFF":
            sys.exit("%s: not an OFF file" % mesh)
        nv = int(words[1])
        rounded = [repr(struct.unpack("f", struct.pack("f", float(w)))[0]) for w in words[4:4 + 3 * nv]]
        with open(os.path.join(out_dir, mesh), "w") as f:
            f.write(" ".join(words[1:4]).join(["OFF\n", "\n"]))
            for i in range(nv):
                f.write(" ".join(rounded[3 * i:3 * i + 3]) + "\n")
            faces = words[4 + 3 * nv:]
            k = 0
            while k < len(faces):  # one face a line: its vertex count, then its vertices
                f.write(" ".join(faces[k:k + 1 + int(faces[k])]) + "\n")
                k += 1 + int(faces[k])


def measure(rayproof, judge, name, command, flags, options, meshes_dir):
    meshes = []
    for column, mesh in MESH_COLUMNS.items():
        meshes.append(mesh if mesh == "generated" else os.path.join(meshes_dir, mesh))
    args = [rayproof, "check", "--json", "--" + judge, name + "=" + command] + options + flags + \
        ["--mesh"] + meshes + ["--meshes", "1"]
    start = time.monotonic()
    run = subprocess.run(args, capture_output=True, text=True, timeout=600)
    print("%s: %.1f s" % (name, time.monotonic() - start), file=sys.stderr)
    if run.returncode not in (0, 1):
        sys.exit("rayproof check failed (%d): %s\n%s" % (run.returncode, " ".join(args), run.stderr))
    out = {}
    for r in json.loads(run.stdout)["functions"]:
        column = next(c for c, m in MESH_COLUMNS.items()
                      if (m == "generated" and r["mesh"].startswith("generated #0")) or r["mesh"].endswith("/" + m))
        values = dict(r)
        values["events"] = len(r["events"])
        if judge == "distance":
            values["random_findings"] = r["sets"].get("random", {}).get("findings", 0) if r["rel_tol"] > 0 else 0
        out[column] = values
    return out


def main():
    argv = [a for a in sys.argv[1:] if a != "--print"]
    print_only = "--print" in sys.argv[1:]
    rayproof, examples_bin, meshes_dir, source_dir = argv
    if not os.path.exists(os.path.join(meshes_dir, "bunny00.off")):
        print("CGAL's meshes are not extracted (libcgal-dev's data.tar.gz): skipped")
        return 77
    with open(os.path.join(source_dir, "docs", "check.md"), encoding="utf-8") as f:
        text = section(f.read())
    options = option_lines(text)
    heading, rows = table(text)
    columns = heading[4:]
    if columns != list(MESH_COLUMNS):
        sys.exit("the table's mesh columns %r are not %r" % (columns, list(MESH_COLUMNS)))
    ran, skipped, wrong = 0, [], []
    float_dir = tempfile.TemporaryDirectory(prefix="engines_table_")
    float_written = False
    for row in rows:
        engine, judge_cell, broken_by, command_cell = row[:4]
        judge = next(j for j in LABELS if j in judge_cell)
        flags = []
        if judge_cell.startswith("signed"):
            flags.append("--distance-signed")
        if "float" in judge_cell:
            flags += ["--%s-precision" % judge, "float"]
        command = engine_command(command_cell.strip("`"), examples_bin, source_dir)
        if command is None:
            skipped.append(engine)
            continue
        labels = LABELS[judge]
        mesh_dir = meshes_dir
        if judge == "crossings" and "float" in judge_cell:
            # The crossings judge rounds the rays to float, not the mesh: the float engine is judged
            # on the float mesh it holds, as the distance judge does by itself.
            if not float_written:
                float_meshes(meshes_dir, float_dir.name)
                float_written = True
            mesh_dir = float_dir.name
        measured = measure(rayproof, judge, engine.strip("`"), command, flags, options[judge], mesh_dir)
        ran += 1
        cells = [format_cell(measured[c], labels) for c in columns]
        if print_only:
            print("| " + " | ".join(row[:4] + cells) + " |")
            continue
        for column, cell, got in zip(columns, row[4:], cells):
            want = parse_cell(cell, labels)
            have = parse_cell(got, labels)
            if want != have:
                wrong.append("%s on %s: the table says '%s', the judge counted '%s'" % (engine, column, cell, got))
    if skipped:
        print("engines not on this machine, their rows not checked: " + ", ".join(skipped))
    if ran == 0:
        print("no engine of the table is on this machine: skipped")
        return 77
    for w in wrong:
        print(w)
    if not print_only:
        print("%d rows of the table checked, %d cells differ" % (ran, len(wrong)))
    return 1 if wrong else 0


if __name__ == "__main__":
    sys.exit(main())
