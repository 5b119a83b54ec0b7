#!/usr/bin/python3
"""The casting's mortar wall on matching wall nodes against its nodal wall.

    compare_mortar_casting.py BINARY ROOT [--np N] [--tolerance T] [--set PATH=VALUE ...]

Runs ROOT/prm/casting.prm with 'Geometry/Subdivisions' = 16, 16 (one mesh,
not adapted, the wall's nodes shared, a nodal interface, and the mortar
scene's interference) and ROOT/prm/casting_mortar.prm
with 16, 16, 32 (the die meshed on its own with 32 cells along the wall, so
that its wall nodes lie where the casting's do, and a mortar interface), both
with the settings given. On a curved wall with coinciding nodes the mortar
coupling is the node-to-node one (M = W = D I), so every physical column of
the statistics table at every step and every physical RESULT line must agree
within T relative to its largest value (default 1e-10). Exit 0 on success, 1
with one line per failed check otherwise.
"""
import argparse
import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "benchmarks"))
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ladder import get_path, set_path  # noqa: E402
from compare_runs import compare, report, run_scene  # noqa: E402

# Work and time; the DoF counts (the die's interior is meshed differently);
# the mortar run's own summary lines; and the contact work, a sum of
# cancelling terms (-8.5e-6 J/m against an elastic energy of about 1e2),
# compared absolutely below.
WORK = re.compile(r"wall|solver|calls|factoris|solves|skipped|reused|dofs|^mortar |contact.work")
CONTACT_WORK_BOUND = 1e-12  # J/m


def scene(root, name, subdivisions, settings, directory):
    with open(os.path.join(root, "prm", name)) as f:
        text = f.read().replace("include include/", "include %s/prm/include/" % root)
    text = set_path(text, "Geometry/Subdivisions", subdivisions)
    for path, value in settings:
        text = set_path(text, path, value)
    return set_path(text, "Output/Directory", os.path.join(directory, "output"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary")
    parser.add_argument("root")
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-10)
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE")
    args = parser.parse_args()
    settings = [s.split("=", 1) for s in args.set] + [("Output/VTU interval", "0")]
    # The nodal run on its one mesh (prm/casting.prm adapts its own) and with
    # the mortar scene's interference, whatever either file says.
    with open(os.path.join(args.root, "prm", "casting_mortar.prm")) as f:
        gap = get_path(f.read(), "Contact/Interface gap", None)
    nodal = [("Mesh refinement/Adaptive refinement interval", "0"),
             ("Mesh refinement/Initial adaptive refinements", "0"),
             ("Mesh refinement/Maximum level", "10"),
             ("Contact/Interface gap", gap)]
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as work:
        runs = []
        for what, name, subdivisions in (("nodal", "casting.prm", "16, 16"),
                                         ("mortar", "casting_mortar.prm", "16, 16, 32")):
            directory = os.path.join(work, what)
            text = scene(args.root, name, subdivisions,
                         (nodal if what == "nodal" else []) + settings, directory)
            runs.append(run_scene(args.binary, text, directory, args.np, what))
    compared, failures = compare(runs[0], runs[1], args.tolerance, WORK, ("nodal", "mortar"),
                                 missing_results_fail=False, absolute=1e-15)
    for name in ("contact_work",):
        a, b = runs[0][1][name], runs[1][1][name]
        worst = max(abs(x - y) for x, y in zip(a, b))
        compared += 1
        if len(a) != len(b) or not worst <= CONTACT_WORK_BOUND:
            failures.append("column %s differs by %.3g J/m" % (name, worst))
    return report("compared %d columns and RESULT lines of the nodal and the mortar run"
                  % compared, failures)


if __name__ == "__main__":
    sys.exit(main())
