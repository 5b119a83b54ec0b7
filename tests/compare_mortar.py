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
(default 1e-10; columns of round-off, such as the energy residual, within
1e-15 absolute), and the same number of contact iterations. In perfect
thermal contact the mortar run's slave temperatures are constrained to their
partners' (M = D I), so a thermal scene compares the same way. Exit 0 on
success, 1 with one line per failed check otherwise.
"""
import argparse
import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "benchmarks"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ladder import set_path  # noqa: E402
from compare_runs import compare, report, run_scene  # noqa: E402

# Columns and RESULT lines that count work or time, not physics; and the
# temperature DoFs, which differ: the nodal run's bodies share the interface
# nodes' temperatures, the mortar run's slave nodes have their own
# (constrained) DoFs.
WORK = re.compile(r"wall|solver|calls|factoris|solves|skipped|reused|^dofs$|^temperature dofs$")


def run(binary, scene_text, directory, mesh, mortar, np):
    text = set_path(scene_text, "Geometry/Mesh file", mesh)
    text = set_path(text, "Output/Directory", os.path.join(directory, "output"))
    text = set_path(text, "Contact/Interface 1-2/Discretisation", "mortar" if mortar else "nodal")
    text = set_path(text, "Contact/Interface 1-2/Mortar boundaries", "14, 15" if mortar else "")
    return run_scene(binary, text, directory, np, "mortar" if mortar else "nodal")


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
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as work:
        nodal = run(args.binary, scene_text, os.path.join(work, "nodal"), args.nodal_mesh,
                    False, args.np)
        mortar = run(args.binary, scene_text, os.path.join(work, "mortar"), args.split_mesh,
                     True, args.np)
    compared, failures = compare(nodal, mortar, args.tolerance, WORK, ("nodal", "mortar"),
                                 missing_results_fail=True, absolute=1e-15)
    return report("compared %d columns and RESULT lines of the nodal and the mortar run"
                  % compared, failures)


if __name__ == "__main__":
    sys.exit(main())
