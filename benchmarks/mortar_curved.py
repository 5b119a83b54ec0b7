#!/usr/bin/python3
"""A curved non-matching interface converges to the matching answer (benchmark M3
of doc/benchmarks.md, doc/contact.md): the two blocks of
tests/scenes/mortar_patch.prm with the interface y = 0.5 + 0.08 sin(pi x),
pressed together by the top's displacement. Each level n meshes the lower
block with n x n/2 cells and the upper one with 2n x n (tests/make_mortar_msh.py,
every interface node on the curve, so the two polylines differ by O(h^2)),
coupled by dual mortar; the reference at each level is the node-to-node
interface on the matching 2n-cell meshes of both blocks (the mortar coupling on
those matching meshes is checked against it too). Prints per level the contact
force of both, their relative difference and its rate, the largest force
imbalance of the mortar coupling, and the wall time of the mortar run (one run
each on the same machine; compare ratios). Standard library only.

    benchmarks/mortar_curved.py [BUILD_DIR] [--levels 6,12,24,48,96] [--iterations]

--iterations prints instead the active-set iterations per step of
tests/scenes/mortar_matching.prm (the active set grows over four steps) with
4 : 10 cells along the interface (mortar) against 10 : 10 (node-to-node) at
global refinement 0, 1, 2 (doc/contact.md).
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
from ladder import run_text, set_path  # noqa: E402

SCENE = os.path.join(ROOT, "tests/scenes/mortar_patch.prm")
MESHER = os.path.join(ROOT, "tests/make_mortar_msh.py")


def mesh(path, lower, upper, *extra):
    subprocess.run([sys.executable, MESHER, path, "--lower", lower, "--upper", upper,
                    "--bump", "0.08"] + list(extra), check=True)


def run(binary, work, name, mesh_file, mortar):
    with open(SCENE) as f:
        text = f.read()
    text = set_path(text, "Geometry/Mesh file", mesh_file)
    text = set_path(text, "Exact solution/Type", "none")
    text = set_path(text, "Output/Directory", name)
    if not mortar:
        text = set_path(text, "Contact/Interface 1-2/Discretisation", "nodal")
        text = set_path(text, "Contact/Interface 1-2/Mortar boundaries", "")
    out, elapsed = run_text(binary, work, name, text)
    value = lambda name: float(re.search(r"^RESULT %s = (\S+)" % re.escape(name), out,
                                         re.M).group(1))
    force = value("contact force interface 1-2")
    balance = value("mortar weight defect interface 1-2") if mortar else 0.0
    dofs = value("displacement dofs")
    return force, balance, dofs, elapsed


def iterations(binary):
    scene_file = os.path.join(ROOT, "tests/scenes/mortar_matching.prm")
    print("| global refinements | mortar 4 : 10: DoFs, max, mean iterations | node-to-node "
          "10 : 10: DoFs, max, mean iterations |")
    print("|---|---|---|")
    with tempfile.TemporaryDirectory() as work:
        split, merged = os.path.join(work, "split.msh"), os.path.join(work, "merged.msh")
        subprocess.run([sys.executable, MESHER, split, "--lower", "4,2", "--upper", "10,4"],
                       check=True)
        subprocess.run([sys.executable, MESHER, merged, "--lower", "10,4", "--upper", "10,4",
                        "--merge"], check=True)
        for level in range(3):
            row = []
            for mortar in (True, False):
                with open(scene_file) as f:
                    text = f.read()
                text = set_path(text, "Geometry/Mesh file", split if mortar else merged)
                text = set_path(text, "Mesh refinement/Initial global refinements", str(level))
                text = set_path(text, "Output/Directory", "it_%d_%d" % (level, mortar))
                if mortar:
                    text = set_path(text, "Contact/Interface 1-2/Discretisation", "mortar")
                    text = set_path(text, "Contact/Interface 1-2/Mortar boundaries", "14, 15")
                scene = os.path.join(work, "it.prm")
                with open(scene, "w") as f:
                    f.write(text)
                out = subprocess.run([binary, scene], cwd=work, check=True,
                                     capture_output=True, text=True).stdout
                value = lambda name: re.search(r"^RESULT %s = (\S+)" % name, out, re.M).group(1)
                row.append("%s, %s, %s" % (value("displacement dofs"),
                                           value("max contact iterations"),
                                           value("mean contact iterations")))
            print("| %d | %s | %s |" % (level, row[0], row[1]))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--levels", default="6,12,24,48,96")
    parser.add_argument("--iterations", action="store_true")
    args = parser.parse_args()
    binary = os.path.join(os.path.abspath(args.build), "contact-stefan")
    if args.iterations:
        iterations(binary)
        return
    print("| n | DoFs | mortar force (n : 2n) | matching force (2n : 2n) | relative difference "
          "| rate | force balance | mortar run (s) |")
    print("|---|---|---|---|---|---|---|---|")
    last = None
    with tempfile.TemporaryDirectory() as work:
        for n in (int(v) for v in args.levels.split(",")):
            m = 2 * n
            coarse = os.path.join(work, "coarse_%d.msh" % n)
            merged = os.path.join(work, "merged_%d.msh" % n)
            mesh(coarse, "%d,%d" % (n, max(1, n // 2)), "%d,%d" % (m, n))
            mesh(merged, "%d,%d" % (m, n), "%d,%d" % (m, n), "--merge")
            force, balance, dofs, elapsed = run(binary, work, "mortar_%d" % n, coarse, True)
            reference, _, _, _ = run(binary, work, "nodal_%d" % n, merged, False)
            difference = abs(force - reference) / reference
            rate = "" if last is None else "%.2f" % math.log2(last / difference)
            print("| %d | %d | %.10g | %.10g | %.2e | %s | %.1e | %.2f |"
                  % (n, dofs, force, reference, difference, rate, balance, elapsed))
            last = difference


if __name__ == "__main__":
    main()
