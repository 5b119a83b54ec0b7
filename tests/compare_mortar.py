#!/usr/bin/python3
"""A mortar interface on matching meshes against the node-to-node interface.

    compare_mortar.py BINARY SCENE.prm NODAL.msh SPLIT.msh [--np N] [--tolerance T]
                      [--set PATH=VALUE ...]

Runs SCENE twice: with the mesh NODAL.msh, whose bodies share the interface's
nodes, and 'Contact/Interface 1-2/Discretisation' = nodal; and with SPLIT.msh,
the same mesh with each body's own copies of those nodes (lines 14 and 15),
and Discretisation = mortar. On matching sides the dual mortar coupling is the
node-to-node one (M = D I with D the lumped weight), so both runs must solve
the same problem: every physical column of the statistics table at every step,
and every physical RESULT line, within T relative to its largest value
(default 1e-10), and the same number of contact iterations. Exit 0 on
success, 1 with one line per failed check otherwise.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "benchmarks"))
from ladder import set_path  # noqa: E402

# Columns and RESULT lines that count work or time, not physics.
WORK = re.compile(r"wall|solver|calls|factoris|solves|skipped|reused")


def run(binary, scene_text, directory, mesh, mortar, np):
    os.makedirs(directory)
    text = set_path(scene_text, "Geometry/Mesh file", mesh)
    text = set_path(text, "Output/Directory", os.path.join(directory, "output"))
    if mortar:
        text = set_path(text, "Contact/Interface 1-2/Discretisation", "mortar")
        text = set_path(text, "Contact/Interface 1-2/Mortar boundaries", "14, 15")
    else:
        text = set_path(text, "Contact/Interface 1-2/Discretisation", "nodal")
        text = set_path(text, "Contact/Interface 1-2/Mortar boundaries", "")
    scene = os.path.join(directory, "scene.prm")
    with open(scene, "w") as f:
        f.write(text)
    command = [binary, scene]
    if np > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(np)] + command
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("the %s run failed (exit %d): %s" % ("mortar" if mortar else "nodal",
                                                      result.returncode,
                                                      result.stderr.strip()[-300:]))
    results = {}
    for line in result.stdout.splitlines():
        if line.startswith("RESULT ") and " = " in line:
            name, value = line[len("RESULT "):].rsplit(" = ", 1)
            results[name] = value.strip()
    with open(os.path.join(directory, "output", "statistics.txt")) as f:
        lines = [l.split() for l in f if not l.startswith("#")]
    columns = {name: [float(row[k]) for row in lines[1:]] for k, name in enumerate(lines[0])}
    return results, columns


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary")
    parser.add_argument("scene")
    parser.add_argument("nodal_mesh")
    parser.add_argument("split_mesh")
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-10)
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE")
    args = parser.parse_args()
    with open(args.scene) as f:
        scene_text = f.read()
    for setting in args.set:
        path, value = setting.split("=", 1)
        scene_text = set_path(scene_text, path, value)
    failures = []
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as work:
        nodal = run(args.binary, scene_text, os.path.join(work, "nodal"), args.nodal_mesh,
                    False, args.np)
        mortar = run(args.binary, scene_text, os.path.join(work, "mortar"), args.split_mesh,
                     True, args.np)
    compared = 0
    for name, values in nodal[1].items():
        if WORK.search(name) or name in ("step", "time"):
            continue
        other = mortar[1].get(name)
        if other is None or len(other) != len(values):
            failures.append("column %s: missing or of another length in the mortar run" % name)
            continue
        scale = max(abs(v) for v in values) or 1.0
        worst = max(abs(a - b) for a, b in zip(values, other)) / scale
        compared += 1
        if not worst <= args.tolerance:
            failures.append("column %s differs by %.3g of its largest value" % (name, worst))
    for name, value in nodal[0].items():
        if WORK.search(name):
            continue
        if name not in mortar[0]:
            failures.append("RESULT %s: missing in the mortar run" % name)
            continue
        try:
            a, b = float(value), float(mortar[0][name])
        except ValueError:
            continue
        compared += 1
        if not abs(a - b) <= args.tolerance * max(abs(a), abs(b), 1e-300) + 1e-15:
            failures.append("RESULT %s: %s (nodal) against %s (mortar)"
                            % (name, value, mortar[0][name]))
    print("compared %d columns and RESULT lines of the nodal and the mortar run" % compared)
    for failure in failures:
        print("FAILED: " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
