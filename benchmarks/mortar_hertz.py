#!/usr/bin/python3
"""Hertz contact of two elastic bodies across a non-matching interface
(benchmark M5 of doc/benchmarks.md): error against the closed form, DoFs,
active-set iterations and run time, over mesh ratios, slave choices and
adaptive levels.

    /usr/bin/python3 benchmarks/mortar_hertz.py [BUILD_DIR] [--levels 6,7,8,9]
                     [--buffer 2] [--time-step 0.1] [--matching-only]
                     [--signed] [--plot doc/figures/mortar_hertz.png]

The scene is tests/scenes/mortar_hertz.prm: two blocks [-2, 2] x [0, 2]
(E = 1, nu = 0.3) and [-2, 2] x [2, 4] (E = 2, nu = 0.25), meshed independently
by tests/make_mortar_msh.py with base cells 0.25 and 1/12, the interface gap the
profile of a cylinder of radius 1, adapted after every step to the contact zone
up to 'Mesh refinement/Maximum level' (each level given) with 'Contact buffer'
as given. For h_top/h_bottom = 1/3 and 3 it runs both slave choices: the finer
side (the default rule) and the coarser side ('Mortar slave' = k or l); for
ratio 1 the default. It also runs the matching mesh (shared nodes, node-to-node
interface) as the reference for the active-set iterations. Each row: the final
displacement DoFs, the contact-node spacing, the half-width error of both
measures (the lumped length of the active nodes; the contact edges where p^2
extrapolates to zero, doc/benchmarks.md M5), the peak-pressure and profile
errors, the most active-set iterations in a step, the active nodes outside the
exact contact zone, and the run's wall time (one
run each, one after the other; compare ratios, not absolute times).

--time-step sets the step (the load is the same function of t up to t = 1;
0.05 doubles the adaptations, which also refine the bulk), --matching-only runs
the matching mesh alone (the converged answer of these finite blocks, doc M5),
--signed prints the half-width (edges) and peak-pressure errors with their sign.

--plot draws the peak-pressure and half-width (edge) errors against the DoFs
(needs Debian's python3-matplotlib).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
from ladder import run_text, set_path  # noqa: E402

SCENE = os.path.join(ROOT, "tests/scenes/mortar_hertz.prm")
MESHER = os.path.join(ROOT, "tests/make_mortar_msh.py")
COARSE, FINE = "16,8", "48,24"
# (label, lower cells, upper cells, the coarser side's body letter)
RATIOS = [("1/3", COARSE, FINE, "k"), ("1", COARSE, COARSE, None), ("3", FINE, COARSE, "l")]
QUANTITIES = ["displacement dofs", "contact mesh width", "Hertz half-width relative error",
              "Hertz contact edge half-width relative error",
              "Hertz peak pressure relative error", "Hertz pressure profile relative L2 error",
              "max contact iterations", "Hertz active nodes outside the exact contact zone"]


def run(binary, work, name, mesh_file, level, buffer, time_step, slave=None, nodal=False):
    with open(SCENE) as f:
        text = f.read()
    text = set_path(text, "Geometry/Mesh file", mesh_file)
    text = set_path(text, "Mesh refinement/Maximum level", str(level))
    text = set_path(text, "Mesh refinement/Contact buffer", str(buffer))
    text = set_path(text, "Output/Directory", name)
    text = set_path(text, "Time stepping/Time step", repr(time_step))
    if slave:
        text = set_path(text, "Contact/Interface 1-2/Mortar slave", slave)
    if nodal:
        text = set_path(text, "Contact/Interface 1-2/Discretisation", "nodal")
        text = set_path(text, "Contact/Interface 1-2/Mortar boundaries", "")
    out, elapsed = run_text(binary, work, name, text)
    values = {q: float(re.search(r"^RESULT %s = (\S+)" % re.escape(q), out, re.M).group(1))
              for q in QUANTITIES}
    values["wall"] = elapsed
    signed = lambda q: float(re.search(r"^RESULT Hertz %s = (\S+)" % q, out, re.M).group(1))
    values["signed a"] = signed("contact edge half-width") / signed("exact half-width") - 1
    values["signed p0"] = signed("peak pressure") / signed("exact peak pressure") - 1
    return values


def row(label, slave, level, v, signed):
    if signed:
        print("| %s | %s | %d | %d | %+.4f %% | %+.4f %% |" % (
            label, slave, level, v["displacement dofs"], 100 * v["signed a"],
            100 * v["signed p0"]))
        return
    print("| %s | %s | %d | %d | %.1e | %.2f %% | %.2f %% | %.2f %% | %.2f %% | %d | %d | %.1f |"
          % (label, slave, level, v["displacement dofs"], v["contact mesh width"],
             100 * v["Hertz half-width relative error"],
             100 * v["Hertz contact edge half-width relative error"],
             100 * v["Hertz peak pressure relative error"],
             100 * v["Hertz pressure profile relative L2 error"],
             v["max contact iterations"],
             v["Hertz active nodes outside the exact contact zone"], v["wall"]))


def plot(results, path):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("no matplotlib (use Debian's /usr/bin/python3): no picture")
        return
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, quantity, title in [
            (axes[0], "Hertz peak pressure relative error", "peak pressure p0"),
            (axes[1], "Hertz contact edge half-width relative error",
             "half-width a (contact edges)")]:
        for (label, slave), rows in results.items():
            if label == "matching":
                continue
            dofs = [v["displacement dofs"] for _, v in rows]
            errors = [max(v[quantity], 1e-6) for _, v in rows]
            style = "-o" if "coarser" in slave or "(=)" in slave else "--s"
            ax.loglog(dofs, errors, style, label="h_top/h_bottom = %s, slave %s" % (label, slave))
        ax.axhline(2e-3, color="grey", lw=0.8)
        ax.axvline(25000, color="grey", lw=0.8)
        ax.set_xlabel("displacement DoFs (levels %s)" % ", ".join(
            str(level) for level, _ in next(iter(results.values()))))
        ax.set_ylabel("relative error")
        ax.set_title(title)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].legend(fontsize=7)
    fig.suptitle("Hertz across a non-matching mortar interface (grey: 0.2 %, 25 000 DoFs)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    print("wrote", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build", nargs="?", default=os.path.join(ROOT, "build"))
    parser.add_argument("--levels", default="6,7,8,9")
    parser.add_argument("--buffer", type=int, default=2)
    parser.add_argument("--time-step", type=float, default=0.1)
    parser.add_argument("--matching-only", action="store_true")
    parser.add_argument("--signed", action="store_true")
    parser.add_argument("--plot")
    args = parser.parse_args()
    binary = os.path.join(os.path.abspath(args.build), "contact-stefan")
    levels = [int(v) for v in args.levels.split(",")]
    if args.signed:
        print("| h_top/h_bottom | slave | level | DoFs | a error (edges) | p0 error |")
        print("|---|---|---|---|---|---|")
    else:
        print("| h_top/h_bottom | slave | level | DoFs | contact spacing | a error (lumped) "
              "| a error (edges) | p0 error | profile L2 error | most PDAS iterations in a "
              "step | outside | run (s) |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    results = {}
    with tempfile.TemporaryDirectory() as work:
        for label, lower, upper, coarser in [] if args.matching_only else RATIOS:
            mesh = os.path.join(work, "ratio_%s.msh" % label.replace("/", "_"))
            subprocess.run([sys.executable, MESHER, mesh, "--width", "4", "--height", "2",
                            "--centre", "--lower", lower, "--upper", upper], check=True)
            choices = [("finer", "finer (=)" if coarser is None else "finer")]
            if coarser:
                choices.append((coarser, coarser + " (coarser)"))
            for slave, name in choices:
                rows = results.setdefault((label, name), [])
                for level in levels:
                    v = run(binary, work, "run", mesh, level, args.buffer, args.time_step,
                            slave)
                    rows.append((level, v))
                    row(label, name, level, v, args.signed)
        merged = os.path.join(work, "matching.msh")
        subprocess.run([sys.executable, MESHER, merged, "--width", "4", "--height", "2",
                        "--centre", "--lower", COARSE, "--upper", COARSE, "--merge"],
                       check=True)
        rows = results.setdefault(("matching", "node-to-node"), [])
        for level in levels:
            v = run(binary, work, "run", merged, level, args.buffer, args.time_step,
                    nodal=True)
            rows.append((level, v))
            row("1 (shared nodes)", "node-to-node", level, v, args.signed)
    if args.plot:
        plot(results, args.plot)


if __name__ == "__main__":
    main()
