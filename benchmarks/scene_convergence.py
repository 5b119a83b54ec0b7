#!/usr/bin/python3
"""A scene's reported quantities under mesh refinement (issue 33's convergence
study of the application scenes, doc/scenes.md section 4).

Level L refines the scene's mesh L more times at the same time step: by
L more 'Mesh refinement/Initial global refinements' than the scene's (default), or, with
--subdivisions, by 'Geometry/Subdivisions' times 2^L (the casting's study of
2026-11-27 was made so, when its disk in ring refused global refinement). VTU
output is switched off. The table gives each quantity per level and its change
from the level before; the last column says whether the last change is below
--target (5 % by default).

    benchmarks/scene_convergence.py prm/subduction.prm --levels 0,1,2,3
        --set "Mesh refinement/Adaptive refinement interval=0"
        --set "Mesh refinement/Initial adaptive refinements=0"
    benchmarks/scene_convergence.py prm/subduction.prm --levels 0
        --set "Mesh refinement/Maximum level=4"
        --set "Mesh refinement/Initial adaptive refinements=4"
    benchmarks/scene_convergence.py benchmarks/scenes/subduction_bent_slab.prm --levels 0,1,2,3 --markdown
    benchmarks/scene_convergence.py prm/casting.prm --levels 0,1,2 --subdivisions
        --set "Mesh refinement/Adaptive refinement interval=0"
        --set "Mesh refinement/Initial adaptive refinements=0"

(each command on one line). The default scene and the casting adapt their meshes
to level 3 themselves: the first and the last command refine their coarse meshes
globally with the adaptation switched off, the second adapts the default scene
one level deeper than the scene (doc/scenes.md section 4).

Wall times are those of single runs: indicative only (time benchmarks on a
quiet machine).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from ladder import get_path, set_path  # noqa: E402
from provenance import provenance_line  # noqa: E402

DEFAULT_BINARY = os.path.join(HERE, "..", "build", "contact-stefan")

# (RESULT name or derived key, row label)
QUANTITIES = [
    ("temperature dofs", "temperature DoFs"),
    ("displacement dofs", "displacement DoFs"),
    ("melt area", "melt area (m²)"),
    ("contact force", "contact force (N/m)"),
    ("contact length", "length in contact at the end (m)"),
    ("max contact length", "largest length in contact over the run (m)"),
    ("max contact pressure", "max contact pressure (Pa)"),
    ("max von Mises stress (cell centres)", "max von Mises, cell centres (Pa)"),
    ("elastic energy", "elastic energy (J/m)"),
    ("total thermoelastic heat", "total thermoelastic heat (J/m)"),
    ("total contact work", "total contact work (J/m)"),
    ("active contact nodes", "interface nodes active at the end"),
    ("wall time", "wall time (s)"),
]
COUNTS = {"temperature dofs", "displacement dofs", "active contact nodes", "wall time"}


def expanded(path, depth=0):
    """The scene's text with its 'include' lines replaced by the included files'
    (relative to the including file), so that entries set in an include can be
    read and changed here (contact-stefan refuses an entry set twice)."""
    if depth > 20:
        sys.exit(f"scene_convergence.py: includes nested too deeply at {path}")
    directory = os.path.dirname(os.path.abspath(path))
    lines = []
    with open(path) as f:
        for line in f:
            m = re.match(r"^\s*include\s+(\S+)", line)
            if m:
                lines.append(expanded(os.path.join(directory, m.group(1)), depth + 1))
            else:
                lines.append(line)
    return "".join(lines)


def run_level(binary, scene_text, scene_dir, level, subdivisions, settings, workdir, np_):
    text = scene_text
    for entry in settings:
        path, value = entry.split("=", 1)
        text = set_path(text, path, value)
    if subdivisions:
        value = get_path(text, "Geometry/Subdivisions", None)
        if value is None:
            sys.exit("scene_convergence.py: --subdivisions: the scene does not set "
                     "Geometry/Subdivisions")
        n = [int(v) for v in value.split(",")]
        text = set_path(text, "Geometry/Subdivisions", ", ".join(str(v * 2**level) for v in n))
    else:
        # L more refinements than the scene's own.
        base = int(get_path(text, "Mesh refinement/Initial global refinements", "0"))
        text = set_path(text, "Mesh refinement/Initial global refinements", str(base + level))
    text = set_path(text, "Output/Directory", os.path.join(workdir, f"level-{level}"))
    text = set_path(text, "Output/VTU interval", "0")
    # Beside the scene, so that its relative includes and meshes resolve; named
    # by the process (two studies of scenes in one folder).
    prm = os.path.join(scene_dir, f".convergence-{os.getpid()}-level-{level}.prm")
    with open(prm, "w") as f:
        f.write(text)
    try:
        cmd = [binary, prm] if np_ == 1 else ["mpirun", "--allow-run-as-root", "--oversubscribe",
                                               "-np", str(np_), binary, prm]
        p = subprocess.run(cmd, capture_output=True, text=True)
    finally:
        os.remove(prm)
    if p.returncode != 0:
        last = p.stderr.strip().splitlines()[-1:] or ["(no message)"]
        sys.exit(f"scene_convergence.py: level {level} failed: {last[0]}")
    results = {k: float(v) for k, v in re.findall(r"^RESULT (.*?) = (\S+)$", p.stdout, re.M)}
    forces = [v for k, v in results.items() if k.startswith("contact force")]
    if forces:
        results["contact force"] = sum(forces)
    # Summed over the contact groups, like the force. (The number of active
    # nodes is no measure on an adapted mesh, whose interface nodes are not
    # evenly spaced: the lengths are.)
    for key, prefix in (("contact length", "contact length "),
                        ("max contact length", "max contact length over the steps ")):
        lengths = [v for k, v in results.items() if k.startswith(prefix)]
        if lengths:
            results[key] = sum(lengths)
    return results


def fmt(key, v):
    if key == "wall time":
        return f"{v:.1f}"
    return f"{v:.0f}" if key in COUNTS else f"{v:.4g}"


def main():
    p = argparse.ArgumentParser(description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("scene")
    p.add_argument("--levels", default="0,1,2", help="comma-separated levels (default 0,1,2)")
    p.add_argument("--subdivisions", action="store_true",
                   help="refine by Geometry/Subdivisions x 2^L instead of global refinement")
    p.add_argument("--set", action="append", default=[], metavar="SUB/ENTRY=VALUE")
    p.add_argument("--target", type=float, default=5.0, help="percent (default 5)")
    p.add_argument("--np", type=int, default=1)
    p.add_argument("--binary", default=DEFAULT_BINARY)
    p.add_argument("--markdown", action="store_true")
    args = p.parse_args()
    levels = [int(v) for v in args.levels.split(",")]
    print(provenance_line(args.binary))
    scene_text = expanded(args.scene)
    with tempfile.TemporaryDirectory() as workdir:
        runs = []
        for level in levels:
            runs.append(run_level(args.binary, scene_text,
                                  os.path.dirname(os.path.abspath(args.scene)), level,
                                  args.subdivisions, args.set, workdir, args.np))
            print(f"level {level}: {runs[-1].get('wall time', float('nan')):.1f} s",
                  file=sys.stderr)
    header = (["quantity"] + [f"L{l}" for l in levels] +
              [f"L{a}→L{b}" for a, b in zip(levels, levels[1:])] + [f"last change < {args.target:g} %"])
    rows = []
    # The mean pressures of the scene's 'Output/Contact pressure windows', in
    # the order the run printed them.
    windows = []
    for r in runs:
        windows += [k for k in r if k.startswith("mean contact pressure") and k not in windows]
    for key, label in QUANTITIES + [(k, k + " (Pa)") for k in windows]:
        values = [r.get(key) for r in runs]
        if all(v is None for v in values):
            continue
        cells = [fmt(key, v) if v is not None else "-" for v in values]
        changes, verdict = [], ""
        for a, b in zip(values, values[1:]):
            changes.append(f"{100 * (b / a - 1):+.1f} %" if a and b is not None else "")
        if key not in COUNTS and len(values) > 1 and values[-2] and values[-1] is not None:
            verdict = "yes" if abs(values[-1] / values[-2] - 1) < args.target / 100 else "**no**"
        rows.append([label] + cells + changes + [verdict])
    if args.markdown:
        print("| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
        for r in rows:
            print("| " + " | ".join(r) + " |")
    else:
        widths = [max(len(str(r[i])) for r in rows + [header]) for i in range(len(header))]
        for r in [header] + rows:
            print("  ".join(str(c).rjust(w) if i else str(c).ljust(w)
                            for i, (c, w) in enumerate(zip(r, widths))))


if __name__ == "__main__":
    main()
