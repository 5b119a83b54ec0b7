#!/usr/bin/python3
"""The adaptive step control's undo of a step: undoing a step and redoing it
with the same size changes nothing.

    compare_undo.py BINARY SCENE.prm --step K [--np N] [--tolerance T]
                    [--set PATH=VALUE ...]

Runs SCENE twice with 'Time stepping/Step control' = adaptive, held at the
scene's own 'Time step' (Maximum time step = Time step, targets so large that
no step is shortened), once as it is and once with CONTACT_STEFAN_REJECT_STEP=K
in the environment: the first attempt of step K is then undone -- the fields
set back to the state kept at the step's start, the way a rejected attempt is
-- and the step is redone with the same size. Checks
  - that the second run undid one attempt and the first none ('RESULT rejected
    step attempts'),
  - that both runs solved the same steps: every physical column of the
    statistics table and every physical RESULT line (all but the wall time and
    the counts of the solvers' work, which a redo with fresh solvers repeats)
    agree within T relative to the largest value (default 1e-9), plus an
    absolute 1e-12 (--absolute) for cancelling sums.
An undo that forgot a piece of the state (a time level, the phase states, a
contact set, the out-of-plane strain, a birth) shows as a difference.
Exit 0 on success, 1 with one line per failed check otherwise.
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

# Work, not physics (as in compare_acceleration.py), and round-off.
WORK = re.compile(r"wall|iterations|changes|damped|fallback|solver|calls|factoris|"
                  r"solves|skipped|adaptations|reused|residual|rejected|corrections|"
                  r"enthalpy change through|enthalpy_change|guess")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary")
    parser.add_argument("scene")
    parser.add_argument("--step", type=int, required=True)
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-9)
    parser.add_argument("--absolute", type=float, default=1e-12,
                        help="absolute allowance: cancelling sums such as the contact "
                             "work are round-off below it (as in tests/run_resume.sh)")
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE")
    args = parser.parse_args()
    with open(args.scene) as f:
        # (relative includes made absolute: the runs are in other directories)
        text = re.sub(r"^(\s*include\s+)([^/\s]\S*)",
                      lambda m: m.group(1) + os.path.join(
                          os.path.dirname(os.path.abspath(args.scene)), m.group(2)),
                      f.read(), flags=re.M)
    for setting in args.set:
        path, value = setting.split("=", 1)
        text = set_path(text, path, value)
    tau = get_path(text, "Time stepping/Time step", "0.1")
    for path, value in (("Step control", "adaptive"), ("Maximum time step", tau),
                        ("Target temperature change", "1e300"),
                        ("Target phase change", "1e300")):
        text = set_path(text, "Time stepping/" + path, value)
    runs = []
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as work:
        for name, forced in (("plain", None), ("undone", str(args.step))):
            directory = os.path.join(work, name)
            scene = set_path(text, "Output/Directory", os.path.join(directory, "output"))
            os.environ.pop("CONTACT_STEFAN_REJECT_STEP", None)
            if forced:
                os.environ["CONTACT_STEFAN_REJECT_STEP"] = forced
            runs.append(run_scene(args.binary, scene, directory, args.np, name))
    os.environ.pop("CONTACT_STEFAN_REJECT_STEP", None)
    failures = []
    for (results, _, _), expected, name in zip(runs, ("0", "1"), ("plain", "undone")):
        if results.get("rejected step attempts") != expected:
            failures.append("the %s run undid %s attempts, not %s"
                            % (name, results.get("rejected step attempts"), expected))
    compared, differences = compare(runs[0], runs[1], args.tolerance, WORK,
                                    ("plain", "undone"), missing_results_fail=True,
                                    absolute=args.absolute)
    failures += differences
    steps = runs[0][0].get("time steps", "?")
    return report("compared %d columns and RESULT lines over %s steps, step %d undone once"
                  % (compared, steps, args.step), failures)


if __name__ == "__main__":
    sys.exit(main())
