#!/usr/bin/python3
"""doc/benchmarks.md T4 (shrink fit with differential expansion) on a refinement ladder.

Runs prm/benchmarks/shrink_fit_T4.prm with 'Geometry/Subdivisions = n, n' for
n = 4, 8, 16, ... (2n cells along the arcs, the interface a polygon of 2n
chords) and prints, per level: DoFs, wall time, the mean contact pressure at
dT = 0 and dT = 5 (the interface force over the polygon's length, against the
Lame pressure p(dT)), the largest nodal pressure error over the run relative to
p(0), the opening temperature dT* (exact 7.692307692) and the mean radial gap
at dT = 10 (exact 3.0e-4), with observed rates between levels.

    benchmarks/t4_ladder.py --levels 5 [--np 2] [--markdown] [--plot doc/figures/t4.png]

Only the standard library is needed; --plot uses matplotlib (Debian's
python3-matplotlib with /usr/bin/python3). Time in benchmarks, never in tests:
quote ratios measured in one run.
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile
from provenance import provenance_line  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENE = os.path.join(ROOT, "prm", "benchmarks", "shrink_fit_T4.prm")

E, NU, B, C, DELTA, DALPHA = 1.0, 0.3, 1.0, 2.0, 1e-3, 1e-4


def exact_pressure(dT):
    d_eff = DELTA - (1 + NU) * DALPHA * B * dT
    return max(d_eff, 0.0) * E * (C * C - B * B) / (2 * B * C * C * (1 - NU * NU))


EXACT_OPENING = DELTA / ((1 + NU) * DALPHA * B)
EXACT_GAP = (1 + NU) * DALPHA * B * 10 - DELTA


def run(binary, n, np_ranks, work):
    text = open(SCENE).read()
    text = re.sub(r"set Subdivisions *=.*", "set Subdivisions = %d, %d" % (n, n), text)
    text = re.sub(r"set Directory *=.*", "set Directory = out-%d" % n, text)
    prm = os.path.join(work, "t4-%d.prm" % n)
    with open(prm, "w") as f:
        f.write(text)
    command = [binary, prm]
    if np_ranks > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(np_ranks)] + command
    out = subprocess.run(command, cwd=work, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("run n = %d failed: %s" % (n, (out.stderr or out.stdout).strip().splitlines()[-1]))
    results = dict(re.findall(r"^RESULT (.*?) = (\S+)$", out.stdout, re.M))
    rows = [line.split() for line in open(os.path.join(work, "out-%d" % n, "statistics.txt"))
            if not line.startswith("#")]
    header, rows = rows[0], rows[1:]
    time, force = header.index("time"), header.index("force_interface_0-1")
    length = 2 * n * 2 * B * math.sin(math.pi / (8 * n))  # the polygon of 2n chords
    mean_pressure = {float(r[time]): float(r[force]) / length for r in rows}
    return {
        "dofs": int(results["displacement dofs"]) + int(results["temperature dofs"]),
        "wall": float(results["wall time"]),
        "p0": mean_pressure[0.0],
        "p5": mean_pressure[5.0],
        "nodal": float(results["max contact pressure error"]) / exact_pressure(0),
        "opening": float(results["opening time interface 0-1"]),
        "gap": float(results["mean gap interface 0-1"]),
    }


def rate(e_coarse, e_fine):
    if e_coarse > 0 and e_fine > 0:
        return "%.2f" % math.log2(e_coarse / e_fine)
    return "-"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--levels", type=int, default=5)
    parser.add_argument("--first", type=int, default=4, help="n of the coarsest level")
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "contact-stefan"))
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--plot", help="PNG of the errors against wall time")
    args = parser.parse_args()
    print(provenance_line(args.binary), flush=True)

    work = tempfile.mkdtemp(prefix="t4-ladder-")
    levels = []
    for level in range(args.levels):
        n = args.first * 2 ** level
        r = run(args.binary, n, args.np, work)
        r["n"] = n
        r["e0"] = abs(r["p0"] - exact_pressure(0)) / exact_pressure(0)
        r["e5"] = abs(r["p5"] - exact_pressure(5)) / exact_pressure(5)
        r["eo"] = abs(r["opening"] - EXACT_OPENING) / EXACT_OPENING
        r["eg"] = abs(r["gap"] - EXACT_GAP) / EXACT_GAP
        levels.append(r)

    columns = ["n", "DoFs", "wall s", "p(0) rel. err", "rate", "p(5) rel. err", "rate",
               "nodal p err / p(0)", "rate", "dT*", "rel. err", "rate", "gap(10)", "rel. err",
               "rate"]
    table = []
    for i, r in enumerate(levels):
        prev = levels[i - 1] if i > 0 else None
        table.append([
            str(r["n"]), str(r["dofs"]), "%.2f" % r["wall"],
            "%.3e" % r["e0"], rate(prev["e0"], r["e0"]) if prev else "-",
            "%.3e" % r["e5"], rate(prev["e5"], r["e5"]) if prev else "-",
            "%.3e" % r["nodal"], rate(prev["nodal"], r["nodal"]) if prev else "-",
            "%.7f" % r["opening"], "%.2e" % r["eo"], rate(prev["eo"], r["eo"]) if prev else "-",
            "%.5e" % r["gap"], "%.2e" % r["eg"], rate(prev["eg"], r["eg"]) if prev else "-",
        ])
    print("T4 shrink fit: p(0) = %.9e, p(5) = %.9e, dT* = %.9f, gap(10) = %.1e (exact)"
          % (exact_pressure(0), exact_pressure(5), EXACT_OPENING, EXACT_GAP))
    if args.markdown:
        print("| " + " | ".join(columns) + " |")
        print("|" + "---|" * len(columns))
        for row in table:
            print("| " + " | ".join(row) + " |")
    else:
        widths = [max(len(c), max(len(row[i]) for row in table)) for i, c in enumerate(columns)]
        print("  ".join(c.rjust(w) for c, w in zip(columns, widths)))
        for row in table:
            print("  ".join(v.rjust(w) for v, w in zip(row, widths)))

    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (by_dofs, by_time) = plt.subplots(1, 2, figsize=(11, 4.2))
        series = [("e0", "mean pressure at dT = 0"), ("e5", "mean pressure at dT = 5"),
                  ("nodal", "max nodal pressure error / p(0)"),
                  ("eo", "opening temperature dT*"), ("eg", "gap at dT = 10")]
        for ax, key_x, label_x in [(by_dofs, "dofs", "DoFs"),
                                   (by_time, "wall", "wall time (s, %d rank%s)"
                                    % (args.np, "s" if args.np > 1 else ""))]:
            x = [r[key_x] for r in levels]
            for key, label in series:
                ax.loglog(x, [max(r[key], 1e-16) for r in levels], "o-", label=label)
            ax.set_xlabel(label_x)
            ax.set_ylabel("relative error")
            ax.grid(True, which="both", alpha=0.3)
        for r in levels:
            by_dofs.annotate("n=%d" % r["n"], (r["dofs"], r["e0"]), fontsize=7,
                             textcoords="offset points", xytext=(3, 3))
        by_dofs.set_title("T4 shrink fit: error against DoFs")
        by_time.set_title("error against run time (small runs: start-up dominates)")
        by_dofs.legend(fontsize=8)
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
        print("wrote", args.plot)


if __name__ == "__main__":
    main()
