#!/usr/bin/python3
"""Large sliding across a mortar interface against the same block meshed
where it ends (doc/contact.md, doc/benchmarks.md M7).

    compare_sliding.py BINARY SCENE.prm SLIDING.msh STATIC.msh --still VALUE
                       [--np N] [--tolerance T] [--control-factor F]
                       [--set PATH=VALUE ...]
    compare_sliding.py BINARY SCENE.prm SLIDING.msh --unmoved VALUE [--np N]
                       [--tolerance T]

Runs three times:
  sliding  SCENE as written, mesh SLIDING.msh: the block slides along the base
           (Mortar sliding = large, on N ranks);
  static   mesh STATIC.msh, the block meshed where the sliding one ends, and
           'Boundary conditions/Mechanical boundary 13/Value' = VALUE (the
           same load without the slide), serial (also coupled where its own
           displacement puts the sides, so that both runs linearise about
           the same configuration once the sliding one has stopped);
  control  as 'sliding' with Mortar sliding = small (paired on the mesh),
           serial.
The last step of 'sliding' and 'static' is the same problem: every physical
column of the statistics table at that step (not the contact work, which
depends on the path, nor the energy residual, round-off) must agree within T
of the column's largest value over the run (default 1e-9, the table's ten
digits), and so must the RESULT lines of the final state (END_RESULTS: the
contact force and energy, the temperature's L2 'error'), relative. The
control must differ from 'static' by more than F times T (default 1e4) both in
some mechanical column and in the temperature: a run that ignored the
sliding, in either field, would fail. With --unmoved the block is not slid ('Mechanical boundary 13/Value' =
VALUE, a push so small that the coupling where the displacement puts the
sides is the mesh's to round-off) and the run ends at t = 13, without the
steady step: 'Mortar sliding = large' on N ranks must then give what 'small'
gives serially at every step, in every physical column and RESULT line
(within T, default 1e-9): the fields' state survives the set-up again after
every step (the final temperature carries its history, which a lost or stale
state changes by kelvins; the steady state alone would not show it).
Exit 0 on success, 1 with one line per failed check otherwise.
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

# Columns that count work or time, not physics, or that follow the mesh
# (the DoF counts are equal, but the segment count depends on the pairing).
# RESULT lines that describe the final state (not a maximum or sum over the run).
END_RESULTS = ["contact force interface 1-2", "elastic energy", "active contact nodes",
               "L2 error temperature", "relative L2 error temperature"]
THERMAL = "L2 error temperature"
WORK = re.compile(r"wall|solver|calls|factoris|solves|skipped|reused|iterations|dofs|segments|"
                  r"through sliding|^step$|^time$|^contact_work$|^energy_residual$")


def last_row_differences(a, b):
    """{column: |a - b| at the last step / the column's largest |value| over a}."""
    result = {}
    for name, values in a[1].items():
        if WORK.search(name) or name not in b[1]:
            continue
        scale = max(abs(v) for v in values) or 1.0
        result[name] = abs(values[-1] - b[1][name][-1]) / scale
    for name in END_RESULTS:
        if name in a[0] and name in b[0]:
            x, y = float(a[0][name]), float(b[0][name])
            result["RESULT " + name] = abs(x - y) / max(abs(x), abs(y), 1e-300)
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary")
    parser.add_argument("scene")
    parser.add_argument("sliding_mesh")
    parser.add_argument("static_mesh", nargs="?")
    parser.add_argument("--still", help="Mechanical boundary 13's Value without the slide")
    parser.add_argument("--unmoved", help="Mechanical boundary 13's Value of the unmoved "
                        "comparison")
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-9)
    parser.add_argument("--control-factor", type=float, default=1e4)
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE")
    args = parser.parse_args()
    with open(args.scene) as f:
        text = f.read()
    for setting in args.set:
        path, value = setting.split("=", 1)
        text = set_path(text, path, value)

    with tempfile.TemporaryDirectory() as work:
        def run(name, mesh, np, changes):
            scene = set_path(text, "Geometry/Mesh file", mesh)
            scene = set_path(scene, "Output/Directory", os.path.join(work, name, "output"))
            for path, value in changes:
                scene = set_path(scene, path, value)
            return run_scene(args.binary, scene, os.path.join(work, name), np, name)

        if args.unmoved is not None:
            # Without the final steady step: the last step's temperature then
            # carries the whole history (the statistics have no temperature
            # column, the final RESULT lines do).
            unmoved = [("Boundary conditions/Mechanical boundary 13/Value", args.unmoved),
                       ("Time stepping/End time", "13"),
                       ("Time stepping/Time step function", "")]
            large = run("large", args.sliding_mesh, args.np, unmoved)
            small = run("small", args.sliding_mesh, 1,
                        unmoved + [("Contact/Interface 1-2/Mortar sliding", "small")])
            compared, failures = compare(large, small, args.tolerance, WORK,
                                         ("large", "small"), False, 1e-15)
            if "RESULT mortar sliding couplings" not in large[2]:
                failures.append("the large-sliding run did not couple again")
            return report("unmoved, large sliding on %d rank(s) against small: %d columns at "
                          "every step and RESULT lines within %.3g" % (args.np, compared,
                                                                       args.tolerance),
                          failures)
        if args.still is None or args.static_mesh is None:
            parser.error("give STATIC.msh and --still (or --unmoved)")
        sliding = run("sliding", args.sliding_mesh, args.np, [])
        static = run("static", args.static_mesh, 1,
                     [("Boundary conditions/Mechanical boundary 13/Value", args.still)])
        control = run("control", args.sliding_mesh, 1,
                      [("Contact/Interface 1-2/Mortar sliding", "small")])

    failures = []
    steps = len(next(iter(static[1].values())))
    if len(next(iter(sliding[1].values()))) != steps:
        failures.append("the sliding and the static run took different numbers of steps")
    differences = last_row_differences(sliding, static)
    for name in END_RESULTS:
        if "RESULT " + name not in differences:
            failures.append("RESULT %s: missing in the sliding or the static run" % name)
    for name, d in sorted(differences.items()):
        if not d <= args.tolerance:
            failures.append("column %s: the last step differs by %.3g of its largest value"
                            % (name, d))
    control_differences = last_row_differences(control, static)
    mechanical = {k: v for k, v in control_differences.items() if not k.endswith(THERMAL)}
    worst_name = max(mechanical, key=mechanical.get)
    worst = mechanical[worst_name]
    thermal = control_differences.get("RESULT " + THERMAL, 0.0)
    if not worst > args.control_factor * args.tolerance:
        failures.append("the control run (Mortar sliding = small) differs from the static one "
                        "by only %.3g (%s): the test cannot tell sliding from none"
                        % (worst, worst_name))
    if not thermal > args.control_factor * args.tolerance:
        failures.append("the control run's temperature differs from the static one by only "
                        "%.3g: the test cannot tell whether the thermal coupling slides" % thermal)
    largest = max(differences.values()) if differences else float("nan")
    summary = ("large sliding on %d rank(s): %d quantities of the last step within %.3g of the "
               "static run (largest %.3g); paired on the mesh: %.3g (%s), temperature %.3g"
               % (args.np, len(differences), args.tolerance, largest, worst, worst_name,
                  thermal))
    return report(summary, failures)


if __name__ == "__main__":
    sys.exit(main())
