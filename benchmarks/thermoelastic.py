#!/usr/bin/python3
"""A linear thermoelastic problem side by side with FEniCSx (issue 33).

The thermoelastic plate (benchmarks/scenes/thermoelastic_plate.prm): fully
coupled (thermal stress and thermoelastic heating, coupling strength 1/3), no
contact, no phase change, N x N cells of Q1/Q1 (N = 144: 63 075 DoFs), 100
steps. Every step is one linear system. Runs, one after the other, each
--repeat times (the smallest process wall time kept):

  contact-stefan, 'Coupling/Fixed-point acceleration' = block solve (default):
      a fixed-point pass, one solve of the coupled block system (factorised
      once), a confirming pass;
  contact-stefan, = none (with --plain; slow: about 30 passes per step);
  FEniCSx (benchmarks/fenicsx/thermoelastic_plate.py), one monolithic LU
      factorisation and one solve per step, with MUMPS and with PETSc's own LU
      (--lu petsc, the faster of the two here).

It prints the process wall times (interpreter start-up, imports and JIT
included for FEniCSx), their ratios, the linear solves per step of each, the
agreement of the two codes' total thermoelastic heat and elastic energy (the
same discrete problem: 1e-9 relative expected from the fixed-point tolerance),
and contact-stefan's cost per step by timer section (assembly, factorisation,
solves, output and statistics, other).

    benchmarks/thermoelastic.py --n 144 --repeat 3
    benchmarks/thermoelastic.py --n 48 --plain --markdown
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from ladder import set_path  # noqa: E402
from provenance import provenance_line  # noqa: E402

SCENE = os.path.join(HERE, "scenes", "thermoelastic_plate.prm")
FENICSX = os.path.join(HERE, "fenicsx", "thermoelastic_plate.py")
DEFAULT_BINARY = os.path.join(HERE, "..", "build", "contact-stefan")

# Sections timed inside another section (counted there, not again).
NESTED = {"statistics: elastic energy"}
# Timer sections of contact-stefan by kind (the rest of the wall time is "other").
KINDS = [("factorise", re.compile(r"factoris|setup|assemble conductivity|contact step: assemble$")),
         ("solve", re.compile(r"linear solve|block solve")),
         ("assemble", re.compile(r"assemble|coupling:")),
         ("statistics+output", re.compile(r"statistics|output"))]


def results(stdout):
    values = {}
    for line in stdout.splitlines():
        if line.startswith("RESULT ") and " = " in line:
            name, value = line[len("RESULT "):].rsplit(" = ", 1)
            try:
                values[name] = float(value)
            except ValueError:
                pass
    return values


def sections(stdout):
    """contact-stefan's timer table: section -> (calls, seconds)."""
    table = {}
    for line in stdout.splitlines():
        m = re.match(r"\| (.+?)\s+\|\s+(\d+) \|\s+([0-9.e+-]+)s", line)
        if m:
            table[m.group(1)] = (int(m.group(2)), float(m.group(3)))
    return table


def timed(command, cwd):
    start = time.perf_counter()
    run = subprocess.run(command, capture_output=True, text=True, cwd=cwd)
    elapsed = time.perf_counter() - start
    if run.returncode != 0:
        sys.exit("failed (%d): %s\n%s" % (run.returncode, " ".join(command), run.stderr[-500:]))
    return elapsed, run.stdout


def ours(binary, n, acceleration, work, repeat):
    with open(SCENE) as f:
        text = f.read()
    text = set_path(text, "Geometry/Subdivisions", "%d, %d" % (n, n))
    text = set_path(text, "Coupling/Fixed-point acceleration", acceleration)
    text = set_path(text, "Output/Directory", os.path.join(work, "output-" + acceleration[:5]))
    scene = os.path.join(work, "plate-%s.prm" % acceleration[:5])
    with open(scene, "w") as f:
        f.write(text)
    best = None
    for _ in range(repeat):
        elapsed, stdout = timed([binary, scene], work)
        if best is None or elapsed < best[0]:
            best = (elapsed, stdout)
    return best


def fenicsx(n, lu, work, repeat):
    best = None
    for _ in range(repeat):
        elapsed, stdout = timed(["/usr/bin/python3", FENICSX, "--n", str(n), "--lu", lu], work)
        if best is None or elapsed < best[0]:
            best = (elapsed, stdout)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=144, help="cells per side (default 144)")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--plain", action="store_true",
                        help="also run contact-stefan without the block correction (slow)")
    parser.add_argument("--no-fenicsx", action="store_true")
    parser.add_argument("--binary", default=DEFAULT_BINARY)
    parser.add_argument("--markdown", action="store_true")
    args = parser.parse_args()
    print(provenance_line(args.binary))
    have_fenicsx = (not args.no_fenicsx and subprocess.run(
        ["/usr/bin/python3", "-c", "import dolfinx"], capture_output=True).returncode == 0)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        runs = [("contact-stefan, block solve", ours(args.binary, args.n, "block solve", work,
                                                      args.repeat))]
        if args.plain:
            runs.append(("contact-stefan, plain passes", ours(args.binary, args.n, "none", work,
                                                              args.repeat)))
        if have_fenicsx:
            # A first run fills FFCx's JIT cache: the timed runs load from it.
            fenicsx(args.n, "petsc", work, 1)
            runs.append(("FEniCSx, PETSc LU", fenicsx(args.n, "petsc", work, args.repeat)))
            runs.append(("FEniCSx, MUMPS", fenicsx(args.n, "mumps", work, args.repeat)))
        else:
            print("# FEniCSx not run (/usr/bin/python3 cannot import dolfinx: "
                  "apt-get install python3-dolfinx-real)")
    reference = results(runs[0][1][1])
    steps = 100
    for name, (elapsed, stdout) in runs:
        r = results(stdout)
        if name.startswith("contact-stefan"):
            table = sections(stdout)
            passes = r.get("mean coupling iterations", float("nan"))
            elasticity = (table.get("contact step: linear solve", (0, 0))[0] -
                          r.get("elasticity solves answered by the corrected guess", 0) -
                          r.get("contact solves skipped (unchanged data)", 0)) / steps
            heat = (table.get("enthalpy step: linear solve", (0, 0))[0] -
                    r.get("heat solves answered by the corrected guess", 0)) / steps
            block = r.get("block corrections", 0) / steps
            solves = ("%.2f passes: %.2f elasticity, %.2f heat and %.2f block solves"
                      % (passes, elasticity, heat, block))
        else:
            solves = "%g monolithic solve" % (r.get("linear solves", float("nan")) / steps)
        heat = r.get("total thermoelastic heat", float("nan"))
        energy = r.get("elastic energy", float("nan"))
        rows.append((name, elapsed, solves,
                     abs(heat / reference["total thermoelastic heat"] - 1),
                     abs(energy / reference["elastic energy"] - 1)))
    dofs = int(reference.get("temperature dofs", 0) + reference.get("displacement dofs", 0))
    print("# thermoelastic plate, N = %d (%s DoFs), %d steps" % (args.n, dofs, steps))
    header = ("run", "process wall [s]", "ratio to the first", "linear solves per step",
              "heat vs first", "energy vs first")
    if args.markdown:
        print("| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
    else:
        print("  ".join(header))
    for name, elapsed, solves, dh, de in rows:
        cells = (name, "%.2f" % elapsed, "%.2f" % (elapsed / rows[0][1]), solves,
                 "%.1e" % dh, "%.1e" % de)
        print(("| " + " | ".join(cells) + " |") if args.markdown else "  ".join(cells))

    # contact-stefan's cost per step, by kind of timer section.
    for name, (elapsed, stdout) in runs:
        if not name.startswith("contact-stefan"):
            continue
        table = sections(stdout)
        wall = results(stdout).get("wall time", elapsed)
        by_kind = {kind: 0.0 for kind, _ in KINDS}
        for section, (_, seconds) in table.items():
            if section in NESTED:
                continue
            for kind, pattern in KINDS:
                if pattern.search(section):
                    by_kind[kind] += seconds
                    break
        other = wall - sum(by_kind.values())
        print("# %s: per step (ms): " % name + ", ".join(
            "%s %.1f" % (kind, 1e3 * seconds / steps) for kind, seconds in by_kind.items()) +
            ", other %.1f; in-run wall time %.2f s of a process time %.2f s" % (
                1e3 * other / steps, wall, elapsed))
    return 0


if __name__ == "__main__":
    sys.exit(main())
