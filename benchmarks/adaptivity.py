#!/usr/bin/python3
"""Adaptive against global refinement: error against DoFs and against wall time.

Three experiments (doc/adaptivity.md), each printed as a table:

  stefan    Neumann case A (S1, prm/benchmarks/neumann_A.prm). Global level L:
            the 64 x 4 mesh refined L times, tau = h = 1/(16 2^L). Adaptive level
            L: the 64 x 4 mesh adapted after every step (and L times to the
            initial data) up to level L, the same tau, coarsen fraction 0.02
            (the default 0.05 ends 0.13 % above the global error). Compared: the space-time
            L2 error of the temperature against the (time-averaged) DoFs and the
            wall time, and the front error in local mesh widths.
  hertz     C1 (prm/benchmarks/hertz_C1.prm) without its geometric pre-refinement.
            Global level L: the 16 x 8 mesh refined L times, one step. Adaptive
            level L: a ramp of 10 steps on the 16 x 8 mesh, adapted after every
            step up to level L. Compared: the errors of a and p0 against the DoFs
            of the final mesh.
  coupled   The coupled scene prm/coupled_melting_contact.prm (melting at a
            contact interface, both couplings on). No exact solution: the global
            level --levels + 1 is the reference; compared are the melt area and
            the contact force at the end against the (time-averaged) DoFs. With
            --pictures DIR, the adaptive run's mesh at three times is drawn.

    /usr/bin/python3 benchmarks/adaptivity.py [--problem all] [--levels 3]
        [--markdown] [--plot doc/figures/adaptivity] [--pictures doc/figures/adaptivity]

Time runs when nothing else runs on the machine.
"""
import argparse
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from ladder import set_entry, set_path  # noqa: E402
from performance import run, table  # noqa: E402

ROOT = os.path.dirname(HERE)
DEFAULT_BINARY = os.path.join(ROOT, "build", "contact-stefan")
SCENES = {"stefan": os.path.join(ROOT, "prm", "benchmarks", "neumann_A.prm"),
          "hertz": os.path.join(ROOT, "prm", "benchmarks", "hertz_C1.prm"),
          "coupled": os.path.join(ROOT, "prm", "coupled_melting_contact.prm")}


def with_settings(text, settings):
    """Set 'Subsection/Entry' paths to values (replaced where the scene sets
    them, appended otherwise: contact-stefan refuses an entry set twice)."""
    for path, value in settings.items():
        text = set_path(text, path, value)
    return text


def run_scene(binary, problem, settings, workdir, name, np_=1):
    with open(SCENES[problem]) as f:
        text = f.read()
    directory = os.path.join(workdir, name)
    text = with_settings(text, {"Output/Directory": directory, "Output/VTU interval": "0",
                                **settings})
    prm = os.path.join(workdir, name + ".prm")
    with open(prm, "w") as f:
        f.write(text)
    cmd = [binary, prm] if np_ == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe",
                                           "-np", str(np_), binary, prm]
    result = run(cmd, f"{problem} {name}")
    if result is None:
        sys.exit(1)
    results, _ = result
    results["directory"] = directory
    return results


def adaptive_settings(level, interval=1, initial=None):
    return {"Mesh refinement/Adaptive refinement interval": str(interval),
            "Mesh refinement/Initial adaptive refinements": str(level if initial is None
                                                               else initial),
            "Mesh refinement/Maximum level": str(level)}


def dofs_of(r, field="temperature dofs"):
    return r.get("time-averaged dofs", r.get(field))


def stefan(binary, levels, workdir):
    rows, curves = [], {"global": [], "adaptive": []}
    for level in range(1, levels + 1):
        tau = repr(0.0625 / 2**level)
        g = run_scene(binary, "stefan", {"Mesh refinement/Initial global refinements": str(level),
                                         "Time stepping/Time step": tau}, workdir, f"global-{level}")
        a = run_scene(binary, "stefan", {"Time stepping/Time step": tau,
                                         "Mesh refinement/Coarsen fraction": "0.02",
                                         **adaptive_settings(level)}, workdir, f"adaptive-{level}")
        for kind, r in (("global", g), ("adaptive", a)):
            e = r["relative space-time L2 error temperature"]
            curves[kind].append((dofs_of(r), r["wall time"], e))
            rows.append([str(level), kind, f"{dofs_of(r):.0f}", f"{e:.4e}",
                         f"{r.get('front position error in local mesh widths', r['front position error in mesh widths']):.3f}",
                         f"{r['wall time']:.2f}"])
        rows.append(["", "ratio", f"{dofs_of(g) / dofs_of(a):.2f}",
                     f"{a['relative space-time L2 error temperature'] / g['relative space-time L2 error temperature']:.4f}",
                     "", f"{g['wall time'] / a['wall time']:.2f}"])
    return (["level", "mesh", "DoFs (time-avg.)", "space-time L2 error", "front error / local h",
             "wall [s]"], rows, curves, "relative space-time L2 error (temperature)")


def hertz(binary, levels, workdir):
    rows, curves = [], {"global": [], "adaptive": []}
    base = {"Mesh refinement/Pre-refinement radius": "0"}
    for level in range(levels + 1):
        g = run_scene(binary, "hertz", {**base, "Mesh refinement/Initial global refinements":
                                        str(level)}, workdir, f"global-{level}")
        curves["global"].append((g["displacement dofs"], g["wall time"],
                                 g["Hertz half-width relative error"]))
        rows.append([str(level), "global", f"{g['displacement dofs']:.0f}",
                     f"{g['Hertz half-width relative error']:.3e}",
                     f"{g['Hertz peak pressure relative error']:.3e}", f"{g['wall time']:.2f}"])
    for level in range(levels, levels + 5):
        a = run_scene(binary, "hertz", {**base, "Time stepping/Time step": "0.1",
                                        "Mesh refinement/Coarsen fraction": "0.02",
                                        "Mesh refinement/Contact buffer": "3",
                                        **adaptive_settings(level, initial=0)},
                      workdir, f"adaptive-{level}")
        curves["adaptive"].append((a["displacement dofs"], a["wall time"],
                                   a["Hertz half-width relative error"]))
        rows.append([str(level), "adaptive", f"{a['displacement dofs']:.0f}",
                     f"{a['Hertz half-width relative error']:.3e}",
                     f"{a['Hertz peak pressure relative error']:.3e}", f"{a['wall time']:.2f}"])
    return (["level", "mesh", "DoFs (final)", "a rel. error", "p0 rel. error", "wall [s]"], rows,
            curves, "relative error of the contact half-width a")


def coupled(binary, levels, workdir, pictures):
    ref = run_scene(binary, "coupled", {"Mesh refinement/Initial global refinements":
                                        str(levels + 1)}, workdir, "reference")
    keys = ("melt area", "contact force interface 0-1")
    rows, curves = [], {"global": [], "adaptive": []}

    def deviation(r):
        return max(abs(r[k] - ref[k]) / abs(ref[k]) for k in keys)
    for level in range(levels + 1):
        g = run_scene(binary, "coupled", {"Mesh refinement/Initial global refinements":
                                          str(level)}, workdir, f"global-{level}")
        extra = {"Output/VTU interval": "1"} if pictures and level == levels else {}
        a = run_scene(binary, "coupled", {**adaptive_settings(level, interval=2, initial=1),
                                          **extra}, workdir, f"adaptive-{level}")
        for kind, r in (("global", g), ("adaptive", a)):
            curves[kind].append((dofs_of(r), r["wall time"], deviation(r)))
            rows.append([str(level), kind, f"{dofs_of(r):.0f}", f"{r['melt area']:.6e}",
                         f"{r['contact force interface 0-1']:.6e}", f"{deviation(r):.2e}",
                         f"{r['wall time']:.2f}"])
        if pictures and level == levels:
            draw_meshes(a["directory"], pictures)
    rows.append(["ref", f"global {levels + 1}", f"{ref['temperature dofs']:.0f}",
                 f"{ref['melt area']:.6e}", f"{ref['contact force interface 0-1']:.6e}", "0",
                 f"{ref['wall time']:.2f}"])
    return (["level", "mesh", "temperature DoFs (time-avg.)", "melt area", "contact force",
             "max rel. deviation", "wall [s]"], rows, curves,
            "largest relative deviation from the reference (melt area, force)")


def draw_meshes(directory, path):
    sys.path.insert(0, os.path.join(ROOT, "doc"))
    import make_pictures as mp  # noqa: E402  (matplotlib, meshio)
    records = mp.read_pvd(os.path.join(directory, "solution.pvd"))
    frames = [records[1], records[len(records) // 2], records[-1]]
    fig, axes = mp.plt.subplots(1, 3, figsize=(13, 4.4))
    for ax, (t, pvtu) in zip(axes, frames):
        points, quads, data = mp.read_pieces(directory, pvtu)
        tri = mp.triangulation(points, quads)
        c = ax.tripcolor(tri, data["temperature"], shading="gouraud", cmap="inferno")
        ax.tricontour(tri, data["liquid_fraction"], levels=[0.5], colors="cyan", linewidths=1)
        edges = points[quads][:, [0, 1, 2, 3, 0]]
        for cell in edges:
            ax.plot(cell[:, 0], cell[:, 1], color="white", linewidth=0.15)
        ax.set_title(f"t = {t / 86400:.2f} d, {len(quads)} cells")
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
    fig.colorbar(c, ax=axes, shrink=0.8, label="temperature")
    os.makedirs(path, exist_ok=True)
    out = os.path.join(path, "coupled_meshes.png")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    print(f"wrote {out}")


def plot(name, curves, ylabel, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for kind, marker in (("global", "o-"), ("adaptive", "s-")):
        pts = curves[kind]
        axes[0].loglog([p[0] for p in pts], [p[2] for p in pts], marker, label=kind)
        axes[1].loglog([p[1] for p in pts], [p[2] for p in pts], marker, label=kind)
    axes[0].set_xlabel("DoFs (time-averaged where the mesh changes)")
    axes[1].set_xlabel("wall time [s]")
    for ax in axes:
        ax.set_ylabel(ylabel)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle(name)
    fig.tight_layout()
    os.makedirs(path, exist_ok=True)
    out = os.path.join(path, f"{name}.png")
    fig.savefig(out, dpi=110, bbox_inches="tight")
    print(f"wrote {out}")


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--problem", choices=["stefan", "hertz", "coupled", "all"], default="all")
    p.add_argument("--levels", type=int, default=3)
    p.add_argument("--binary", default=DEFAULT_BINARY)
    p.add_argument("--markdown", action="store_true")
    p.add_argument("--plot", metavar="DIR")
    p.add_argument("--pictures", metavar="DIR")
    args = p.parse_args()
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"adaptivity.py: no executable '{args.binary}' (build first)")
    problems = ["stefan", "hertz", "coupled"] if args.problem == "all" else [args.problem]
    with tempfile.TemporaryDirectory() as workdir:
        for problem in problems:
            if problem == "stefan":
                headers, rows, curves, label = stefan(args.binary, args.levels, workdir)
            elif problem == "hertz":
                headers, rows, curves, label = hertz(args.binary, args.levels + 2, workdir)
            else:
                headers, rows, curves, label = coupled(args.binary, args.levels - 1, workdir,
                                                       args.pictures)
            print(f"## {problem}\n")
            table(headers, rows, args.markdown)
            if args.plot:
                plot(f"adaptivity-{problem}", curves, label, args.plot)


if __name__ == "__main__":
    main()
