#!/usr/bin/python3
"""The adaptive step control's undo of a step: undoing a step and redoing it
with the same size changes nothing.

    compare_undo.py BINARY SCENE.prm --step K [--factor F] [--np N]
                    [--tolerance T] [--set PATH=VALUE ...]

Runs SCENE twice with 'Time stepping/Step control' = adaptive, held at the
scene's own 'Time step' (Maximum time step = Time step, targets so large that
no step is shortened), once as it is and once with CONTACT_STEFAN_REJECT_STEP=K
in the environment: the first attempt of step K is then undone -- the fields
set back to the state kept at the step's start, the way a rejected attempt is
-- and the step is redone with the same size, or with F times the size
(--factor F < 1: then the plain run is made to take step K that short from the
start, by a Step end time, so that what a shorter redo changes -- the
extrapolation from the previous step's size, the step's own data -- is
compared too). Checks
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
    parser.add_argument("--factor", type=float, default=1.0,
                        help="redo step K this many times as long (< 1); the plain run "
                             "then ends its step K there by a Step end time")
    parser.add_argument("--previous", type=float, default=1.0,
                        help="in both runs, shorten step K-1 to this fraction of the Time "
                             "step by a Step end time (so that the undone attempt differs "
                             "in size from the step before it)")
    parser.add_argument("--work", action="store_true",
                        help="compare the solvers' work too: both runs write a checkpoint "
                             "after step K-1, which starts the solvers afresh as the undo "
                             "does, so the iterations and factorisations of every step "
                             "that stands must agree as well")
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
    # Redone shorter: the plain run takes step K that long from the start (a
    # step shortened for a stop keeps the proposal, as the redone run's
    # controller grows back to the pinned Time step).
    start, step = float(get_path(text, "Time stepping/Start time", "0")), float(tau)
    stops = []
    if args.previous != 1.0:
        stops.append(start + (args.step - 2 + args.previous) * step)
    if stops:
        text = set_path(text, "Time stepping/Step end times", repr(stops[0]))
    if args.work:
        text = set_path(text, "Checkpoint/Interval (steps)", str(args.step - 1))
    plain_text = text
    forced = str(args.step)
    if args.factor != 1.0:
        stops.append((stops[-1] if stops else start + (args.step - 1) * step)
                     + args.factor * step)
        plain_text = set_path(text, "Time stepping/Step end times",
                              ", ".join(repr(t) for t in stops))
        forced += ":%r" % args.factor
    runs = []
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as work:
        for name, forced in (("plain", None), ("undone", forced)):
            directory = os.path.join(work, name)
            scene = set_path(plain_text if forced is None else text, "Output/Directory",
                             os.path.join(directory, "output"))
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
    # With --work only what differs by construction: wall times, the timer
    # calls and the block's counts (both count the undone attempt too).
    work = re.compile(r"wall|calls|rejected|corrections|residual|enthalpy change through|"
                      r"enthalpy_change|guess") if args.work else WORK
    compared, differences = compare(runs[0], runs[1], args.tolerance, work,
                                    ("plain", "undone"), missing_results_fail=True,
                                    absolute=args.absolute)
    failures += differences
    steps = runs[0][0].get("time steps", "?")
    return report("compared %d columns and RESULT lines over %s steps, step %d undone once"
                  % (compared, steps, args.step), failures)


if __name__ == "__main__":
    sys.exit(main())
