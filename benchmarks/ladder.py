#!/usr/bin/python3
"""Run a benchmark scene on a refinement ladder and print run time against error.

Level L refines the scene's mesh L more times and divides its time step by 2^L
(h and tau halved together). Each run's RESULT lines are collected; the table
gives DoFs, steps, wall time, the errors and observed rates between levels, and
a least-squares rate over the whole ladder.

    benchmarks/ladder.py prm/benchmarks/neumann_A.prm --levels 4
    benchmarks/ladder.py prm/benchmarks/neumann_A.prm --levels 5 --np 2 --markdown
    benchmarks/ladder.py tests/scenes/manufactured_stress.prm --levels 6 --no-refine-time \
        --require-rate "max relative stress L2 error (recovered)>=1.4"

--require-rate "NAME>=VALUE" (or <=) makes the exit code 1 unless the
least-squares rate of that RESULT over the ladder meets it (ctest uses it).

Only the standard library is needed; --plot FILE also draws error against wall
time with matplotlib (Debian: python3-matplotlib, run with /usr/bin/python3).
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile
import time
from provenance import provenance_line  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_BINARY = os.path.join(HERE, "..", "build", "contact-stefan")

# Columns: (RESULT name, header, format, fit a rate?)
COLUMNS = [
    ("temperature dofs", "DoFs", "{:>9.0f}", False),
    ("displacement dofs", "DoFs", "{:>9.0f}", False),
    ("time steps", "steps", "{:>6.0f}", False),
    ("wall time", "wall [s]", "{:>9.2f}", False),
    ("mean active-set iterations", "PDAS/step", "{:>9.2f}", False),
    ("relative L2 error temperature", "rel L2(T)", "{:>10.3e}", True),
    ("relative space-time L2 error temperature", "rel L2L2", "{:>10.3e}", True),
    ("max-norm error temperature", "max err", "{:>10.3e}", True),
    ("front position error in mesh widths", "front/h", "{:>8.3f}", False),
    ("front position error in mesh widths 0", "front0/h", "{:>8.3f}", False),
    ("front position error in mesh widths 1", "front1/h", "{:>8.3f}", False),
    ("max energy-balance residual", "energy res", "{:>10.1e}", False),
    ("contact iterations first step", "contact it", "{:>10.0f}", False),
    ("Hertz force P", "P", "{:>10.4e}", False),
    ("Hertz half-width relative error", "a rel err", "{:>10.3e}", True),
    ("Hertz peak pressure relative error", "p0 rel err", "{:>10.3e}", True),
    ("Hertz pressure profile relative L2 error", "p(x) L2", "{:>10.3e}", True),
    ("max relative stress L2 error", "sigma vert", "{:>10.3e}", True),
    ("max relative stress L2 error (cell centres)", "sigma cell", "{:>10.3e}", True),
    ("max relative stress L2 error (recovered)", "sigma rec", "{:>10.3e}", True),
    ("max relative heat flux L2 error (cell centres)", "q cell", "{:>10.3e}", True),
    ("max relative heat flux L2 error (recovered)", "q rec", "{:>10.3e}", True),
]


def set_entry(text, name, value):
    """Replace 'set name = ...' in a .prm text; the entry must be there."""
    pattern = re.compile(r"^(\s*set\s+" + re.escape(name) + r"\s*=).*$", re.M)
    if not pattern.search(text):
        sys.exit(f"ladder.py: the scene has no entry '{name}'")
    return pattern.sub(lambda m: m.group(1) + " " + value, text)


def _logical_lines(text):
    """(index, subsection path, 'set' name or None) per line, as deal.II reads
    them: a comment runs from '#' on, 'subsection'/'end' nest."""
    stack = []
    for k, raw in enumerate(text.splitlines()):
        line = raw.split("#", 1)[0].replace("\t", " ").strip()
        name = None
        if line.startswith(("subsection ", "SUBSECTION ")):
            stack.append(line[len("subsection "):].strip())
        elif line in ("end", "END") and stack:
            stack.pop()
        elif line.startswith(("set ", "SET ")) and "=" in line:
            name = line[4:].split("=", 1)[0].strip()
        yield k, list(stack), name, line


def set_path(text, path, value):
    """Set 'Sub/section/Entry' to value: replace the lines that set it in that
    subsection path, or append a subsection block if there are none
    (contact-stefan refuses an entry set twice)."""
    *sections, key = [p.strip() for p in path.split("/")]
    lines, found = text.splitlines(), False
    for k, stack, name, _ in _logical_lines(text):
        if name == key and stack == sections:
            raw = lines[k]
            lines[k] = f"{raw[: len(raw) - len(raw.lstrip())]}set {key} = {value}"
            found = True
    text = "\n".join(lines) + "\n"
    if not found:
        text += "".join(f"subsection {s}\n" for s in sections)
        text += f"  set {key} = {value}\n" + "end\n" * len(sections)
    return text


def run_text(binary, work, name, text):
    """Write the scene text to WORK/NAME.prm, run it there; (stdout, wall seconds)."""
    scene = os.path.join(work, name + ".prm")
    with open(scene, "w") as f:
        f.write(text)
    start = time.time()
    out = subprocess.run([binary, scene], cwd=work, check=True, capture_output=True,
                         text=True).stdout
    return out, time.time() - start


def get_path(text, path, default):
    """The value the scene gives 'Sub/section/Entry' (the last one), else default."""
    *sections, key = [p.strip() for p in path.split("/")]
    value = default
    for _, stack, name, line in _logical_lines(text):
        if name == key and stack == sections:
            value = line.split("=", 1)[1].strip()
    return value


def get_entry(text, name):
    m = re.search(r"^\s*set\s+" + re.escape(name) + r"\s*=\s*(.*?)\s*(#.*)?$", text, re.M)
    if not m:
        sys.exit(f"ladder.py: the scene has no entry '{name}'")
    return m.group(1)


def run_level(binary, scene_text, scene_dir, level, np_, workdir, refine_time, halve=()):
    # A scene that does not set an entry has its default (0 refinements, the
    # output written to 'output' every step).
    base = re.search(r"^\s*set\s+Initial global refinements\s*=\s*(\d+)", scene_text, re.M)
    refinements = (int(base.group(1)) if base else 0) + level
    tau = float(get_entry(scene_text, "Time step")) / (2**level if refine_time else 1)
    text = set_path(scene_text, "Mesh refinement/Initial global refinements", str(refinements))
    text = set_entry(text, "Time step", repr(tau))
    for path in halve:
        value = get_path(text, path, None)
        if value is None:
            sys.exit(f"ladder.py: --halve '{path}': the scene does not set it")
        text = set_path(text, path, repr(float(value) / 2**level))
    text = set_path(text, "Output/Directory", os.path.join(workdir, f"level-{level}"))
    text = set_path(text, "Output/VTU interval", "0")
    # Beside the scene, so that its relative includes and meshes resolve; named
    # by the process, so that two ladders over scenes of one folder (two ctest
    # jobs) do not write and delete each other's file.
    prm = os.path.join(scene_dir, f".ladder-{os.getpid()}-level-{level}.prm")
    with open(prm, "w") as f:
        f.write(text)
    try:
        cmd = ([binary, prm] if np_ == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe",
                                                "-np", str(np_), binary, prm])
        out = subprocess.run(cmd, capture_output=True, text=True)
    finally:
        os.remove(prm)
    if out.returncode != 0:
        sys.exit(f"ladder.py: level {level} failed:\n{out.stderr}{out.stdout[-2000:]}")
    results = {}
    for line in out.stdout.splitlines():
        m = re.match(r"RESULT (.+?) = (\S+)", line)
        if m:
            results[m.group(1)] = float(m.group(2))
    results["tau"] = tau
    return results


def width(r):
    """The mesh width of a run: of the whole mesh, or at the contact zone."""
    return r.get("mesh width", r.get("contact mesh width", float("nan")))


def least_squares_rate(h, e):
    """The slope of log e against log h; NaN where an error is not positive (no
    rate: a requirement on it fails)."""
    if not all(v > 0 for v in e):
        return float("nan")
    x = [math.log(v) for v in h]
    y = [math.log(v) for v in e]
    n = len(x)
    mx, my = sum(x) / n, sum(y) / n
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("scene")
    parser.add_argument("--levels", type=int, default=4)
    parser.add_argument("--np", type=int, default=1, help="MPI ranks per run")
    parser.add_argument("--binary", default=DEFAULT_BINARY)
    parser.add_argument("--no-refine-time", action="store_true",
                        help="keep the time step (quasi-static scenes: refine h only)")
    parser.add_argument("--set", action="append", default=[], metavar="PATH=VALUE",
                        help="set 'Subsection/Entry' to VALUE on every level (e.g. "
                             "'Time stepping/Time step function=if(t < 0.5, tau, 2 * tau)')")
    parser.add_argument("--halve", action="append", default=[], metavar="PATH",
                        help="divide 'Subsection/Entry' by 2^level too (set it with --set), "
                             "e.g. 'Time stepping/Target temperature change' for adaptive steps")
    parser.add_argument("--require-last", action="append", default=[], metavar="NAME<VALUE",
                        help="exit code 1 unless RESULT NAME of the finest level is below "
                             "(<) or above (>) VALUE")
    parser.add_argument("--result", action="append", default=[], metavar="NAME",
                        help="also a column of the RESULT line NAME (e.g. 'melt area')")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--plot", help="write error against wall time to this PNG")
    parser.add_argument("--require-rate", action="append", default=[],
                        help="'RESULT name>=rate' or '<=': exit 1 unless the least-squares "
                             "rate over the ladder meets it")
    args = parser.parse_args()
    print(provenance_line(args.binary), flush=True)
    if not os.path.exists(args.binary):
        sys.exit(f"ladder.py: no binary at {args.binary}; build first (see README)")

    with open(args.scene) as f:
        scene_text = f.read()
    for setting in args.set:
        path, _, value = setting.partition("=")
        if not value:
            sys.exit(f"ladder.py: --set '{setting}' is not PATH=VALUE")
        scene_text = set_path(scene_text, path.strip(), value.strip())
    rows = []
    with tempfile.TemporaryDirectory() as workdir:
        for level in range(args.levels):
            rows.append(run_level(args.binary, scene_text, os.path.dirname(os.path.abspath(args.scene)),
                                  level, args.np, workdir, not args.no_refine_time,
                                  args.halve))
            print(f"level {level} done in {rows[-1]['wall time']:.2f} s", file=sys.stderr)

    have = []
    extra = [(name, name, "{:>10.4g}", False) for name in args.result]
    for name in args.result:
        if name not in rows[0]:
            sys.exit(f"ladder.py: the runs print no 'RESULT {name} = ...' line")
    for c in COLUMNS + extra:  # the first DoF column present only
        if c[0] in rows[0] and not (c[1] == "DoFs" and any(h[1] == "DoFs" for h in have)):
            have.append(c)
    headers = ["level", "h", "tau"] + [c[1] for c in have]
    rate_cols = [c for c in have if c[3]]
    if args.markdown:
        print("| " + " | ".join(headers + [f"rate {c[1]}" for c in rate_cols]) + " |")
        print("|" + "---|" * (len(headers) + len(rate_cols)))
    else:
        print("  ".join(f"{h:>9}" for h in headers + [f"rate {c[1]}"[:9] for c in rate_cols]))
    for i, r in enumerate(rows):
        cells = [f"{i:>9d}", f"{width(r):>9.3e}", f"{r['tau']:>9.3e}"]
        cells += [c[2].format(r[c[0]]) for c in have]
        for c in rate_cols:
            if i == 0 or not (rows[i-1][c[0]] > 0 and r[c[0]] > 0):
                # (a zero error, as a stress exact at the cell centres, has no rate)
                cells.append(f"{'-':>9}")
            else:
                cells.append(f"{math.log(rows[i-1][c[0]] / r[c[0]]) / math.log(2):>9.2f}")
        print(("| " + " | ".join(x.strip() for x in cells) + " |") if args.markdown else "  ".join(cells))
    failed = []
    if len(rows) > 1:
        # Without a reported mesh width the ladder halves h per level.
        h = [width(r) if not math.isnan(width(r)) else 2.0**-i for i, r in enumerate(rows)]
        print()
        for c in rate_cols:
            print(f"least-squares rate of {c[0]}: {least_squares_rate(h, [r[c[0]] for r in rows]):.3f}")
        for requirement in args.require_rate:
            m = re.match(r"(.+?)\s*(>=|<=)\s*(\S+)$", requirement)
            if not m or m.group(1) not in rows[0]:
                sys.exit(f"ladder.py: cannot read the requirement '{requirement}'")
            rate = least_squares_rate(h, [r[m.group(1)] for r in rows])
            ok = rate >= float(m.group(3)) if m.group(2) == ">=" else rate <= float(m.group(3))
            print(f"requirement {'met' if ok else 'FAILED'}: rate of {m.group(1)} = {rate:.3f} "
                  f"{m.group(2)} {m.group(3)}")
            if not ok:
                failed.append(requirement)
        for requirement in args.require_last:
            m = re.match(r"(.+?)\s*(<|>)\s*(\S+)$", requirement)
            if not m or m.group(1) not in rows[-1]:
                sys.exit(f"ladder.py: cannot read the requirement '{requirement}'")
            value = rows[-1][m.group(1)]
            ok = value < float(m.group(3)) if m.group(2) == "<" else value > float(m.group(3))
            print(f"requirement {'met' if ok else 'FAILED'}: {m.group(1)} = {value:g} on the "
                  f"finest level, {m.group(2)} {m.group(3)}")
            if not ok:
                failed.append(requirement)
        if "mean active-set iterations" in rows[0]:
            print(f"mean active-set iterations over the ladder: "
                  f"{sum(r['mean active-set iterations'] for r in rows) / len(rows):.2f}")
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6, 4))
        for c in rate_cols:
            ax.loglog([r["wall time"] for r in rows], [r[c[0]] for r in rows], "o-", label=c[1])
        ax.set_xlabel("wall time [s]")
        ax.set_ylabel("error")
        ax.set_title(os.path.basename(args.scene))
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.plot, dpi=120)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
