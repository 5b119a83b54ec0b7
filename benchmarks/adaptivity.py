#!/usr/bin/python3
"""Adaptive against global refinement: error against DoFs and against wall time.

Three experiments (doc/adaptivity.md), each printed as a table:

  stefan    Neumann case A (S1, prm/benchmarks/neumann_A.prm). Global level L:
            the 64 x 4 mesh refined L times, tau = h = 1/(16 2^L). Adaptive level
            L: the 64 x 4 mesh adapted every --interval steps (and L times to the
            initial data) up to level L with --front-buffer, the same tau,
            coarsen fraction 0.02 (the default 0.05 ends above the global
            error). Compared: the space-time L2 error of the temperature against
            the (time-averaged) DoFs and the wall time, the front error in local
            mesh widths, and the cost of an adapted step against a global step
            of the same DoFs and tau (the global levels L-2, L-1, L at the tau
            of level L, interpolated). Each
            configuration runs --repeat times; the smallest wall time counts.
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

    /usr/bin/python3 benchmarks/adaptivity.py [--problem all] [--levels L]
        [--interval 3] [--front-buffer 4] [--repeat 3] [--markdown] [--plot doc/figures/adaptivity] [--pictures doc/figures/adaptivity]

Time runs when nothing else runs on the machine.
"""
import argparse
import math
import os
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from ladder import set_entry, set_path  # noqa: E402
from performance import run, table  # noqa: E402
from provenance import provenance_line  # noqa: E402

ROOT = os.path.dirname(HERE)
DEFAULT_BINARY = os.path.join(ROOT, "build", "contact-stefan")
# Neumann A adaptive: adapt every INTERVAL steps, front buffer FRONT_BUFFER cells
# (doc/adaptivity.md, section 5: the buffer covers the front's motion over an
# interval, up to 1.2 cells per step at tau = h).
INTERVAL = 3
FRONT_BUFFER = 4
SCENES = {"stefan": os.path.join(ROOT, "prm", "benchmarks", "neumann_A.prm"),
          "hertz": os.path.join(ROOT, "prm", "benchmarks", "hertz_C1.prm"),
          "coupled": os.path.join(ROOT, "prm", "coupled_melting_contact.prm")}


def with_settings(text, settings):
    """Set 'Subsection/Entry' paths to values (replaced where the scene sets
    them, appended otherwise: contact-stefan refuses an entry set twice)."""
    for path, value in settings.items():
        text = set_path(text, path, value)
    return text


def run_scene(binary, problem, settings, workdir, name, np_=1, repeat=1):
    """Run the scene `repeat` times; the results of the first run, the
    smallest wall time of all (the machine's noise only ever adds time)."""
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
    best = None
    for _ in range(repeat):
        result = run(cmd, f"{problem} {name}")
        if result is None:
            sys.exit(1)
        results, _ = result
        loop = time_loop_seconds(os.path.join(directory, "statistics.txt"))
        if best is None:
            best = results
            best["loop times"] = []
        best["wall time"] = min(best["wall time"], results["wall time"])
        if loop is not None:
            best["loop times"].append(loop)
    best["directory"] = directory
    return best


def time_loop_seconds(path):
    """The time loop's wall time: the last row's wall_time minus step 0's (set-up,
    initial state and the final output are outside it). None without the file."""
    try:
        with open(path) as f:
            lines = [line.split() for line in f if line.strip() and not line.startswith("#")]
    except OSError:
        return None
    column = lines[0].index("wall_time")
    return float(lines[-1][column]) - float(lines[1][column])


def per_step(r):
    """Seconds per step of the time loop, the smallest of the repeats."""
    return min(r["loop times"]) / r["time steps"]


def spread(r):
    times = r["loop times"]
    return max(times) / min(times) - 1 if len(times) > 1 else 0.


def adaptive_settings(level, interval=1, initial=None):
    return {"Mesh refinement/Adaptive refinement interval": str(interval),
            "Mesh refinement/Initial adaptive refinements": str(level if initial is None
                                                               else initial),
            "Mesh refinement/Maximum level": str(level)}


def dofs_of(r, field="temperature dofs"):
    return r.get("time-averaged dofs", r.get(field))


def per_step_at(curve, dofs):
    """The wall time per step of the global runs (DoFs, seconds per step),
    interpolated log-log to `dofs` (extrapolated from the nearest two)."""
    curve = sorted(curve)
    i = 1
    while i < len(curve) - 1 and curve[i][0] < dofs:
        i += 1
    (n0, t0), (n1, t1) = curve[i - 1], curve[i]
    return math.exp(math.log(t0) + (math.log(dofs) - math.log(n0)) *
                    (math.log(t1) - math.log(t0)) / (math.log(n1) - math.log(n0)))


def stefan(binary, levels, workdir, interval, buffer, repeat, margin=0):
    """Neumann case A. The adaptive run at level L against the global run at
    level L (the error to reach) and the global runs at levels 0 ... L (the
    cost of a step at a given number of DoFs)."""
    rows, curves = [], {"global": [], "adaptive": []}
    summary, margin_summary = [], []
    for level in range(1, levels + 1):
        tau = repr(0.0625 / 2**level)
        g = run_scene(binary, "stefan", {"Mesh refinement/Initial global refinements": str(level),
                                         "Time stepping/Time step": tau}, workdir,
                      f"global-{level}", repeat=repeat)
        # The cost of a global step at this tau on the coarser levels, whose
        # DoFs bracket the adaptive run's.
        step_cost = [(dofs_of(g), per_step(g))]
        for coarser in range(max(0, level - 2), level):
            c = run_scene(binary, "stefan",
                          {"Mesh refinement/Initial global refinements": str(coarser),
                           "Time stepping/Time step": tau}, workdir,
                          f"global-{coarser}-tau-{level}", repeat=repeat)
            step_cost.append((dofs_of(c), per_step(c)))
        a = run_scene(binary, "stefan", {"Time stepping/Time step": tau,
                                         "Mesh refinement/Coarsen fraction": "0.02",
                                         "Mesh refinement/Front buffer": str(buffer),
                                         **adaptive_settings(level, interval)}, workdir,
                      f"adaptive-{level}", repeat=repeat)
        runs = [("global", g), ("adaptive", a)]
        if margin > 0:
            # The same, checked after every step but adapted only when a front
            # comes within `margin` cells of the edge of its refined zone.
            m = run_scene(binary, "stefan", {"Time stepping/Time step": tau,
                                             "Mesh refinement/Coarsen fraction": "0.02",
                                             "Mesh refinement/Front buffer": str(buffer),
                                             "Mesh refinement/Front margin": str(margin),
                                             **adaptive_settings(level, 1)}, workdir,
                          f"adaptive-margin-{level}", repeat=repeat)
            runs.append((f"adaptive, margin {margin}", m))
            curves.setdefault(f"adaptive, margin {margin}", [])
        for kind, r in runs:
            e = r["relative space-time L2 error temperature"]
            curves[kind].append((dofs_of(r), r["wall time"], e))
            rows.append([str(level), kind, f"{dofs_of(r):.0f}", f"{e:.4e}",
                         f"{r.get('front position error in local mesh widths', r['front position error in mesh widths']):.3f}",
                         f"{1e3 * per_step(r):.2f}", f"{100 * spread(r):.0f} %",
                         f"{r['wall time']:.2f}"])
        error_ratio = (a["relative space-time L2 error temperature"] /
                       g["relative space-time L2 error temperature"])
        rows.append(["", "ratio", f"{dofs_of(g) / dofs_of(a):.2f}", f"{error_ratio:.4f}", "", "",
                     "", f"{g['wall time'] / a['wall time']:.2f}"])
        summary.append((level, error_ratio, a["wall time"] / g["wall time"],
                        per_step(a), dofs_of(a),
                        per_step_at(step_cost, dofs_of(a))))
        if margin > 0:
            rows.append(["", f"ratio, margin {margin}", f"{dofs_of(g) / dofs_of(m):.2f}",
                         f"{m['relative space-time L2 error temperature'] / g['relative space-time L2 error temperature']:.4f}",
                         "", "", "", f"{g['wall time'] / m['wall time']:.2f}"])
            margin_summary.append((level, m["relative space-time L2 error temperature"] /
                                   g["relative space-time L2 error temperature"],
                                   m["wall time"] / g["wall time"], per_step(m), dofs_of(m),
                                   per_step_at(step_cost, dofs_of(m)), m["mesh adaptations"],
                                   a["mesh adaptations"]))
    notes = []
    for level, error_ratio, time_ratio, adapted_step, dofs, same_dofs in summary:
        notes.append(f"level {level}: adaptive error {100 * (error_ratio - 1):+.2f} % against "
                     f"global, wall time {time_ratio:.3f} of global; an adapted step costs "
                     f"{adapted_step / same_dofs:.2f}x a global step of the same DoFs "
                     f"({1e3 * same_dofs:.2f} ms at {dofs:.0f} DoFs and the same tau, interpolated)")
    for level, error_ratio, time_ratio, adapted_step, dofs, same_dofs, n, n_interval in margin_summary:
        notes.append(f"level {level}, front margin {margin}: adaptive error "
                     f"{100 * (error_ratio - 1):+.2f} % against global, wall time "
                     f"{time_ratio:.3f} of global, {n:.0f} adaptations (every {interval} steps: "
                     f"{n_interval:.0f}); an adapted step costs {adapted_step / same_dofs:.2f}x a "
                     f"global step of the same DoFs")
    global ERROR_RATIOS
    ERROR_RATIOS = [(level, ratio) for level, ratio, *_ in summary]
    return (["level", "mesh", "DoFs (time-avg.)", "space-time L2 error", "front error / local h",
             "ms per step (loop)", "spread", "wall [s]"], rows, curves,
            "relative space-time L2 error (temperature)", notes)


ERROR_RATIOS = []


def hertz(binary, levels, workdir, repeat=1):
    rows, curves = [], {"global": [], "adaptive": []}
    base = {"Mesh refinement/Pre-refinement radius": "0"}
    for level in range(levels + 1):
        g = run_scene(binary, "hertz", {**base, "Mesh refinement/Initial global refinements":
                                        str(level)}, workdir, f"global-{level}", repeat=repeat)
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
                      workdir, f"adaptive-{level}", repeat=repeat)
        curves["adaptive"].append((a["displacement dofs"], a["wall time"],
                                   a["Hertz half-width relative error"]))
        rows.append([str(level), "adaptive", f"{a['displacement dofs']:.0f}",
                     f"{a['Hertz half-width relative error']:.3e}",
                     f"{a['Hertz peak pressure relative error']:.3e}", f"{a['wall time']:.2f}"])
    return (["level", "mesh", "DoFs (final)", "a rel. error", "p0 rel. error", "wall [s]"], rows,
            curves, "relative error of the contact half-width a", [])


def coupled(binary, levels, workdir, pictures, repeat=1):
    ref = run_scene(binary, "coupled", {"Mesh refinement/Initial global refinements":
                                        str(levels + 1)}, workdir, "reference", repeat=repeat)
    keys = ("melt area", "contact force interface 0-1")
    rows, curves = [], {"global": [], "adaptive": []}

    def deviation(r):
        return max(abs(r[k] - ref[k]) / abs(ref[k]) for k in keys)
    for level in range(levels + 1):
        g = run_scene(binary, "coupled", {"Mesh refinement/Initial global refinements":
                                          str(level)}, workdir, f"global-{level}", repeat=repeat)
        a = run_scene(binary, "coupled", adaptive_settings(level, interval=2, initial=1),
                      workdir, f"adaptive-{level}", repeat=repeat)
        for kind, r in (("global", g), ("adaptive", a)):
            curves[kind].append((dofs_of(r), r["wall time"], deviation(r)))
            rows.append([str(level), kind, f"{dofs_of(r):.0f}", f"{r['melt area']:.6e}",
                         f"{r['contact force interface 0-1']:.6e}", f"{deviation(r):.2e}",
                         f"{r['wall time']:.2f}"])
        if pictures and level == levels:
            # A run of its own for the pictures: writing VTU files is not timed.
            shown = run_scene(binary, "coupled", {**adaptive_settings(level, interval=2, initial=1),
                                                  "Output/VTU interval": "1"},
                              workdir, f"pictures-{level}")
            draw_meshes(shown["directory"], pictures)
    rows.append(["ref", f"global {levels + 1}", f"{ref['temperature dofs']:.0f}",
                 f"{ref['melt area']:.6e}", f"{ref['contact force interface 0-1']:.6e}", "0",
                 f"{ref['wall time']:.2f}"])
    return (["level", "mesh", "temperature DoFs (time-avg.)", "melt area", "contact force",
             "max rel. deviation", "wall [s]"], rows, curves,
            "largest relative deviation from the reference (melt area, force)", [])


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
    markers = ["o-", "s-", "^-", "v-"]
    for (kind, pts), marker in zip(curves.items(), markers):
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
    p.add_argument("--levels", type=int,
                   help="finest level (default: stefan 4, hertz 3 (+2), coupled 3 (-1))")
    p.add_argument("--interval", type=int, default=INTERVAL,
                   help="stefan: adapt every this many steps (default %(default)s)")
    p.add_argument("--front-buffer", type=int, default=FRONT_BUFFER,
                   help="stefan: 'Mesh refinement/Front buffer' (default %(default)s)")
    p.add_argument("--front-margin", type=int, default=0,
                   help="stefan: also run each adaptive level checked after every step but "
                        "adapted only when a front nears the edge of its refined zone "
                        "('Mesh refinement/Front margin'; default 0: not run)")
    p.add_argument("--repeat", type=int, default=3,
                   help="runs of each configuration; the smallest wall time counts")
    p.add_argument("--binary", default=DEFAULT_BINARY)
    p.add_argument("--require-error-ratio", type=float, metavar="R",
                   help="stefan: exit 1 unless the adaptive error is at most R times the "
                        "global error at every level (the ctest adaptive/neumann-A-vs-global)")
    p.add_argument("--markdown", action="store_true")
    p.add_argument("--plot", metavar="DIR")
    p.add_argument("--pictures", metavar="DIR")
    args = p.parse_args()
    print(provenance_line(args.binary), flush=True)
    if not os.access(args.binary, os.X_OK):
        sys.exit(f"adaptivity.py: no executable '{args.binary}' (build first)")
    problems = ["stefan", "hertz", "coupled"] if args.problem == "all" else [args.problem]
    with tempfile.TemporaryDirectory() as workdir:
        for problem in problems:
            if problem == "stefan":
                headers, rows, curves, label, notes = stefan(
                    args.binary, args.levels or 4, workdir, args.interval, args.front_buffer,
                    args.repeat, args.front_margin)
            elif problem == "hertz":
                headers, rows, curves, label, notes = hertz(args.binary, (args.levels or 3) + 2, workdir,
                                                            args.repeat)
            else:
                headers, rows, curves, label, notes = coupled(args.binary, (args.levels or 3) - 1,
                                                              workdir, args.pictures, args.repeat)
            print(f"## {problem}\n")
            table(headers, rows, args.markdown)
            for note in notes:
                print(f"- {note}")
            print()
            if args.plot:
                plot(f"adaptivity-{problem}", curves, label, args.plot)
    if args.require_error_ratio is not None:
        bad = [(level, r) for level, r in ERROR_RATIOS if not r <= args.require_error_ratio]
        for level, r in ERROR_RATIOS:
            print(f"level {level}: adaptive / global error = {r:.5f} "
                  f"({'ok' if r <= args.require_error_ratio else 'FAILED'}, "
                  f"bound {args.require_error_ratio})")
        if bad or not ERROR_RATIOS:
            sys.exit(1)


if __name__ == "__main__":
    main()
