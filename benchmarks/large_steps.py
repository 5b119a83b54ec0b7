#!/usr/bin/python3
"""Linear solves per enthalpy step against tau/h^2: active set against truncated Newton.

Neumann case A (prm/benchmarks/neumann_A.prm) at h = 1/128 (level 3, 16 929
DoFs), t = 0.1 -> 1, tau = k h^2/kappa for k in --multiples (default 10, 100,
1000, 10^4). Each tau is run one after the other with 'Enthalpy solver =
active-set' (the default: a step that needs more than 'Truncated Newton
hand-over' solves goes to the truncated Newton method, and so do the following
steps until one needs at most 'Active set hand-back' solves), with
'truncated-newton', and with the active-set method whose hand-over happens only
at 'Max active-set iterations' (hand-over 0, the method before the large-step
mode). The script prints the mean solves per step, the steps that needed the
relaxation fallback, the wall time and the relative space-time L2 error (all
solve the same discrete problem, so the errors must agree). With --plot PATH it
also draws solves per step against tau/h^2.

    benchmarks/large_steps.py --markdown --plot doc/figures/performance-large-steps.png
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from ladder import set_entry, set_path  # noqa: E402
from performance import parse  # noqa: E402
from provenance import provenance_line  # noqa: E402

DEFAULT_BINARY = os.path.join(HERE, "..", "build", "contact-stefan")
SCENE = os.path.join(HERE, "..", "prm", "benchmarks", "neumann_A.prm")
# (label, Solver entries): the default active-set method (with its large-step
# mode), the truncated Newton method, and the active-set method that hands a
# step over only at its iteration limit (the large-step mode off).
SOLVERS = [("active-set", {"Enthalpy solver": "active-set"}),
           ("truncated-newton", {"Enthalpy solver": "truncated-newton"}),
           ("active-set, hand-over at the limit only",
            {"Enthalpy solver": "active-set", "Truncated Newton hand-over": "0"})]


def run(binary, multiple, index, workdir):
    settings = SOLVERS[index][1]
    with open(SCENE) as f:
        text = f.read()
    h = 1.0 / 128
    text = set_entry(text, "Initial global refinements", "3")
    text = set_entry(text, "Time step", repr(multiple * h * h))
    name = f"{index}-{multiple}"
    text = set_entry(text, "Directory", os.path.join(workdir, name))
    for entry, value in settings.items():
        text = set_path(text, "Solver/" + entry, value)
    prm = os.path.join(workdir, f"{name}.prm")
    with open(prm, "w") as f:
        f.write(text)
    start = time.time()
    out = subprocess.run([binary, prm], capture_output=True, text=True)
    wall = time.time() - start
    if out.returncode != 0:
        last = (out.stderr.strip() or out.stdout.strip()).splitlines()[-1:]
        return {"failed": last[0] if last else f"exit {out.returncode}", "wall": wall}
    results, _ = parse(out.stdout)
    results["wall"] = wall
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default=DEFAULT_BINARY)
    parser.add_argument("--multiples", type=float, nargs="+", default=[10, 100, 1000, 10000])
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--plot", metavar="PATH")
    args = parser.parse_args()
    print(provenance_line(args.binary), flush=True)
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"large_steps.py: no executable '{args.binary}' (build first)")

    rows, curves = [], {s: [] for s, _ in SOLVERS}
    with tempfile.TemporaryDirectory() as workdir:
        for k in args.multiples:
            for index, (solver, _) in enumerate(SOLVERS):
                r = run(args.binary, k, index, workdir)
                if "failed" in r:
                    rows.append([f"{k:g}", solver, "failed", "", f"{r['wall']:.2f}", r["failed"]])
                    continue
                solves = r["mean active-set iterations"]
                curves[solver].append((k, solves))
                rows.append([f"{k:g}", solver, f"{solves:.2f}",
                             f"{r['steps with relaxation fallback']:.0f}", f"{r['wall']:.2f}",
                             f"{r['relative space-time L2 error temperature']:.10g}"])
                print(" ".join(rows[-1]), file=sys.stderr)

    headers = ["tau kappa/h^2", "enthalpy solver", "solves per step", "relaxation steps",
               "wall [s]", "space-time error"]
    if args.markdown:
        print("| " + " | ".join(headers) + " |")
        print("|" + "---|" * len(headers))
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
        print("  ".join(h.rjust(w) for h, w in zip(headers, widths)))
        for row in rows:
            print("  ".join(c.rjust(w) for c, w in zip(row, widths)))

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(5.5, 3.8))
        for (solver, _), marker in zip(SOLVERS, "os^"):
            if curves[solver]:
                x, y = zip(*curves[solver])
                ax.semilogx(x, y, marker=marker, label=solver)
        ax.axhline(6, color="grey", linestyle=":", label="target (6)")
        ax.set_xlabel(r"time step $\tau\kappa/h^2$")
        ax.set_ylabel("linear solves per step")
        ax.set_title("Neumann case A, h = 1/128")
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print(f"wrote {args.plot}", file=sys.stderr)


if __name__ == "__main__":
    main()
