#!/usr/bin/python3
"""The freezing slab of doc/benchmarks.md B1: the crust's stress profile against
the closed form, on three meshes, with and without 'Stress free at solidification'.

Computes the Neumann constant lambda of the mirrored case A independently (the
Stefan condition  L lambda sqrt(pi) = e^{-lambda^2} (1/erf lambda - 1/erfc lambda),
bisection with math.erf/erfc), checks that the scene file uses it, runs
tests/scenes/birth_freezing_slab.prm on levels 0, 1, 2 (global refinement, tau
halved) and once with the switch off, and plots sigma_xx of the cell centres at
t = 1 against the exact profile

    crust (y < 2 lambda sqrt t):  -E_s alpha/(1 - nu) (-1 + erf(eta)/erf(lambda))
    melt:                         -E_l alpha/(1 - nu) (1 - erfc(eta)/erfc(lambda))

with eta = y / (2 sqrt t). Prints the run time and the errors of each run.

    /usr/bin/python3 benchmarks/birth_slab.py [--binary build/contact-stefan]
        [--plot doc/figures/birth_freezing_slab.png]

Needs Debian's python3-matplotlib and python3-meshio for the picture.
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENE = os.path.join(ROOT, "tests", "scenes", "birth_freezing_slab.prm")
sys.path.insert(0, HERE)
from ladder import set_path  # noqa: E402

E_S, E_L, NU, ALPHA, T_END = 1000.0, 10.0, 0.25, 1e-4, 1.0


def neumann_lambda():
    def f(l):
        return l * math.sqrt(math.pi) - math.exp(-l * l) * (1 / math.erf(l) - 1 / math.erfc(l))
    a, b = 1e-6, 2.0
    for _ in range(200):
        m = 0.5 * (a + b)
        a, b = (m, b) if f(m) < 0 else (a, m)
    return 0.5 * (a + b)


def exact_sigma_xx(y, lam, t=T_END):
    eta = y / (2 * math.sqrt(t))
    if y < 2 * lam * math.sqrt(t):
        return -E_S * ALPHA / (1 - NU) * (-1 + math.erf(eta) / math.erf(lam))
    return -E_L * ALPHA / (1 - NU) * (1 - math.erfc(eta) / math.erfc(lam))


def run(binary, text, workdir, settings):
    for path, value in settings.items():
        text = set_path(text, path, value)
    os.makedirs(workdir, exist_ok=True)
    with open(os.path.join(workdir, "scene.prm"), "w") as f:
        f.write(text)
    out = subprocess.run([binary, "scene.prm"], cwd=workdir, capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("run failed in %s:\n%s" % (workdir, out.stderr))
    results = dict((m.group(1), float(m.group(2))) for m in
                   re.finditer(r"^RESULT (.+?) = (\S+)$", out.stdout, re.M))
    return results


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "contact-stefan"))
    parser.add_argument("--plot", default=None, help="PNG file for the profiles")
    args = parser.parse_args()
    lam = neumann_lambda()
    text = open(SCENE).read()
    if "%.10f" % lam not in text:
        sys.exit("the scene does not use lambda = %.10f" % lam)
    print("lambda = %.10f (front at t = 1: %.10f)" % (lam, 2 * lam))
    runs = [("level %d" % level, {"Mesh refinement/Initial global refinements": str(level),
                                  "Time stepping/Time step": repr(0.125 / 2**level)})
            for level in range(3)]
    runs.append(("level 2, switch off", dict(
        runs[2][1], **{"Materials/Body 0/Phase change/Stress free at solidification": "false"})))
    tmp = tempfile.mkdtemp(prefix="birth-slab-")
    profiles = []
    print("%-22s %8s %9s %12s %12s" % ("run", "cells", "wall [s]", "cell L2 err", "recov L2 err"))
    for k, (name, settings) in enumerate(runs):
        settings = dict(settings, **{"Output/VTU interval": "100000",
                                     "Output/Directory": "output"})
        workdir = os.path.join(tmp, "run%d" % k)
        r = run(args.binary, text, workdir, settings)
        cells = 32 * 4**int(settings["Mesh refinement/Initial global refinements"])
        print("%-22s %8d %9.2f %12.3e %12.3e" % (
            name, cells, r["wall time"], r["max relative stress L2 error (cell centres)"],
            r["max relative stress L2 error (recovered)"]))
        profiles.append((name, workdir))
    if not args.plot:
        return
    from plot_run import np, plt, read_pvd  # noqa: E402
    import meshio  # noqa: E402
    import xml.etree.ElementTree as ET  # noqa: E402
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ys = np.linspace(0, 1.4, 600)
    ax.plot(ys, [exact_sigma_xx(y, lam) for y in ys], "k-", lw=1.5, label="exact (born at $\\Theta_m$)")
    styles = ["o", "s", "^", "x"]
    for (name, workdir), style in zip(profiles, styles):
        directory = os.path.join(workdir, "output")
        last = read_pvd(os.path.join(directory, "solution.pvd"))[-1][1]
        centres, values = [], []
        for piece in ET.parse(os.path.join(directory, last)).getroot().iter("Piece"):
            m = meshio.read(os.path.join(directory, piece.get("Source")))
            quads = m.cells_dict["quad"]
            # Cell data are written as constant point data on each cell's own vertices.
            for quad in quads:
                y = m.points[quad, 1].mean()
                if y < 1.4:
                    centres.append(y)
                    values.append(m.point_data["cell_stress_xx"][quad[0]])
        order = np.argsort(centres)
        ax.plot(np.array(centres)[order], np.array(values)[order], style, ms=3.5,
                mfc="none", label=name)
    ax.axvline(2 * lam, color="0.6", ls=":", lw=1)
    ax.text(2 * lam, ax.get_ylim()[1] * 0.9, " front", color="0.4")
    ax.set_xlabel("distance from the cold wall y")
    ax.set_ylabel("$\\sigma_{xx}$ at the cell centres, t = 1")
    ax.set_title("Freezing slab held laterally: crust born stress-free at $\\Theta_m$")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.plot, dpi=120)
    print("wrote", args.plot)


if __name__ == "__main__":
    main()
