#!/usr/bin/python3
"""Mutation test of a run's output under signals and rival runs (issue 23, section 4).

A run writes VTU files, a PVD index, a statistics table and checkpoints; none of
that may be left damaged or mixed by a signal or by a second run into the same
directory. This script runs Neumann case A (180 steps, VTU every step, a
checkpoint every 25) uninterrupted once, then:

  term   SIGTERM at 12 fixed fractions of the uninterrupted run's wall time
         (serial)
  int    SIGINT at 4 fractions (serial)
  usr1   SIGUSR1 to mpirun at 5 fractions of the 2-rank run's time (mpirun
         forwards it; SIGTERM it follows by SIGKILL after a second); at least
         one must stop the run between two steps
  rival  two runs started into one directory at offsets 0, 0.05 and 0.3 s
         (with a 5x smaller step, so that the first outlasts the offset)

A signal before main() (while the libraries load, about 0.3 s; under mpirun on
a rank still loading) ends the process by its default action: accepted
('stopped before start-up') only if what was written is whole. Every other stopped case must end with exit 143
(SIGTERM), 130 (SIGINT) or 138 (SIGUSR1) and exactly
one stderr line naming the signal, or with exit 0 if it finished first; the
statistics rows must be complete and consecutive; the PVD index must be whole and
every file it names (and each piece) complete, with no unlisted solution file
beside it. If the stopped run left a checkpoint, --resume must finish it: exit 0,
all rows, and the same errors (RESULT lines with 'error') as the uninterrupted run
to 1e-8 relative. Of two rival runs exactly one runs (exit 0, complete output);
the other is refused with exit 1 and one line saying the directory is in use.
No case may end by a signal, print a backtrace or hang (--timeout).

  mutation_guard.py --binary build/contact-stefan --source-dir . [--keep DIR]

It prints a FAIL line per failure, the counts 'refused / ran / stopped / failed'
per class and 'N passed, M failed'; exit code 1 if any failed. Standard library
only.
"""

import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "benchmarks"))
from ladder import set_path  # noqa: E402

SCENE = "prm/benchmarks/neumann_A.prm"
OUTPUT = "out"
ROWS = None  # statistics rows of the uninterrupted run (steps + 1)
SETTINGS = [
    ("Time stepping/Time step", "0.005"),  # 180 steps from t = 0.1 to 1
    ("Checkpoint/Interval (steps)", "25"),
    ("Output/Directory", OUTPUT),
    ("Output/VTU interval", "1"),
]
TERM_FRACTIONS = [0.02, 0.15, 0.25, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 0.97, 1.2]
USR1_FRACTIONS_MPI = [0.2, 0.5, 0.7, 0.8, 0.9]
INT_FRACTIONS = [0.1, 0.45, 0.75, 0.99]
RIVAL_OFFSETS = [0.0, 0.05, 0.3]
# The rival runs take a five times smaller step (900 steps, about 3 s alone)
# so that the second one's start-up (0.3-0.5 s under ctest -j2) ends well
# inside the first run even at the largest offset: with the 0.6 s run, the
# offset 0.3 s let the first finish before the second took the lock in CI.
RIVAL_TIME_STEP = "0.001"
RIVAL_ROWS = 901


def command(binary, np, extra=()):
    c = [binary] + list(extra) + ["scene.prm"]
    if np > 1:
        c = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--quiet", "-np", str(np)] + c
    return c


def start(binary, np, cwd, extra=()):
    env = dict(os.environ)
    env["TMPDIR"] = tempfile.mkdtemp(prefix="guard-mpi-")
    out = open(os.path.join(cwd, "stdout%s.txt" % ("".join(extra))), "wb")
    err = open(os.path.join(cwd, "stderr%s.txt" % ("".join(extra))), "wb")
    p = subprocess.Popen(command(binary, np, extra), cwd=cwd, env=env, stdout=out, stderr=err)
    p.files = (out, err, env["TMPDIR"])
    return p


def finish(p, timeout):
    try:
        code = p.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        p.kill()
        p.wait()
        code = None
    out, err, tmp = p.files
    out.close()
    err.close()
    shutil.rmtree(tmp, ignore_errors=True)
    # Open MPI's singleton daemon sometimes complains about its own session
    # files when the process ends early ('[host:pid] PMIX ERROR: ...'): not
    # the program's output.
    text = re.sub(r"(?m)^\[[^\]]*\] PMIX ERROR: .*\n?", "",
                  open(err.name, encoding="latin-1").read())
    return code, open(out.name, encoding="latin-1").read(), text


def statistics_problem(directory, rows_expected=None):
    path = os.path.join(directory, "statistics.txt")
    if not os.path.isfile(path):
        return "no statistics table"
    lines = open(path, encoding="latin-1").read().split("\n")
    if lines[-1] != "":
        return "the statistics table does not end with a complete line"
    # Without the header's comment lines (column units and meanings).
    lines = [line for line in lines[:-1] if not line.startswith("#")]
    if not lines:
        return "the statistics table has no line of column names"
    n = len(lines[0].split())
    for k, line in enumerate(lines[1:]):
        fields = line.split()
        if len(fields) != n:
            return "statistics row %d has %d of %d columns" % (k, len(fields), n)
        if fields[0] != str(k):
            return "statistics row %d is step %s (rows lost or repeated)" % (k, fields[0])
    if rows_expected is not None and len(lines) - 1 != rows_expected:
        return "%d statistics rows, expected %d" % (len(lines) - 1, rows_expected)
    return None


def complete(path):
    try:
        return open(path, "rb").read().rstrip().endswith(b"</VTKFile>")
    except OSError:
        return False


def pvd_problem(directory):
    pvd = os.path.join(directory, "solution.pvd")
    if not complete(pvd):
        return "solution.pvd is missing or not whole"
    listed = re.findall(r'file="([^"]*)"', open(pvd).read())
    for name in listed:
        if not complete(os.path.join(directory, name)):
            return "%s (in the index) is missing or cut" % name
        for piece in re.findall(r'Source="([^"]*)"', open(os.path.join(directory, name)).read()):
            if not complete(os.path.join(directory, piece)):
                return "piece %s of %s is missing or cut" % (piece, name)
    present = sorted(f for f in os.listdir(directory) if re.match(r"solution_\d+\.pvtu$", f))
    if present != sorted(listed):
        return "the index lists %d files, the directory holds %d" % (len(listed), len(present))
    return None


def errors(stdout):
    return {m.group(1): float(m.group(2))
            for m in re.finditer(r"^RESULT (.*error.*) = (\S+)$", stdout, re.M)}


def same_errors(a, b):
    if a.keys() != b.keys():
        return "RESULT error lines differ: %s" % sorted(set(a) ^ set(b))
    for k in a:
        if abs(a[k] - b[k]) > 1e-8 * max(abs(a[k]), abs(b[k])) + 1e-300:
            return "'%s' = %.12g, uninterrupted %.12g" % (k, b[k], a[k])
    return None


def bad_stderr(err):
    lines = [l for l in err.split("\n") if l]
    if len(lines) != 1:
        return "stderr is %d lines, not one: %r" % (len(lines), err[:300])
    if re.search(r"[^\x20-\x7e]", lines[0]):
        return "stderr holds control or non-ASCII bytes"
    return None


def stopped_case(binary, np, sig, delay, work, reference, timeout):
    """A run stopped by sig after delay seconds: its output, then its resume."""
    p = start(binary, np, work)
    time.sleep(delay)
    if p.poll() is None:
        p.send_signal(sig)
    code, out, err = finish(p, timeout)
    directory = os.path.join(work, OUTPUT)
    expected = 128 + sig
    if code == 0:
        problem = statistics_problem(directory, ROWS) or pvd_problem(directory)
        return ("failed" if problem else "ran", problem)
    if not err.strip() and code in (expected, -sig, 1):
        # Before main(): while the dynamic loader maps and initialises the
        # MPI, Trilinos and PETSc libraries (about 0.3 s) no handler can be
        # installed and the signal ends the process (under mpirun: one rank
        # that was still loading, and mpirun ends the others). Accepted when
        # what was written is whole: no directory, or complete rows and index.
        if not os.path.exists(directory):
            return ("early", None)
        problem = (statistics_problem(directory) if
                   os.path.exists(os.path.join(directory, "statistics.txt")) else None)
        problem = problem or (pvd_problem(directory) if
                              os.path.exists(os.path.join(directory, "solution.pvd")) else None)
        return ("failed", "killed in start-up with damaged output: " + problem) if problem \
            else ("early", None)
    if code != expected:
        return ("failed", "exit %s, expected %d or 0; stderr %r" % (code, expected, err[:300]))
    name = signal.Signals(sig).name
    problem = bad_stderr(err) or (None if ("stopped by " + name) in err else
                                  "stderr does not name %s: %r" % (name, err))
    problem = problem or statistics_problem(directory) or pvd_problem(directory)
    if problem:
        return ("failed", problem)
    if not os.path.isdir(os.path.join(directory, "checkpoint")):
        return ("stopped", None)
    p = start(binary, np, work, ["--resume"])
    code, out, err = finish(p, timeout)
    if code != 0 or err:
        return ("failed", "the resume: exit %s, stderr %r" % (code, err[:300]))
    problem = (statistics_problem(directory, ROWS) or pvd_problem(directory) or
               same_errors(reference, errors(out)))
    return ("failed" if problem else "stopped", problem and "after the resume: " + problem)


def rival_case(binary, offset, work, timeout):
    # Both runs may finish when the machine is so loaded (ctest -j2) that the
    # second one's start-up outlasts the first run (about 1 s): then they did
    # not overlap, and nothing was to be refused. Such an attempt is repeated,
    # twice at most; a broken lock fails every attempt.
    for attempt in range(3):
        result = rival_attempt(binary, offset, os.path.join(work, "attempt%d" % attempt), timeout)
        if result != "sequential":
            return result
    return ("failed", "exit codes 0 and 0 in three attempts, expected one 0 and one 1")


def rival_attempt(binary, offset, work, timeout):
    os.makedirs(work, exist_ok=True)
    text = open(os.path.join(os.path.dirname(work), "scene.prm")).read()
    open(os.path.join(work, "scene.prm"), "w").write(
        set_path(text, "Time stepping/Time step", RIVAL_TIME_STEP))
    a = start(binary, 1, work, [])
    time.sleep(offset)
    os.makedirs(os.path.join(work, "b"), exist_ok=True)
    shutil.copy(os.path.join(work, "scene.prm"), os.path.join(work, "b", "scene.prm"))
    # The second run in a directory of its own whose Output/Directory is the
    # first one's: the same output directory, other stdout/stderr files.
    text = open(os.path.join(work, "b", "scene.prm")).read()
    open(os.path.join(work, "b", "scene.prm"), "w").write(
        set_path(text, "Output/Directory", os.path.join(work, OUTPUT)))
    b = start(binary, 1, os.path.join(work, "b"), [])
    (ca, oa, ea), (cb, ob, eb) = finish(a, timeout), finish(b, timeout)
    codes = sorted([ca, cb], key=lambda c: -1 if c is None else c)
    if codes == [0, 0]:
        return "sequential"
    if codes != [0, 1]:
        return ("failed", "exit codes %s and %s, expected one 0 and one 1" % (ca, cb))
    refused = ea if ca == 1 else eb
    problem = bad_stderr(refused) or (None if "is in use by another run" in refused else
                                      "the refusal does not say why: %r" % refused)
    directory = os.path.join(work, OUTPUT)
    problem = problem or statistics_problem(directory, RIVAL_ROWS) or pvd_problem(directory)
    return ("failed" if problem else "refused", problem)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary", required=True)
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--timeout", type=float, default=120)
    parser.add_argument("--keep", help="keep the work directories here")
    args = parser.parse_args()
    binary = os.path.abspath(args.binary)
    root = args.keep or tempfile.mkdtemp(prefix="mutation-guard-")
    os.makedirs(root, exist_ok=True)
    text = open(os.path.join(args.source_dir, SCENE)).read()
    for path, value in SETTINGS:
        text = set_path(text, path, value)

    def workdir(name):
        d = os.path.join(root, name)
        shutil.rmtree(d, ignore_errors=True)
        os.makedirs(d)
        open(os.path.join(d, "scene.prm"), "w").write(text)
        return d

    begin = time.time()
    p = start(binary, 1, workdir("whole"))
    code, out, err = finish(p, args.timeout)
    wall = time.time() - begin
    global ROWS
    if code != 0 or statistics_problem(os.path.join(root, "whole", OUTPUT)):
        print("FAIL setup: the uninterrupted run: exit %s %r" % (code, err[:300]))
        return 1
    reference = errors(out)
    ROWS = sum(1 for line in open(os.path.join(root, "whole", OUTPUT, "statistics.txt"))
               if not line.startswith("#")) - 1

    # On 2 ranks: SIGUSR1 to mpirun, which forwards it (SIGTERM it follows by
    # SIGKILL after a second), at fractions of the 2-rank run's own time.
    begin = time.time()
    code, _, err = finish(start(binary, 2, workdir("whole-np2")), args.timeout)
    wall_np2 = time.time() - begin
    if code != 0:
        print("FAIL setup: the uninterrupted run on 2 ranks: exit %s %r" % (code, err[:300]))
        return 1
    # (class, ranks, signal, delays)
    stops = [("term", 1, signal.SIGTERM, [f * wall for f in TERM_FRACTIONS]),
             ("int", 1, signal.SIGINT, [f * wall for f in INT_FRACTIONS]),
             ("usr1", 2, signal.SIGUSR1, [f * wall_np2 for f in USR1_FRACTIONS_MPI])]
    cases = [(cls, "np%d-%.2fs" % (np, delay),
              lambda d, np=np, sig=sig, delay=delay: stopped_case(
                  binary, np, sig, delay, d, reference, args.timeout))
             for cls, np, sig, delays in stops for delay in delays]
    for offset in RIVAL_OFFSETS:
        cases.append(("rival", "offset-%.2f" % offset,
                      lambda d, o=offset: rival_case(binary, o, d, args.timeout)))

    counts = {}
    failed = 0
    for cls, name, run in cases:
        verdict, problem = run(workdir(cls + "-" + name))
        counts.setdefault(cls, {"refused": 0, "ran": 0, "stopped": 0, "early": 0, "failed": 0})
        counts[cls][verdict] += 1
        if verdict == "failed":
            failed += 1
            print("FAIL %s %s: %s" % (cls, name, problem))
    if counts.get("usr1", {}).get("stopped", 0) == 0:
        failed += 1
        print("FAIL usr1: no 2-rank run was stopped between two steps (all too early or late)")
    for cls, c in counts.items():
        print("%-6s refused: %d  ran: %d  stopped: %d  stopped before start-up: %d  failed: %d" %
              (cls, c["refused"], c["ran"], c["stopped"], c["early"], c["failed"]))
    print("uninterrupted run %.2f s; %d cases" % (wall, len(cases)))
    print("%d passed, %d failed" % (len(cases) - failed, failed))
    if not args.keep and failed == 0:
        shutil.rmtree(root, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
