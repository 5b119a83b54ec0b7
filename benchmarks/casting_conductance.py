#!/usr/bin/python3
"""The casting with perfect thermal contact and with the gap conductance
(doc/scenes.md, doc/interface_heat.md): runs prm/casting.prm both ways (the
conductance settings are the test's, read from tests/cmake/interface_heat.cmake,
and both runs take its pins of the scene before 2026-12-07: 8 x 8, no adaptation,
the linear interference),
prints the melt area, the mean conductance and the heat rate over time, and
plots them to doc/figures/casting_conductance.png.

    benchmarks/casting_conductance.py BUILD_DIR [OUTPUT.png]
    benchmarks/casting_conductance.py BUILD_DIR --mortar

With --mortar it runs the gap conductance on the matching mesh
(prm/casting.prm, Subdivisions = n, n) and across the mortar wall
(prm/casting_mortar.prm, Subdivisions = n, 3n/4, 3n/2: the die meshed on its
own, coarser along the wall) for n = 8, 16, 32, and prints the table of
doc/scenes.md: melt area, heat crossed, mean h and contact force at 60 s, and
plots the melt fraction and the closed share of the wall over time to
doc/figures/casting_conductance_mortar.png.
"""
import math
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def scene_settings():
    """The entries of settings() that fix the scene itself, not its thermal contact:
    the mesh and the interference of the scene before 2026-12-07 (doc/scenes.md),
    for the perfect-contact run, so that both runs are of one scene."""
    return [s for s in settings()
            if s.startswith("SET:Mesh refinement/") or s.startswith("SET:Contact/Interface gap=")]


def settings():
    text = open(os.path.join(ROOT, "tests/cmake/interface_heat.cmake")).read()
    block = re.search(r"set\(CASTING_CONDUCTANCE\n(.*?)\)\n", text, re.S).group(1)
    return re.findall(r'"(SET:[^"]*)"', block)


def run(binary, work, name, extra, prm="prm/casting.prm"):
    scene = os.path.join(work, name + ".prm")
    with open(os.path.join(ROOT, prm)) as f:
        text = f.read().replace("include include/", "include %s/prm/include/" % ROOT)
    with open(scene, "w") as f:
        f.write(text)
    subprocess.run([os.path.join(ROOT, "tests/apply_settings.sh"), scene,
                    "SET:Output/Directory=" + name, "SET:Output/VTU interval=0"] + extra,
                   check=True, stdout=subprocess.DEVNULL)
    start = time.time()
    subprocess.run([binary, scene], cwd=work, check=True, stdout=subprocess.DEVNULL)
    elapsed = time.time() - start
    rows, names = [], []
    for line in open(os.path.join(work, name, "statistics.txt")):
        if line.startswith("#"):
            continue
        if not names:
            names = line.split()
            continue
        rows.append(dict(zip(names, map(float, line.split()))))
    return rows, elapsed


def pyplot():
    """matplotlib's pyplot without a display, or None (with a message)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        return plt
    except ImportError:
        print("no matplotlib (use Debian's /usr/bin/python3): no picture")
        return None


def mortar_table(binary, png):
    print("casting cells along the wall | die cells | melt area matching / mortar (m^2) | "
          "heat crossed matching / mortar (J/m) | mean h matching / mortar (W/(m^2 K)) | "
          "contact force matching / mortar (N/m) | run matching / mortar (s)")
    curves = []
    with tempfile.TemporaryDirectory() as work:
        for n in (8, 16, 32):
            matching, t_matching = run(binary, work, "matching%d" % n,
                                       settings() + ["SET:Geometry/Subdivisions=%d, %d" % (n, n)])
            mortar, t_mortar = run(binary, work, "mortar%d" % n,
                                   settings() + ["SET:Geometry/Subdivisions=%d, %d, %d"
                                                 % (n, 3 * n // 4, 3 * n // 2)],
                                   "prm/casting_mortar.prm")
            a, b = matching[-1], mortar[-1]
            force = [k for k in a if k.startswith("force_interface")][0]
            # Heat crossed: each step's end rate times its length (the
            # implicit step's own accounting).
            crossed = [sum(r["heat_rate_interface_0_1"] * (r["time"] - q["time"])
                           for q, r in zip(rows, rows[1:])) for rows in (matching, mortar)]
            print(f"{2 * n} | {3 * n // 2} | {a['liquid_area']:.4e} / {b['liquid_area']:.4e} "
                  f"({100 * (b['liquid_area'] / a['liquid_area'] - 1):+.1f} %) | "
                  f"{crossed[0]:.4e} / {crossed[1]:.4e} ({100 * (crossed[1] / crossed[0] - 1):+.1f} %) | "
                  f"{a['mean_h_interface_0_1']:.0f} / {b['mean_h_interface_0_1']:.0f} | "
                  f"{a[force]:.3e} / {b[force]:.3e} | {t_matching:.2f} / {t_mortar:.2f}")
            curves.append((n, matching, mortar))
    plt = pyplot()
    if plt is None:
        return 0
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    area0 = curves[0][1][0]["liquid_area"]
    for k, (n, matching, mortar) in enumerate(curves):
        t = [r["time"] for r in matching]
        ax[0].plot(t, [r["liquid_area"] / area0 for r in matching], "C%d-" % k,
                   label="matching, %d cells" % (2 * n))
        ax[0].plot(t, [r["liquid_area"] / area0 for r in mortar], "C%d--" % k,
                   label="mortar, %d : %d" % (2 * n, 3 * n // 2))
        ax[1].plot(t, [r["active_nodes"] / matching[0]["active_nodes"] for r in matching],
                   "C%d-" % k)
        ax[1].plot(t, [r["active_nodes"] / mortar[0]["active_nodes"] for r in mortar], "C%d--" % k)
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("liquid fraction of the casting")
    ax[0].legend(fontsize=7)
    ax[0].set_title("gap conductance: matching wall (solid), mortar wall (dashed)")
    ax[0].title.set_fontsize(9)
    ax[1].set_xlabel("t [s]")
    ax[1].set_ylabel("closed wall nodes / all")
    ax[1].set_title("contact closed along the wall")
    ax[1].title.set_fontsize(9)
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print("wrote", png)
    return 0


def main():
    if "--mortar" in sys.argv:
        build = sys.argv[1] if sys.argv[1] != "--mortar" else os.path.join(ROOT, "build")
        return mortar_table(os.path.abspath(os.path.join(build, "contact-stefan")),
                            os.path.join(ROOT, "doc/figures/casting_conductance_mortar.png"))
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
    png = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "doc/figures/casting_conductance.png")
    binary = os.path.abspath(os.path.join(build, "contact-stefan"))
    with tempfile.TemporaryDirectory() as work:
        perfect, t_perfect = run(binary, work, "perfect", scene_settings())
        gap, t_gap = run(binary, work, "conductance", settings())
    # Fractions of the casting (the quarter disk of radius 50 mm), the
    # table's of doc/scenes.md: with perfect contact the wall's nodes start at
    # the mixed temperature, below the melting point, so not at 1.
    area0 = math.pi * 0.05**2 / 4
    print(f"run time: perfect {t_perfect:.2f} s, conductance {t_gap:.2f} s "
          f"(ratio {t_gap / t_perfect:.2f}, one run each)")
    print(" t [s]  liquid perfect  liquid gap  mean h [W/(m^2 K)]  heat rate [W/m]  active nodes")
    for p, g in zip(perfect, gap):
        if int(p["step"]) % 10 == 0:
            print(f"{p['time']:6.0f}  {p['liquid_area'] / area0:14.3f}  {g['liquid_area'] / area0:10.3f}"
                  f"  {g['mean_h_interface_0_1']:18.0f}  {g['heat_rate_interface_0_1']:15.0f}"
                  f"  {int(g['active_nodes']):12d}")
    plt = pyplot()
    if plt is None:
        return 0
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8))
    t = [r["time"] for r in perfect]
    ax[0].plot(t, [r["liquid_area"] / area0 for r in perfect], label="perfect contact")
    ax[0].plot(t, [r["liquid_area"] / area0 for r in gap], label="gap conductance")
    ax[0].set_xlabel("t [s]")
    ax[0].set_ylabel("liquid fraction of the casting")
    ax[0].legend()
    ax[0].set_title("solidification")
    ax[1].plot(t, [r["mean_h_interface_0_1"] for r in gap], "C1", label="mean h")
    ax[1].set_xlabel("t [s]")
    ax[1].set_ylabel("mean h [W/(m² K)]", color="C1")
    twin = ax[1].twinx()
    twin.plot(t, [r["active_nodes"] for r in gap], "C2--", label="closed nodes")
    twin.set_ylabel("interface nodes in contact", color="C2")
    ax[1].set_title("the gap opens, h falls")
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    print("wrote", png)
    return 0


if __name__ == "__main__":
    sys.exit(main())
