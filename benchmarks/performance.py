#!/usr/bin/python3
"""Run time against error for contact-stefan and, where installed, FEniCSx.

The two problems of issue #10, on a refinement ladder, one run at a time:

  contact  the contact block (benchmarks/scenes/contact_block.prm), N x N cells,
           N = 32 * 2^L. Both codes solve the same nodal Signorini problem, so
           at equal N they give the same contact force (to ~10 digits): the
           table compares wall times at equal N, i.e. at equal error.
  stefan   the Stefan strip (benchmarks/scenes/stefan_strip.prm), nx = 100 * 2^L
           cells along the strip, ny = nx/10, tau = h/10; the error is the
           relative space-time L2 error against Neumann's solution. FEniCSx
           solves a smoothed enthalpy (mushy width 2h) with Newton; the ratio
           at equal error interpolates FEniCSx's time-error curve (log-log) at
           contact-stefan's errors.

For every contact-stefan run the script also prints the cost profile (the
TimerOutput sections), the average cost of a step against the cost of one
linear solve of the same operator (an average of the "factorise" section, which
holds full factorisations and AMG builds as well as the cheaper
refactorisations and recomputations after an active-set change, plus an
average solve; for the contact block the "step" is the whole run), and the
cost exponent (time per step against DoFs).

Runs whose elasticity system is solved by CG + AMG also get a table of CG
iterations per solve (largest and mean, with the growth per doubling of N) and
AMG set-ups, from the run's 'RESULT elasticity solver: ...' lines; --set
'Solver/Linear solver=cg-amg' forces that path at every N.

    benchmarks/performance.py --problem stefan --levels 4
    benchmarks/performance.py --problem contact --levels 4 --markdown --plot doc/figures/perf
    benchmarks/performance.py --problem contact --levels 6 --no-fenicsx \
        --set "Solver/Linear solver=cg-amg"
    benchmarks/performance.py --problem stefan --sizes 200,280,400 --markdown

--sizes runs the given sizes instead of the ladder, by both codes (issue 33 asks
the Stefan strip at nx = 280): the ratio at equal error then interpolates between
FEniCSx's runs at the neighbouring sizes.

FEniCSx runs when /usr/bin/python3 can import dolfinx (Debian:
python3-dolfinx-real); --no-fenicsx skips it. Time benchmarks on a quiet
machine: the ratios compare runs made one after the other in one session.
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from ladder import get_entry, least_squares_rate, set_entry, set_path  # noqa: E402
from provenance import provenance_line  # noqa: E402

DEFAULT_BINARY = os.path.join(HERE, "..", "build", "contact-stefan")
FENICSX_PYTHON = "/usr/bin/python3"
SCENES = {"contact": os.path.join(HERE, "scenes", "contact_block.prm"),
          "stefan": os.path.join(HERE, "scenes", "stefan_strip.prm")}
FENICSX_SCRIPTS = {"contact": os.path.join(HERE, "fenicsx", "contact_block.py"),
                   "stefan": os.path.join(HERE, "fenicsx", "stefan_strip.py")}


def parse(stdout):
    """RESULT lines and TimerOutput rows (section -> (calls, seconds))."""
    results, timers = {}, {}
    for line in stdout.splitlines():
        m = re.match(r"RESULT (.+?) = (\S+)", line)
        if m:
            results[m.group(1)] = float(m.group(2))
            continue
        # | section | calls | min time  rank | avg time | max time  rank |: the
        # largest time over the ranks (all equal in a serial run).
        m = re.match(r"\|\s*([^|]+?)\s*\|\s*(\d+)\s*\|[^|]*\|[^|]*\|\s*([0-9.e+-]+)s", line)
        if m:
            timers[m.group(1)] = (int(m.group(2)), float(m.group(3)))
    return results, timers


def run(cmd, what):
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        print(f"performance.py: {what} failed (exit {out.returncode}):\n"
              f"{out.stderr[-1500:]}{out.stdout[-1500:]}", file=sys.stderr)
        return None
    return parse(out.stdout)


def append_setting(text, setting):
    """Set 'Sub/section/Entry=value' in the scene text (replaced where the scene
    sets it, appended otherwise: contact-stefan refuses an entry set twice)."""
    path, sep, value = setting.partition("=")
    parts = [p.strip() for p in path.split("/")]
    if not sep or len(parts) < 2 or not all(parts):
        sys.exit(f"performance.py: --set '{setting}' is not 'Subsection/Entry=value'")
    return set_path(text, "/".join(parts), value.strip())


def size_of_level(problem, level):
    """N (contact) or nx (stefan) of a level of the ladder."""
    return (32 if problem == "contact" else 100) * 2**level


def run_ours(binary, problem, size, np_, workdir, settings=()):
    with open(SCENES[problem]) as f:
        text = f.read()
    for setting in settings:
        text = append_setting(text, setting)
    if problem == "contact":
        text = set_entry(text, "Subdivisions", f"{size}, {size}")
    else:
        # (nx a multiple of 10: ny = nx/10 keeps the cells square)
        text = set_entry(text, "Subdivisions", f"{size}, {size // 10}")
        text = set_entry(text, "Time step", repr(0.1 / size))
    text = set_entry(text, "Directory", os.path.join(workdir, f"{problem}-{size}"))
    prm = os.path.join(workdir, f"{problem}-{size}.prm")
    with open(prm, "w") as f:
        f.write(text)
    cmd = [binary, prm] if np_ == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe",
                                          "-np", str(np_), binary, prm]
    parsed = run(cmd, f"contact-stefan {problem} at size {size}")
    if parsed is None:
        return None
    results, timers = parsed
    results["size"] = size
    results["timers"] = timers
    return results


def run_fenicsx(problem, size, workdir):
    script = FENICSX_SCRIPTS[problem]
    flag = "--n" if problem == "contact" else "--nx"
    parsed = run([FENICSX_PYTHON, script, flag, str(size)], f"FEniCSx {problem} at size {size}")
    if parsed is None:
        return {"size": size, "failed": True}
    results, _ = parsed
    results["size"] = size
    return results


def fenicsx_available():
    if not os.path.exists(FENICSX_PYTHON):
        return False
    probe = subprocess.run([FENICSX_PYTHON, "-c", "import dolfinx"], capture_output=True)
    return probe.returncode == 0


def dofs(r):
    for key in ("temperature dofs", "displacement dofs", "dofs"):
        if key in r:
            return r[key]
    return float("nan")


def error_of(problem, r):
    if problem == "stefan":
        return r.get("relative space-time L2 error temperature", float("nan"))
    return r.get("contact force boundary 2", r.get("contact force", float("nan")))


def time_at_error(curve, error):
    """Wall time of a (error, time) curve at the given error: log-log
    interpolation between the two bracketing runs; None outside the curve."""
    pts = sorted((e, t) for e, t in curve if e > 0 and t > 0)
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e0 <= error <= e1:
            w = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + w * (math.log(t1) - math.log(t0)))
    return None


def table(headers, rows, markdown):
    if markdown:
        print("| " + " | ".join(headers) + " |")
        print("|" + "---|" * len(headers))
        for row in rows:
            print("| " + " | ".join(row) + " |")
    else:
        widths = [max(len(h), *(len(r[i]) for r in rows)) for i, h in enumerate(headers)]
        print("  ".join(h.rjust(w) for h, w in zip(headers, widths)))
        for row in rows:
            print("  ".join(c.rjust(w) for c, w in zip(row, widths)))
    print()


def solve_section(problem):
    return "contact step: linear solve" if problem == "contact" else "enthalpy step: linear solve"


def report(problem, ours, theirs, markdown):
    print(f"## {problem}: contact-stefan" + (" against FEniCSx" if theirs else ""))
    print()
    size_name = "N" if problem == "contact" else "nx"
    headers = [size_name, "DoFs", "steps", "wall [s]", "solves", "factorisations / AMG setups",
               "error" if problem == "stefan" else "contact force"]
    if theirs:
        headers += ["FEniCSx wall [s]", "FEniCSx " + ("error" if problem == "stefan" else "force")]
        headers += ["ratio at equal " + ("N" if problem == "contact" else "error")]
    curve = [(error_of(problem, t), t["wall time"]) for t in theirs if not t.get("failed")]
    rows = []
    for i, r in enumerate(ours):
        timers = r["timers"]
        solves = timers.get(solve_section(problem), (0, 0))[0]
        setups = timers.get(solve_section(problem).replace("linear solve", "factorise"), (0, 0))[0]
        # Of them, the CHOLMOD factors modified row by row (Solver/Row update limit).
        system = "enthalpy" if problem == "stefan" else "elasticity"
        modified = r.get(f"{system} solver: factors modified row by row", 0)
        setups = f"{setups} ({modified:.0f} modified)" if modified else f"{setups}"
        row = [f"{r['size']}", f"{dofs(r):.0f}", f"{r.get('time steps', 1):.0f}",
               f"{r['wall time']:.2f}", f"{solves}", setups,
               f"{error_of(problem, r):.6e}" if problem == "stefan" else f"{error_of(problem, r):.10e}"]
        if theirs:
            t = theirs[i] if i < len(theirs) else None
            if t is None:
                row += ["not run", "-", "-"]
            elif t.get("failed"):
                row += ["failed", "-", "-"]
            else:
                row += [f"{t['wall time']:.2f}",
                        f"{error_of(problem, t):.6e}" if problem == "stefan"
                        else f"{error_of(problem, t):.10e}"]
                if problem == "contact":
                    row.append(f"{t['wall time'] / r['wall time']:.1f}")
                else:
                    at = time_at_error(curve, error_of(problem, r))
                    row.append(f"{at / r['wall time']:.1f}" if at else "outside")
        rows.append(row)
    table(headers, rows, markdown)

    # Cost profile and cost of a step against one linear solve.
    print(f"### {problem}: where the time goes (contact-stefan, share of the wall time)")
    print()
    sections = []
    for r in ours:
        for name, (_, seconds) in r["timers"].items():
            if seconds > 0.02 * r["wall time"] and name not in sections:
                sections.append(name)
    headers = [size_name] + sections + ["step / one solve"]
    rows = []
    for r in ours:
        timers = r["timers"]
        row = [f"{r['size']}"]
        row += [f"{100 * timers.get(s, (0, 0))[1] / r['wall time']:.0f} %" for s in sections]
        # One linear solve of the operator: an average of the "factorise"
        # section (full factorisations and AMG builds, and the cheaper
        # refactorisations and AMG recomputations of a changed active set)
        # plus an average solve.
        calls, seconds = timers.get(solve_section(problem), (0, 0))
        f_calls, f_seconds = timers.get(solve_section(problem).replace("linear solve", "factorise"),
                                        (0, 0))
        one_solve = (seconds / calls if calls else 0) + (f_seconds / f_calls if f_calls else 0)
        steps = max(r.get("time steps", 1), 1)
        row.append(f"{(r['wall time'] / steps) / one_solve:.2f}" if one_solve > 0 else "-")
        rows.append(row)
    table(headers, rows, markdown)
    cg_table(problem, ours, markdown)
    if len(ours) > 2:
        per_step = [r["wall time"] / max(r.get("time steps", 1), 1) for r in ours]
        exponent = least_squares_rate([dofs(r) for r in ours], per_step)
        print(f"cost exponent (time per step ~ DoFs^p, least squares over the ladder): "
              f"p = {exponent:.2f}")
        print()


def cg_runs(ours):
    return [r for r in ours if r.get("elasticity solver: CG solves", 0) > 0]


def cg_table(problem, ours, markdown, label=""):
    """CG iterations per elasticity solve, where CG + AMG solved it."""
    cg = cg_runs(ours)
    if not cg:
        return
    size_name = "N" if problem == "contact" else "nx"
    print(f"### {problem}: CG iterations per elasticity solve (contact-stefan{label})")
    print()
    headers = [size_name, "CG solves", "largest", "growth of the largest", "mean",
               "growth of the mean", "AMG builds", "AMG recomputations"]
    key = "elasticity solver: "
    rows = []
    for i, r in enumerate(cg):
        largest = r[key + "max CG iterations per solve"]
        mean = r[key + "mean CG iterations per solve"]
        growth = ["-", "-"]
        if i > 0 and cg[i - 1]["size"] * 2 == r["size"]:
            before = cg[i - 1]
            growth = [f"{100 * (largest / before[key + 'max CG iterations per solve'] - 1):+.0f} %",
                      f"{100 * (mean / before[key + 'mean CG iterations per solve'] - 1):+.0f} %"]
        rows.append([f"{r['size']}", f"{r[key + 'CG solves']:.0f}", f"{largest:.0f}", growth[0],
                     f"{mean:.1f}", growth[1], f"{r[key + 'AMG builds']:.0f}",
                     f"{r[key + 'AMG recomputations']:.0f}"])
    table(headers, rows, markdown)


def plot_cg(series, path):
    """Largest and mean CG iterations per elasticity solve against N, one
    pair of curves per (label, runs) in series."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    key = "elasticity solver: "
    for i, (label, runs) in enumerate(series):
        cg = cg_runs(runs)
        if not cg:
            continue
        n = [r["size"] for r in cg]
        line, = ax.semilogx(n, [r[key + "max CG iterations per solve"] for r in cg], "o-",
                            base=2, label=f"largest, {label}")
        ax.semilogx(n, [r[key + "mean CG iterations per solve"] for r in cg], "s--", base=2,
                    color=line.get_color(), label=f"mean, {label}")
    ax.set_xlabel("N (N x N cells)")
    ax.set_ylabel("CG iterations per solve")
    # Room above the curves for the legend.
    top = max((r[key + "max CG iterations per solve"] for _, runs in series
               for r in cg_runs(runs)), default=1)
    ax.set_ylim(0, 1.6 * top)
    ax.set_title("contact block: CG + AMG iterations per elasticity solve")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot(problem, ours, theirs, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    if problem == "stefan":
        ax.loglog([r["wall time"] for r in ours], [error_of(problem, r) for r in ours], "o-",
                  label="contact-stefan (sharp, active set)")
        good = [t for t in theirs if not t.get("failed")]
        if good:
            ax.loglog([t["wall time"] for t in good], [error_of(problem, t) for t in good], "s--",
                      label="FEniCSx (smoothed, eps = 2h, Newton)")
        ax.set_ylabel("relative space-time L2 error")
    else:
        ax.loglog([dofs(r) for r in ours], [r["wall time"] for r in ours], "o-",
                  label="contact-stefan (active set, CG + AMG)")
        good = [t for t in theirs if not t.get("failed")]
        if good:
            ax.loglog([dofs(t) for t in good], [t["wall time"] for t in good], "s--",
                      label="FEniCSx (SNES-VI)")
        ax.set_ylabel("wall time [s]")
    ax.set_xlabel("wall time [s]" if problem == "stefan" else "DoFs")
    ax.set_title(f"{problem}: run time against " + ("error" if problem == "stefan" else "size"))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--problem", choices=["contact", "stefan", "all"], default="all")
    parser.add_argument("--levels", type=int, default=4)
    parser.add_argument("--np", type=int, default=1, help="MPI ranks of contact-stefan")
    parser.add_argument("--binary", default=DEFAULT_BINARY)
    parser.add_argument("--no-fenicsx", action="store_true")
    parser.add_argument("--fenicsx-levels", type=int, help="FEniCSx levels (default: --levels)")
    parser.add_argument("--sizes", help="comma-separated sizes (N of the contact block, nx of "
                                        "the Stefan strip, a multiple of 10) to run instead of "
                                        "the ladder's levels, by both codes; e.g. 200,280,400")
    parser.add_argument("--markdown", action="store_true")
    parser.add_argument("--plot", help="write PLOT-<problem>.png (and PLOT-<problem>-cg.png "
                                       "where CG solved the elasticity system)")
    parser.add_argument("--plot-cg", help="write only the CG-iterations plot, to this PNG")
    parser.add_argument("--set", action="append", default=[], metavar="SUB/ENTRY=VALUE",
                        help="set a parameter of contact-stefan's scenes (repeatable)")
    parser.add_argument("--compare-set", action="append", default=[], metavar="SUB/ENTRY=VALUE",
                        help="run contact-stefan's ladder again with these settings added "
                             "and compare its CG iterations per elasticity solve")
    args = parser.parse_args()
    print(provenance_line(args.binary), flush=True)
    if not os.path.exists(args.binary):
        sys.exit(f"performance.py: no binary at {args.binary}; build first (see README)")
    fenicsx = not args.no_fenicsx and fenicsx_available()
    if not args.no_fenicsx and not fenicsx:
        print("performance.py: FEniCSx not found for /usr/bin/python3 "
              "(apt-get install python3-dolfinx-real); contact-stefan only", file=sys.stderr)
    problems = ["contact", "stefan"] if args.problem == "all" else [args.problem]
    sizes = None
    if args.sizes:
        try:
            sizes = [int(x) for x in args.sizes.split(",")]
        except ValueError:
            sys.exit(f"performance.py: --sizes '{args.sizes}' is not a comma-separated list "
                     "of integers")
        if any(n < 10 for n in sizes) or ("stefan" in problems and any(n % 10 for n in sizes)):
            sys.exit(f"performance.py: --sizes '{args.sizes}': every size must be at least 10 "
                     "(and a multiple of 10 for the Stefan strip, whose ny = nx/10)")
        if len(set(sizes)) != len(sizes):
            sys.exit(f"performance.py: --sizes '{args.sizes}' names a size twice")
        if len(problems) > 1 or args.fenicsx_levels is not None:
            sys.exit("performance.py: --sizes needs one --problem (N and nx differ) and "
                     "replaces --levels and --fenicsx-levels")
    with tempfile.TemporaryDirectory() as workdir:
        for problem in problems:
            ours, theirs = [], []
            ladder = sizes or [size_of_level(problem, level) for level in range(args.levels)]
            for size in ladder:
                r = run_ours(args.binary, problem, size, args.np, workdir, args.set)
                if r is None:
                    sys.exit(1)
                ours.append(r)
                print(f"{problem} size {size}: contact-stefan {r['wall time']:.2f} s",
                      file=sys.stderr)
            if fenicsx:
                # Untimed warm-up: FEniCSx compiles its forms on first use.
                run_fenicsx(problem, size_of_level(problem, 0), workdir)
                theirs_ladder = sizes or [
                    size_of_level(problem, level)
                    for level in range(args.fenicsx_levels if args.fenicsx_levels is not None
                                       else args.levels)]
                for size in theirs_ladder:
                    t = run_fenicsx(problem, size, workdir)
                    theirs.append(t)
                    took = "failed" if t.get("failed") else f"{t['wall time']:.2f} s"
                    print(f"{problem} size {size}: FEniCSx {took}", file=sys.stderr)
            report(problem, ours, theirs, args.markdown)
            compared = []
            if args.compare_set:
                for size in ladder:
                    r = run_ours(args.binary, problem, size, args.np, workdir,
                                 args.set + args.compare_set)
                    if r is None:
                        sys.exit(1)
                    compared.append(r)
                    print(f"{problem} size {size}: contact-stefan with "
                          f"{', '.join(args.compare_set)} {r['wall time']:.2f} s", file=sys.stderr)
                label = ", ".join(args.compare_set)
                print(f"## {problem}: contact-stefan with {label}")
                print()
                size_name = "N" if problem == "contact" else "nx"
                table([size_name, "wall [s]", "the first run's wall [s]", "ratio"],
                      [[f"{r['size']}", f"{r['wall time']:.2f}", f"{o['wall time']:.2f}",
                        f"{r['wall time'] / o['wall time']:.2f}"]
                       for r, o in zip(compared, ours)], args.markdown)
                cg_table(problem, compared, args.markdown, f", with {label}")
            if args.plot:
                plot(problem, ours, theirs, f"{args.plot}-{problem}.png")
            if (args.plot or args.plot_cg) and (cg_runs(ours) or cg_runs(compared)):
                def short(settings):
                    # 'Solver/Linear solver=cg-amg' -> 'Linear solver=cg-amg'
                    return ", ".join(x.split("/")[-1] for x in settings) or "defaults"
                series = [(short(args.set), ours)]
                if compared:
                    series.append((short(args.set + args.compare_set), compared))
                plot_cg(series, args.plot_cg or f"{args.plot}-{problem}-cg.png")


if __name__ == "__main__":
    main()
