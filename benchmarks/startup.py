#!/usr/bin/python3
"""Time what a user waits for first: the command-line options, a whole run of the
shipped scenes, and the cost of writing VTU files per compression level.

    /usr/bin/python3 benchmarks/startup.py [--binary build/contact-stefan] [--repeat 3]

Prints (Markdown tables, after the '# run:' provenance line):
  1. the wall time of `--help`, `--version`, `--print-parameters` (answered by
     the launcher) and `--check prm/subduction.prm` (the solver, without MPI),
     the smallest and the largest of --repeat runs each; then the solver's
     `--version` with its libraries in the order of cmake/load_order.py
     against load-order-probe (the default order), max(10, 5 x --repeat)
     alternating pairs;
  2. the process wall time of the default scene (prm/subduction.prm, on its
     coarse mesh: the adaptation set in the file is switched off) and of the
     tutorial's scene, and the time loop's share (`RESULT wall time` less the
     set-up: the statistics' last wall_time minus step 0's); then both scenes
     with the serial MPI start (fast), with the isolated singleton alone and
     with Open MPI's own defaults (plain), alternating;
  3. the default scene (coarse) with a VTU file after every step for each
     `Output/VTU compression`: the `output: vtu` timer section, the run's
     `RESULT wall time` and the size of the output directory.
Times are of this machine and its load: quote ratios from one run of the script,
with its '# run:' line. Only the standard library is needed.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time

from ladder import set_path  # noqa: E402
from provenance import provenance_line  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)


# The variables of the serial MPI start: a mode sets them, the caller's are
# not passed on (they would change what a mode measures).
MPI_START_VARIABLES = ("CONTACT_STEFAN_SERIAL_MPI", "OMPI_MCA_pml",
                       "OMPI_MCA_ess_singleton_isolated")


def timed(command, cwd, env=None):
    start = time.perf_counter()
    base = {k: v for k, v in os.environ.items() if k not in MPI_START_VARIABLES}
    out = subprocess.run(command, cwd=cwd, capture_output=True, text=True,
                         env={**base, **(env or {})})
    elapsed = time.perf_counter() - start
    if out.returncode not in (0, 3):
        sys.exit("startup.py: %s failed: %s" % (" ".join(command), out.stderr.strip()[-300:]))
    return elapsed, out.stdout


def directory_size(path):
    return sum(os.path.getsize(os.path.join(d, f)) for d, _, files in os.walk(path) for f in files)


def loop_seconds(statistics):
    rows = [line.split() for line in open(statistics) if line.strip() and not line.startswith("#")]
    column = rows[0].index("wall_time")
    return float(rows[-1][column]) - float(rows[1][column])


def coarse(text):
    """The scene on its coarse mesh: the default scene adapts its mesh (about
    20 s), which would hide the start-up this script measures."""
    if "Adaptive refinement interval" in text:
        text = set_path(text, "Mesh refinement/Adaptive refinement interval", "0")
        text = set_path(text, "Mesh refinement/Initial adaptive refinements", "0")
    return text


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "contact-stefan"))
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(provenance_line(args.binary), flush=True)
    binary = os.path.abspath(args.binary)
    work = tempfile.mkdtemp(prefix="startup-")
    subduction = os.path.join(ROOT, "prm", "subduction.prm")

    print("\n| command | wall time (min–max of %d) |\n|---|---|" % args.repeat)
    for option in (["--help"], ["--version"], ["--print-parameters"], ["--check", subduction]):
        times = [timed([binary] + option, work)[0] for _ in range(args.repeat)]
        print("| `contact-stefan %s` | %.3f–%.3f s |" % (" ".join(option).replace(ROOT + "/", ""),
                                                      min(times), max(times)))

    # The solver's libraries in the order of cmake/load_order.py against the
    # default order (load-order-probe, the same code linked without it):
    # --version, which loads every library and does nothing else, in
    # alternating pairs.
    solver = os.path.join(os.path.dirname(binary), "contact-stefan-solver")
    probe = os.path.join(os.path.dirname(binary), "load-order-probe")
    if os.path.exists(probe):
        pairs = max(10, 5 * args.repeat)
        times = {"load order (contact-stefan-solver)": [], "default order (load-order-probe)": []}
        for _ in range(pairs):
            for program, name in ((probe, "default order (load-order-probe)"),
                                  (solver, "load order (contact-stefan-solver)")):
                times[name].append(timed([program, "--version"], work)[0])
        print("\n| libraries | `--version`: median (min–max) of %d alternating runs |\n|---|---|"
              % pairs)
        for name, values in times.items():
            values.sort()
            print("| %s | %.3f (%.3f–%.3f) s |" % (name, values[len(values) // 2], values[0],
                                                  values[-1]))

    print("\n| scene | process wall time (min–max of %d) | time loop (min) |\n|---|---|---|"
          % args.repeat)
    for name in ("subduction", "tutorial_ice_on_rock"):
        text = open(os.path.join(ROOT, "prm", name + ".prm")).read()
        text = set_path(text, "Output/Directory", "out-" + name)
        text = coarse(text)
        prm = os.path.join(work, name + ".prm")
        open(prm, "w").write(text)
        times, loops = [], []
        for _ in range(args.repeat):
            times.append(timed([binary, prm], work)[0])
            loops.append(loop_seconds(os.path.join(work, "out-" + name, "statistics.txt")))
        print("| `prm/%s.prm` | %.2f–%.2f s | %.2f s |" % (name, min(times), max(times), min(loops)))

    # A serial run starts MPI as an isolated singleton with the ob1 layer
    # (include/contact-stefan/app/mpi_start.h). Compared, in alternating runs
    # so that the machine's load falls on all alike: that ('fast'), the
    # isolated singleton alone (the code before the ob1 layer was named:
    # 'plain' with the isolation set by hand) and Open MPI's own defaults
    # ('plain': a singleton that forks its daemon).
    modes = {"fast": {},
             "isolated only": {"CONTACT_STEFAN_SERIAL_MPI": "plain",
                               "OMPI_MCA_ess_singleton_isolated": "1"},
             "plain": {"CONTACT_STEFAN_SERIAL_MPI": "plain"}}
    print("\n| scene | serial MPI start | process wall time: median (min–max) of %d "
          "alternating runs |\n|---|---|---|" % args.repeat)
    for name in ("subduction", "tutorial_ice_on_rock"):
        prm = os.path.join(work, name + ".prm")
        times = {mode: [] for mode in modes}
        for _ in range(args.repeat):
            for mode, env in modes.items():
                times[mode].append(timed([binary, prm], work, env)[0])
        for mode, values in times.items():
            values.sort()
            print("| `prm/%s.prm` | %s | %.2f (%.2f–%.2f) s |" % (
                name, mode, values[len(values) // 2], values[0], values[-1]))

    print("\n| VTU compression | output: vtu | RESULT wall time | output directory |\n"
          "|---|---|---|---|")
    for level in ("best compression", "default", "best speed", "none"):
        text = coarse(open(subduction).read())
        text = set_path(text, "Output/Directory", "out-vtu")
        text = set_path(text, "Output/VTU interval", "1")
        text = set_path(text, "Output/VTU compression", level)
        prm = os.path.join(work, "vtu.prm")
        open(prm, "w").write(text)
        _, stdout = timed([binary, prm], work)
        section = re.search(r"\| output: vtu\s*\|\s*\d+\s*\|\s*([0-9.e+-]+)s", stdout)
        wall = re.search(r"^RESULT wall time = (\S+)", stdout, re.M)
        print("| %s | %.2f s | %.2f s | %.2f MB |" % (
            level, float(section.group(1)), float(wall.group(1)),
            directory_size(os.path.join(work, "out-vtu")) / 1e6))


if __name__ == "__main__":
    main()
