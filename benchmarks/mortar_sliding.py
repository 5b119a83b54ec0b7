#!/usr/bin/python3
"""The picture of large sliding across a mortar interface (doc/contact.md,
doc/benchmarks.md M7): the block of tests/scenes/mortar_sliding.prm sliding
along its base, refined, on the sides' true positions (x + u, the slide not
magnified), with the temperature and the contact pressure along the wall.

    /usr/bin/python3 benchmarks/mortar_sliding.py BUILD_DIR [--refinements 2]
                     [--time-step 0.25] [--output doc/figures/mortar_sliding.png]

Writes the meshes with tests/make_mortar_msh.py, runs the scene with
'Mesh refinement/Initial global refinements' and 'Time stepping/Time step' as
given (the default 0.25 slides the block by about one of its edges, 0.023 m,
per step) and a VTU file after every step, and draws four moments of the slide
and the pressure at the block's slave nodes at those moments. Prints the run's
RESULT wall time and the timer section of the couplings. Needs Debian's
python3-matplotlib and python3-meshio.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "tests"))
from ladder import set_path  # noqa: E402
from plot_run import np, plt, read_pieces, read_pvd, triangulation  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("build")
    parser.add_argument("--refinements", type=int, default=2)
    parser.add_argument("--time-step", type=float, default=0.25)
    parser.add_argument("--output", default=os.path.join(HERE, "..", "doc", "figures",
                                                         "mortar_sliding.png"))
    args = parser.parse_args()
    root = os.path.join(HERE, "..")
    binary = os.path.join(args.build, "contact-stefan")
    with open(os.path.join(root, "tests", "scenes", "mortar_sliding.prm")) as f:
        text = f.read()
    with tempfile.TemporaryDirectory() as work:
        mesh = os.path.join(work, "sliding.msh")
        subprocess.run(["/usr/bin/python3", os.path.join(root, "tests", "make_mortar_msh.py"),
                        mesh, "--width", "2", "--lower", "8,2", "--upper", "5,4",
                        "--upper-width", "0.5", "--shift", "0.3"], check=True)
        out = os.path.join(work, "output")
        for path, value in [("Geometry/Mesh file", mesh), ("Output/Directory", out),
                            ("Output/VTU interval", "1"),
                            ("Time stepping/Time step", repr(args.time_step)),
                            ("Mesh refinement/Initial global refinements",
                             str(args.refinements))]:
            text = set_path(text, path, value)
        scene = os.path.join(work, "scene.prm")
        with open(scene, "w") as f:
            f.write(text)
        run = subprocess.run([binary, scene], capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit("the run failed: " + run.stderr.strip()[-300:])
        for line in run.stdout.splitlines():
            if (line.startswith("RESULT wall time") or "setup: sliding" in line
                    or line.startswith("RESULT mortar sliding")
                    or line.startswith("RESULT max relative enthalpy change through sliding")):
                print(line)
        records = read_pvd(os.path.join(out, "solution.pvd"))
        # Four moments: the start, a third and two thirds of the slide, its end.
        wanted = [0.0, 10.0 / 3, 20.0 / 3, 10.0]
        chosen = [min(records, key=lambda r: abs(r[0] - t)) for t in wanted]
        frames = [(t,) + read_pieces(out, f) for t, f in chosen]

    all_T = np.concatenate([d["temperature"] for _, _, _, d in frames])
    levels = np.linspace(all_T.min(), all_T.max(), 21)
    from matplotlib.collections import PolyCollection
    fig = plt.figure(figsize=(11, 8.5), constrained_layout=True)
    grid = fig.add_gridspec(3, 2, height_ratios=[1, 1, 1.1])
    field_axes = []
    for k, (t, points, quads, data) in enumerate(frames):
        ax = fig.add_subplot(grid[k // 2, k % 2])
        u = data["displacement"][:, :2]
        tri = triangulation(points, quads, u)
        c = ax.tricontourf(tri, data["temperature"], levels=levels, cmap="inferno")
        # The cells (quadrilaterals) where they are.
        ax.add_collection(PolyCollection((points + u)[quads], facecolors="none",
                                         edgecolors="white", linewidths=0.2, alpha=0.5))
        field_axes.append(ax)
        ax.set_aspect("equal")
        ax.set_xlim(-0.02, 2.02)
        ax.set_ylim(-0.02, 1.02)
        ax.set_title("t = %.2f s: slid %.3f m" % (t, 0.093 * min(t, 10.0)), fontsize=10)
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
    fig.colorbar(c, ax=field_axes, shrink=0.8, label="temperature")
    ax = fig.add_subplot(grid[2, :])
    for t, points, quads, data in frames:
        p = data["contact_pressure"]
        x = points[:, 0] + data["displacement"][:, 0]
        on = (p > 0) & (np.abs(points[:, 1] - 0.5) < 1e-12)
        order = np.argsort(x[on])
        ax.plot(x[on][order], 1e3 * p[on][order], ".-", ms=3,
                label="t = %.2f s" % t)
    ax.set_xlim(-0.02, 2.02)
    ax.set_xlabel("x of the block's slave node, where it is (m)")
    ax.set_ylabel("contact pressure (10⁻³)")
    ax.legend(fontsize=8, ncol=4)
    ax.set_title("pressure along the wall: the block's nodes, paired with the base where "
                 "they are", fontsize=10)
    fig.suptitle("Large sliding across a mortar interface (tests/scenes/mortar_sliding.prm, "
                 "%d refinements, τ = %g s)" % (args.refinements, args.time_step), fontsize=11)
    fig.savefig(args.output, dpi=110)
    print("wrote " + os.path.relpath(args.output))


if __name__ == "__main__":
    main()
