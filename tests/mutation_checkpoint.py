#!/usr/bin/python3
"""Mutation test of checkpoints (issue 23, section 2).

A checkpoint is whole, of this run and of this geometry, or the resume is
refused in one line. This script writes checkpoints of a short adaptive scene
(Neumann case A) on each of --ranks, then damages them one way at a time and
resumes (on the same number of ranks). Classes:

  emptied, truncated, deleted, flipped   each file of the checkpoint: emptied,
                                         cut to half its size, removed, its
                                         middle byte inverted
  digit                                  each text file: the digit nearest its
                                         middle changed
  older                                  each file swapped with the same file of
                                         an older checkpoint of the same run
  other-run                              each file swapped with the same file of
                                         the checkpoint of another run (another
                                         latent heat), at the same step
  forged                                 a value changed in state.txt or the
                                         statistics copy, with the manifest
                                         written anew to match (the checks of
                                         the values read back: the time 1 %
                                         off, the step, rows dropped)
  mesh-file                              the scene's Gmsh mesh file changed
                                         under the same name
  new-only                               only an incomplete checkpoint.new
  old-hint                               a damaged checkpoint beside a
                                         checkpoint.old: the line must say so

A damaged case must be refused: exit code 1, exactly one non-empty line on
stderr ('contact-stefan: error: ...', no control bytes) that names the file
(or the manifest, for files of mixed checkpoints) and the cause, no signal,
and the output directory unchanged (statistics table and checkpoint byte for
byte). A swap with a byte-identical file is no damage: that case must run
(exit 0, empty stderr) and reproduce the uninterrupted run's statistics
(numbers to 1e-8 relative, without the wall time). It prints a FAIL line per
failure, the counts 'refused / ran / failed' per class and
'N passed, M failed'; exit code 1 if any failed. Standard library only:

  mutation_checkpoint.py --binary build/contact-stefan --source-dir . \\
      --mesh build/tests/two_blocks.msh [--ranks 1,2] [--jobs 2] [--keep DIR]
  mutation_checkpoint.py --rewrite-manifest out/checkpoint
"""

import argparse
import concurrent.futures
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "benchmarks"))
from ladder import set_path  # noqa: E402  (the one .prm editor of the project's scripts)

SCENE = "prm/benchmarks/neumann_A.prm"
GMSH_SCENE = "tests/scenes/two_blocks_gmsh.prm"
OUTPUT = "out"
# Adaptive (so that meshes of different steps differ), a checkpoint every 3
# steps: the last at step 12 of 15, an older one at step 6. Set in place
# (contact-stefan refuses an entry set twice).
SETTINGS = [
    ("Mesh refinement/Adaptive refinement interval", "1"),
    ("Mesh refinement/Initial adaptive refinements", "2"),
    ("Mesh refinement/Maximum level", "2"),
    ("Checkpoint/Interval (steps)", "3"),
    ("Output/Directory", OUTPUT),
    ("Output/VTU interval", "0"),
]
OTHER_RUN = [("Materials/Body 0/Phase change/Latent heats", "1.5")]
RESUME = [("Checkpoint/Resume", "true")]


def with_settings(text, settings):
    for path, value in settings:
        text = set_path(text, path, value)
    return text


TEXT_FILES = {"manifest", "state.txt", "statistics", "mesh.info"}
CAUSES = {
    "emptied": r"emptied|is empty",
    "truncated": r"truncated|incomplete",
    "deleted": r"is missing",
    "flipped": r"damaged|does not match",
    "digit": r"damaged|does not match",
    "older": r"damaged|does not match|another checkpoint|different checkpoints",
    "other-run": r"damaged|does not match|another checkpoint|different checkpoints",
    "forged": r"does not hold a valid state|rows|not the time|statistics",
    "mesh-file": r"another content of the mesh file",
    "new-only": r"only the unfinished '[^']*checkpoint\.new'.*incomplete",
    "old-hint": r"damaged.*previous one exists: rename 'checkpoint\.old'",
}


def run(binary, np, arguments, cwd, env_extra=None, timeout=120):
    env = dict(os.environ)
    env.update(env_extra or {})
    tmp = tempfile.mkdtemp(prefix="ckpt-mpi-")  # Open MPI's session directory
    env["TMPDIR"] = tmp
    command = [binary] + arguments
    if np > 1:
        # (--quiet: without the launcher's own banner about a rank's exit code)
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--quiet", "-np",
                   str(np)] + command
    try:
        p = subprocess.run(command, cwd=cwd, env=env, capture_output=True, timeout=timeout)
        return p.returncode, p.stdout.decode("latin-1"), p.stderr.decode("latin-1")
    except subprocess.TimeoutExpired:
        return None, "", "timeout"
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def fnv1a(data):
    h = 14695981039346656037
    for b in data:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return "%016x" % h


def write_manifest(directory):
    """The manifest written anew for the files now in directory (as the
    program writes it), so that only the checks of the values remain."""
    path = os.path.join(directory, "manifest")
    head = open(path).read().split("\nfile ")[0] + "\n"
    text = head
    for name in sorted(os.listdir(directory)):
        if name != "manifest":
            data = open(os.path.join(directory, name), "rb").read()
            text += "file %s %d %s\n" % (name, len(data), fnv1a(data))
    open(path, "w").write(text + "checksum %s\n" % fnv1a(text.encode()))


def snapshot(directory):
    """Every file under directory (relative path -> bytes)."""
    files = {}
    for root, _, names in os.walk(directory):
        for name in names:
            path = os.path.join(root, name)
            files[os.path.relpath(path, directory)] = open(path, "rb").read()
    return files


def deterministic(statistics):
    """The statistics table without its wall_time column, as rows of tokens."""
    lines = [line.split() for line in statistics.decode().splitlines()
             if not line.startswith("#")]
    keep = [i for i, word in enumerate(lines[0]) if word != "wall_time"]
    return [[row[i] for i in keep if i < len(row)] for row in lines]


def same_numbers(a, b):
    if len(a) != len(b):
        return False
    for row_a, row_b in zip(a, b):
        if len(row_a) != len(row_b):
            return False
        for x, y in zip(row_a, row_b):
            if x == y:
                continue
            try:
                fx, fy = float(x), float(y)
            except ValueError:
                return False
            if abs(fx - fy) > 1e-8 * max(abs(fx), abs(fy)) + 1e-12:
                return False
    return True


class Case:
    def __init__(self, np, cls, name, prepare, expect_file, scene="scene.prm", base="run"):
        self.np, self.cls, self.name = np, cls, name
        self.prepare, self.expect_file, self.scene, self.base = prepare, expect_file, scene, base


def mutate_bytes(kind, data):
    if kind == "emptied":
        return b""
    if kind == "truncated":
        return data[: len(data) // 2]
    if kind == "flipped":
        i = len(data) // 2
        return data[:i] + bytes([data[i] ^ 0xFF]) + data[i + 1:]
    if kind == "digit":
        digits = [m.start() for m in re.finditer(rb"[0-9]", data)]
        if not digits:
            return None
        i = min(digits, key=lambda k: abs(k - len(data) // 2))
        new = b"7" if data[i:i + 1] != b"7" else b"3"
        return data[:i] + new + data[i + 1:]
    raise ValueError(kind)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--binary")
    parser.add_argument("--source-dir")
    parser.add_argument("--mesh", help="two_blocks.msh of the test suite")
    parser.add_argument("--rewrite-manifest", metavar="DIR",
                        help="only write the manifest of checkpoint DIR anew (for "
                             "tests/resume_damaged.sh) and exit")
    parser.add_argument("--ranks", default="1,2")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--keep", help="keep the work directories here")
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    if args.rewrite_manifest:
        write_manifest(args.rewrite_manifest)
        return 0
    if not (args.binary and args.source_dir and args.mesh):
        parser.error("--binary, --source-dir and --mesh are required")
    binary = os.path.abspath(args.binary)
    source = os.path.abspath(args.source_dir)
    work = args.keep or tempfile.mkdtemp(prefix="mutation-checkpoint-")
    os.makedirs(work, exist_ok=True)
    scene_text = with_settings(open(os.path.join(source, SCENE)).read(), SETTINGS)
    gmsh_text = with_settings(open(os.path.join(source, GMSH_SCENE)).read(),
                              [("Checkpoint/Interval (steps)", "3"), ("Output/Directory", OUTPUT)])

    def setup_failed(message):
        print("FAIL setup: " + message)
        sys.exit(1)

    # The checkpoints to damage, per number of ranks.
    cases = []
    bases = {}
    for np in [int(n) for n in args.ranks.split(",")]:
        root = os.path.join(work, "np%d" % np)
        os.makedirs(root, exist_ok=True)
        # The run: killed after step 7 (its checkpoint of step 6 kept as the
        # older one), then resumed to the end (last checkpoint: step 12).
        d = os.path.join(root, "run")
        os.makedirs(d, exist_ok=True)
        open(os.path.join(d, "scene.prm"), "w").write(scene_text)
        code, _, err = run(binary, np, ["scene.prm"], d, {"CONTACT_STEFAN_KILL_AFTER_STEP": "7"})
        if code == 0 or not os.path.isdir(os.path.join(d, OUTPUT, "checkpoint")):
            setup_failed("np %d: the run was not killed after a checkpoint: %s" % (np, err))
        shutil.copytree(os.path.join(d, OUTPUT, "checkpoint"), os.path.join(root, "older"))
        code, _, err = run(binary, np, ["--resume", "scene.prm"], d)
        if code != 0:
            setup_failed("np %d: the resume failed: %s" % (np, err))
        # The uninterrupted run (the reference of the cases that run).
        w = os.path.join(root, "whole")
        os.makedirs(w, exist_ok=True)
        open(os.path.join(w, "scene.prm"), "w").write(scene_text)
        code, _, err = run(binary, np, ["scene.prm"], w)
        if code != 0:
            setup_failed("np %d: the uninterrupted run failed: %s" % (np, err))
        reference = deterministic(open(os.path.join(w, OUTPUT, "statistics.txt"), "rb").read())
        if not same_numbers(reference, deterministic(
                open(os.path.join(d, OUTPUT, "statistics.txt"), "rb").read())):
            setup_failed("np %d: the resumed run differs from the uninterrupted one" % np)
        # Another run: another latent heat.
        o = os.path.join(root, "other")
        os.makedirs(o, exist_ok=True)
        open(os.path.join(o, "scene.prm"), "w").write(with_settings(scene_text, OTHER_RUN))
        code, _, err = run(binary, np, ["scene.prm"], o)
        if code != 0:
            setup_failed("np %d: the other run failed: %s" % (np, err))
        # Killed while writing its first checkpoint: checkpoint.new alone.
        n = os.path.join(root, "new")
        os.makedirs(n, exist_ok=True)
        open(os.path.join(n, "scene.prm"), "w").write(scene_text)
        code, _, err = run(binary, np, ["scene.prm"], n,
                           {"CONTACT_STEFAN_KILL_DURING_CHECKPOINT": "3"})
        if code == 0 or not os.path.isdir(os.path.join(n, OUTPUT, "checkpoint.new")):
            setup_failed("np %d: the run was not killed while writing" % np)
        # The Gmsh scene.
        g = os.path.join(root, "gmsh")
        os.makedirs(g, exist_ok=True)
        open(os.path.join(g, "scene.prm"), "w").write(gmsh_text)
        shutil.copy(args.mesh, os.path.join(g, "two_blocks.msh"))
        code, _, err = run(binary, np, ["scene.prm"], g)
        if code != 0:
            setup_failed("np %d: the Gmsh scene failed: %s" % (np, err))
        bases[np] = {"run": d, "new": n, "gmsh": g, "reference": reference}

        checkpoint = os.path.join(d, OUTPUT, "checkpoint")
        for name in sorted(os.listdir(checkpoint)):
            here = "checkpoint/" + name
            for kind in ["emptied", "truncated", "deleted", "flipped", "digit"]:
                if kind == "digit" and name not in TEXT_FILES:
                    continue
                cases.append(Case(np, kind, name, (kind, name), here))
            for kind, source_dir in [("older", os.path.join(root, "older")),
                                     ("other-run", os.path.join(o, OUTPUT, "checkpoint"))]:
                cases.append(Case(np, kind, name, ("swap", name, source_dir), here))
        forged = [("time 1 % later", "state.txt", "time"),
                  ("step 12 -> 13", "state.txt", "step"),
                  ("statistics rows 0-3 dropped", "statistics", "rows"),
                  ("statistics emptied", "statistics", "empty")]
        for label, name, what in forged:
            cases.append(Case(np, "forged", label, ("forge", name, what), "checkpoint/" + name))
        cases.append(Case(np, "mesh-file", "node moved", ("mesh",), "two_blocks.msh",
                          base="gmsh"))
        cases.append(Case(np, "new-only", "killed while writing", ("none",), "checkpoint.new",
                          base="new"))
        cases.append(Case(np, "old-hint", "flipped mesh beside checkpoint.old",
                          ("old", os.path.join(root, "older")), "checkpoint/mesh"))

    def apply(case, directory):
        """Damages the copy in directory; False: the file is unchanged."""
        cp = os.path.join(directory, OUTPUT, "checkpoint")
        action = case.prepare
        if action[0] in ("emptied", "truncated", "flipped", "digit"):
            path = os.path.join(cp, action[1])
            data = open(path, "rb").read()
            new = mutate_bytes(action[0], data)
            if new is None or new == data:
                return False
            open(path, "wb").write(new)
        elif action[0] == "deleted":
            os.remove(os.path.join(cp, action[1]))
        elif action[0] == "swap":
            data = open(os.path.join(action[2], action[1]), "rb").read()
            unchanged = data == open(os.path.join(cp, action[1]), "rb").read()
            open(os.path.join(cp, action[1]), "wb").write(data)
            return not unchanged
        elif action[0] == "forge":
            path = os.path.join(cp, action[1])
            text = open(path).read()
            if action[2] == "time":
                # state.txt: '... <n_ranks> <time> <step size> <step> ...'
                m = re.search(r" ([0-9]) ([0-9.e+-]+) ([0-9.e+-]+) 12 ", text)
                t = "%.17e" % (float(m.group(2)) * 1.01)
                text = text[:m.start(2)] + t + text[m.end(2):]
            elif action[2] == "step":
                m = re.search(r" ([0-9]) ([0-9.e+-]+) ([0-9.e+-]+) 12 ", text)
                text = text[:m.start()] + m.group(0).replace(" 12 ", " 13 ") + text[m.end():]
            elif action[2] == "rows":
                lines = text.splitlines(True)
                # The header: its comment lines and the line of column names.
                header = next(k for k, line in enumerate(lines) if not line.startswith("#")) + 1
                text = "".join(lines[:header]) + "".join(lines[header + 4:])
            else:
                text = ""
            open(path, "w").write(text)
            write_manifest(cp)
        elif action[0] == "mesh":
            path = os.path.join(directory, "two_blocks.msh")
            text = open(path).read()
            new = text.replace("\n12 2 1 0\n", "\n12 2.1 1 0\n")
            if new == text:
                raise RuntimeError("no node 12 at (2, 1) in the mesh")
            open(path, "w").write(new)
        elif action[0] == "old":
            shutil.copytree(action[1], cp + ".old")
            path = os.path.join(cp, "mesh")
            data = open(path, "rb").read()
            open(path, "wb").write(mutate_bytes("flipped", data))
        return True

    def check(case):
        base = bases[case.np][case.base]
        directory = os.path.join(work, "np%d" % case.np, "cases",
                                 re.sub(r"[^A-Za-z0-9.-]+", "_", case.cls + "-" + case.name))
        shutil.rmtree(directory, ignore_errors=True)
        shutil.copytree(base, directory)
        scene = os.path.join(directory, "scene.prm")
        resumed = with_settings(open(scene).read(), RESUME)
        open(scene, "w").write(resumed)
        damaged = apply(case, directory)
        before = snapshot(os.path.join(directory, OUTPUT))
        code, _, err = run(binary, case.np, ["scene.prm"], directory)
        label = "np %d %s %s" % (case.np, case.cls, case.name)
        problems = []
        if code is None:
            problems.append("timeout")
        elif code < 0:
            problems.append("killed by signal %d" % -code)
        if damaged:
            outcome = "refused"
            lines = err.splitlines()
            if code != 1:
                problems.append("exit code %s, expected 1" % code)
            if len(lines) != 1 or not lines[0].strip():
                problems.append("stderr is %d lines" % len(lines))
            line = lines[0] if lines else ""
            if not line.startswith("contact-stefan: error: "):
                problems.append("not an error line")
            if re.search(r"[^\x20-\x7e]", err.rstrip("\n")):
                problems.append("control or non-ASCII bytes on stderr")
            name = case.expect_file
            mixed = ("checkpoint/manifest'" in line and
                     re.search(r"\b%s\b" % re.escape(name.split("/")[-1]), line))
            if name not in line and not mixed:
                problems.append("the line does not name '%s'" % name)
            if not re.search(CAUSES[case.cls], line):
                problems.append("the line does not say the cause (%s)" % CAUSES[case.cls])
            if snapshot(os.path.join(directory, OUTPUT)) != before:
                problems.append("the output directory was changed")
        else:
            outcome = "ran"
            if code != 0 or err.strip():
                problems.append("a whole checkpoint (identical file) was refused: %s" % err.strip())
            else:
                statistics = open(os.path.join(directory, OUTPUT, "statistics.txt"), "rb").read()
                if not same_numbers(bases[case.np]["reference"], deterministic(statistics)):
                    problems.append("the resumed run differs from the uninterrupted one")
        if problems:
            outcome = "failed"
        elif not args.keep:
            shutil.rmtree(directory, ignore_errors=True)
        return case, outcome, label, problems, err.strip()

    counts = {}
    failed = passed = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for case, outcome, label, problems, err in pool.map(check, cases):
            counts.setdefault(case.cls, {"refused": 0, "ran": 0, "failed": 0})[outcome] += 1
            if problems:
                failed += 1
                print("FAIL %s: %s | stderr: %s" % (label, "; ".join(problems), err[:300]))
            else:
                passed += 1
                if args.verbose:
                    print("ok   %s: %s" % (label, err[:200] if err else "ran"))
    print("%-10s %8s %5s %7s" % ("class", "refused", "ran", "failed"))
    for cls in CAUSES:
        if cls in counts:
            c = counts[cls]
            print("%-10s %8d %5d %7d" % (cls, c["refused"], c["ran"], c["failed"]))
    print("%d passed, %d failed" % (passed, failed))
    if not args.keep:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
