#!/usr/bin/python3
"""The block correction of the coupling against plain fixed-point passes.

    compare_acceleration.py BINARY SCENE.prm [--np N] [--tolerance T] [--passes P]
                            [--set PATH=VALUE ...] [--guesses-stand] [--ldlt all|none]

Runs SCENE twice, with 'Coupling/Fixed-point acceleration' = none and = block
solve (each in a directory of its own), and checks
  - that the block run says it corrected its passes (the 'Coupling:' line),
  - that every step of the block run took at most P passes (default 2),
  - that both runs solved the same coupled steps: every physical column of the
    statistics table (all but the wall time and the counts of the solvers'
    work) agrees at every step within T relative to the column's largest
    value (default 1e-8: both stop at 'Coupling/Fixed-point tolerance' 1e-10
    of the change over a step), and the same for the physical RESULT lines,
  - with --guesses-stand, that every corrected displacement and temperature
    was taken without a linear solve (exact inner solves),
  - with --ldlt, that all or none of the block factorisations were CHOLMOD's
    LDL^T (a constant or a varying Theta_0).
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

# Statistics columns and RESULT lines that count work, not physics, or that are
# round-off (energy-balance residuals, the enthalpy change of a mesh transfer).
WORK = re.compile(r"wall|iterations|changes|damped|fallback|solver|calls|factoris|"
                  r"solves|skipped|adaptations|restiffened|reused|residual|"
                  r"enthalpy change through|enthalpy_change")


def run(binary, scene_text, directory, acceleration, np):
    """One run in directory; returns its RESULT lines, statistics columns and
    'Coupling:' line."""
    text = set_path(scene_text, "Coupling/Fixed-point acceleration", acceleration)
    text = set_path(text, "Output/Directory", os.path.join(directory, "output"))
    results, columns, stdout = run_scene(binary, text, directory, np,
                                         "'%s' acceleration" % acceleration)
    coupling = [l for l in stdout.splitlines() if l.startswith("Coupling:")]
    return results, columns, coupling[0] if coupling else ""


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("binary")
    parser.add_argument("scene")
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--tolerance", type=float, default=1e-8)
    parser.add_argument("--passes", type=int, default=2)
    parser.add_argument("--guesses-stand", action="store_true",
                        help="every corrected guess answers its elasticity and heat solve "
                             "(exact inner solves)")
    parser.add_argument("--ldlt", choices=["all", "none"],
                        help="every block factorisation by CHOLMOD's LDL^T (a constant "
                             "Theta_0), or none (PETSc's LU)")
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                        help="set an entry of the scene in both runs")
    args = parser.parse_args()
    with open(args.scene) as f:
        scene_text = f.read()
    for setting in args.set:
        path, value = setting.split("=", 1)
        scene_text = set_path(scene_text, path, value)
    failures = []
    with tempfile.TemporaryDirectory(dir=os.getcwd()) as work:
        plain = run(args.binary, scene_text, os.path.join(work, "none"), "none", args.np)
        block = run(args.binary, scene_text, os.path.join(work, "block"), "block solve", args.np)
    if "corrected by a block solve" not in block[2]:
        failures.append("the block run did not use the block correction: " + block[2])
    passes = block[1].get("coupling_iterations", [])
    if not passes or max(passes[1:] or [0]) > args.passes:
        failures.append("the block run took up to %g passes per step (allowed %d)"
                        % (max(passes or [0]), args.passes))
    if args.ldlt:
        total = float(block[0].get("block factorisations", 0))
        ldlt = float(block[0].get("block factorisations by LDLT (constant Theta_0)", -1))
        if total < 1 or ldlt != (total if args.ldlt == "all" else 0):
            failures.append("expected %s of the %g block factorisations by LDL^T, got %g"
                            % (args.ldlt, total, ldlt))
    if args.guesses_stand:
        corrections = float(block[0].get("block corrections", 0))
        for field in ("elasticity", "heat"):
            stood = float(block[0].get(field + " solves answered by the corrected guess", -1))
            if corrections < 1 or stood != corrections:
                failures.append("%g of the %g corrected %s guesses stood (expected all)"
                                % (stood, corrections, field))
    plain_passes = plain[1].get("coupling_iterations", [0])
    compared, differences = compare(plain, block, args.tolerance, WORK, ("none", "block solve"),
                                    missing_results_fail=False)
    failures += differences
    return report("compared %d columns and RESULT lines; passes per step: none up to %g, "
                  "block up to %g" % (compared, max(plain_passes), max(passes or [0])), failures)


if __name__ == "__main__":
    sys.exit(main())
