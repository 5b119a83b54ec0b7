#!/usr/bin/python3
"""Check the numbers that README.md and doc/*.md quote against what the code prints now.

Issue 32: every quantitative statement in the documentation is either produced
by a script in benchmarks/ or removed, and the claims that are cheap to re-check
(counts, errors, iteration numbers) are checked against a run of the current
binary. The claims are data, in benchmarks/claims.json; each one names

  file        the document, relative to the repository root ("doc/results.md")
  text        an exact passage of that document that contains the number; runs of
              white space (line breaks included) compare as one space, so a
              passage may cross a line break of the Markdown source
  prm         a scene file relative to the repository root
  set         optional list of "Subsection/Entry=value": the entry is replaced
              where the scene sets it in that subsection path and appended
              otherwise (as tests/apply_settings.sh and benchmarks/ladder.py do)
  result      what the run printed:
                "NAME"                      the line 'RESULT NAME = value'
                ["NAME1", "NAME2"]          the sum of several RESULT lines
                "statistics:COLUMN:ROW"     a value of the statistics table;
                                            ROW is a step number (0: the initial
                                            state), "last", or min/max/sum/mean
                                            over the rows, optionally of steps
                                            a..b-1 as in "min@2:" or "max@1:5"
                "stdout:REGEX"              the first group of the first match
                                            of REGEX in the screen output
                "ctest:LABEL"               the number of tests 'ctest -N'
                                            lists (with '-L LABEL' unless LABEL
                                            is empty); needs --build-dir, else
                                            the claim is skipped
  expected    the number as the document quotes it, as a string ("5.5e8" for
              5.5·10⁸), so that its precision is known
  tolerance   "quoted" (the default): the value must round to the quoted digits,
              |measured - expected| <= half a unit of the last quoted digit;
              {"rel": r} or {"abs": a}: for numbers quoted as "about";
              "at most" / "at least": the document states a bound
              ("energy residual <= 3.7e-16", "within 0.7 %")
  note        optional: where the number comes from, why this tolerance

Each distinct (prm, set) combination runs once, in a temporary work directory
of its own (the scene's Output/Directory is relative to it), on --jobs
processes at a time. Then one line per claim: PASS or FAIL, where the passage
is, the passage, the measured value. A passage that is no longer in the
document fails too: a change of a quoted number must change the table with it.
Exit code 1 if any claim fails.

    /usr/bin/python3 benchmarks/check_claims.py [--binary build/contact-stefan]
        [--claims benchmarks/claims.json] [--only doc/results.md] [--list]
        [--jobs 2] [--build-dir build] [--keep]

Timings are not claims: they depend on the machine, and the documents give the
machine, commit and date of the runs that produced them. Only the standard
library is needed.
"""
import argparse
import concurrent.futures
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from ladder import get_path, set_path  # noqa: E402
from provenance import provenance_line  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
DEFAULT_BINARY = os.path.join(ROOT, "build", "contact-stefan")
DEFAULT_CLAIMS = os.path.join(HERE, "claims.json")
RUN_TIMEOUT = 600  # seconds per scene; the claims' scenes take about one


# --- the claims ----------------------------------------------------------------------

def load_claims(path):
    with open(path, encoding="utf-8") as f:
        data = json.load(f)
    claims = data["claims"] if isinstance(data, dict) else data
    for k, c in enumerate(claims):
        for field in ("file", "text", "result", "expected"):
            if field not in c:
                sys.exit(f"check_claims.py: claim {k + 1} has no '{field}'")
        if not str(c["result"]).startswith("ctest:") and "prm" not in c:
            sys.exit(f"check_claims.py: claim {k + 1} has no 'prm'")
        c.setdefault("set", [])
        c.setdefault("tolerance", "quoted")
        c["number"] = k + 1
    return claims


def run_key(claim):
    """Claims with the same scene and the same settings share one run."""
    if str(claim["result"]).startswith("ctest:"):
        return None
    return (claim["prm"], tuple(sorted(claim["set"])))


def normalise(text):
    return " ".join(text.split())


def locate(document, passage):
    """Line number (1-based) where the passage starts in the document, white
    space compared as one space; None if it is not there."""
    words = passage.split()
    if not words:
        return None
    flat, starts, line = [], [], 1
    for m in re.finditer(r"\S+|\n", document):
        if m.group() == "\n":
            line += 1
        else:
            flat.append(m.group())
            starts.append(line)
    target = normalise(passage)
    joined = " ".join(flat)
    pos = joined.find(target)
    if pos < 0:
        return None
    return starts[joined.count(" ", 0, pos)]


def half_unit(expected):
    """Half a unit of the last digit of a quoted number ('6.826e-03' -> 5e-7)."""
    m = re.fullmatch(r"\s*[-+]?(\d*)(?:\.(\d*))?(?:[eE]([-+]?\d+))?\s*", expected)
    if not m or not (m.group(1) or m.group(2)):
        raise ValueError(f"'{expected}' is not a number as quoted")
    decimals = len(m.group(2) or "")
    exponent = int(m.group(3) or 0)
    return 0.5 * 10.0 ** (exponent - decimals)


def compare(measured, claim):
    """(passed, the tolerance in words)."""
    expected = float(claim["expected"])
    tol = claim["tolerance"]
    if tol == "quoted":
        bound = half_unit(claim["expected"]) * (1 + 1e-9) + 1e-12 * abs(expected)
        return (abs(measured - expected) <= bound,
                f"quoted {claim['expected']} ± {bound:.2g} (its last digit)")
    if tol == "at most":
        return measured <= expected, f"quoted as at most {claim['expected']}"
    if tol == "at least":
        return measured >= expected, f"quoted as at least {claim['expected']}"
    if isinstance(tol, dict) and "rel" in tol:
        return (abs(measured - expected) <= tol["rel"] * abs(expected),
                f"quoted {claim['expected']} ± {100 * tol['rel']:g} %")
    if isinstance(tol, dict) and "abs" in tol:
        return (abs(measured - expected) <= tol["abs"],
                f"quoted {claim['expected']} ± {tol['abs']:g}")
    raise ValueError(f"claim {claim['number']}: unknown tolerance {tol!r}")


# --- runs --------------------------------------------------------------------------

class Run:
    """One run of a scene: its RESULT lines, screen output and statistics table."""

    def __init__(self, key):
        self.key = key
        self.results, self.stdout, self.statistics = {}, "", None
        self.error, self.seconds, self.directory = None, 0.0, None


def run_scene(binary, key, workroot):
    prm, settings = key
    run = Run(key)
    try:
        with open(os.path.join(ROOT, prm), encoding="utf-8") as f:
            text = f.read()
    except OSError as e:
        run.error = f"cannot read {prm}: {e.strerror}"
        return run
    for setting in settings:
        path, _, value = setting.partition("=")
        text = set_path(text, path, value)
    # The copy runs elsewhere: a relative include names a file beside the scene.
    scene_dir = os.path.dirname(os.path.join(ROOT, prm))
    text = re.sub(r"^(\s*include\s+)(?!/)(\S.*)$",
                  lambda m: m.group(1) + os.path.join(scene_dir, m.group(2)), text, flags=re.M)
    work = tempfile.mkdtemp(prefix="run-", dir=workroot)
    run.directory = work
    with open(os.path.join(work, "scene.prm"), "w", encoding="utf-8") as f:
        f.write(text)
    # Open MPI's session directory per run: parallel runs must not race for one.
    env = dict(os.environ, TMPDIR=work)
    start = time.monotonic()
    try:
        out = subprocess.run([binary, "scene.prm"], cwd=work, env=env, capture_output=True,
                             text=True, timeout=RUN_TIMEOUT)
    except subprocess.TimeoutExpired:
        run.error = f"no result within {RUN_TIMEOUT} s"
        return run
    except OSError as e:
        run.error = f"cannot run {binary}: {e.strerror}"
        return run
    run.seconds = time.monotonic() - start
    run.stdout = out.stdout
    if out.returncode != 0:
        last = (out.stderr.strip() or out.stdout.strip() or "no output").splitlines()[-1]
        run.error = f"exit code {out.returncode}: {last}"
        return run
    for m in re.finditer(r"^RESULT (.+?) = (\S+)\s*$", out.stdout, re.M):
        try:
            run.results[m.group(1)] = float(m.group(2))
        except ValueError:
            pass
    directory = get_path(text, "Output/Directory", "output")
    name = get_path(text, "Output/Statistics file", "statistics.txt")
    path = os.path.join(work, directory, name)
    try:
        with open(path) as f:
            rows = [line.split() for line in f if line.strip() and not line.startswith("#")]
        run.statistics = (rows[0], [[float(v) for v in r] for r in rows[1:]])
    except (OSError, IndexError, ValueError):
        run.statistics = None
    return run


def statistic(run, column, row):
    if run.statistics is None:
        raise KeyError("the run wrote no statistics table")
    header, rows = run.statistics
    if column not in header:
        raise KeyError(f"no statistics column '{column}'")
    c = header.index(column)
    by_step = {int(r[0]): r[c] for r in rows}
    if row == "last":
        return rows[-1][c]
    if re.fullmatch(r"\d+", row):
        if int(row) not in by_step:
            raise KeyError(f"no statistics row of step {row}")
        return by_step[int(row)]
    m = re.fullmatch(r"(min|max|sum|mean)(?:@(\d*):(\d*))?", row)
    if not m:
        raise KeyError(f"statistics row '{row}': a step, 'last' or min/max/sum/mean[@a:b]")
    first = int(m.group(2)) if m.group(2) else None
    end = int(m.group(3)) if m.group(3) else None
    values = [v for step, v in sorted(by_step.items())
              if (first is None or step >= first) and (end is None or step < end)]
    if not values:
        raise KeyError(f"no statistics rows in '{row}'")
    return {"min": min, "max": max, "sum": sum,
            "mean": lambda v: sum(v) / len(v)}[m.group(1)](values)


def ctest_count(build_dir, label, workroot):
    """The number of tests ctest lists, read from a copy of the build tree's
    CTestTestfile.cmake files (ctest -N writes a log; the build stays untouched)."""
    copy = tempfile.mkdtemp(prefix="ctest-", dir=workroot)
    for directory, _, files in os.walk(build_dir):
        if "CTestTestfile.cmake" in files:
            target = os.path.join(copy, os.path.relpath(directory, build_dir))
            os.makedirs(target, exist_ok=True)
            shutil.copy(os.path.join(directory, "CTestTestfile.cmake"), target)
    command = ["ctest", "-N"] + (["-L", label] if label else [])
    out = subprocess.run(command, cwd=copy, capture_output=True, text=True)
    m = re.search(r"Total Tests:\s*(\d+)", out.stdout)
    if not m:
        raise KeyError("ctest -N printed no 'Total Tests'")
    return float(m.group(1))


def measure(claim, runs, build_dir, workroot):
    """The measured value of a claim; KeyError with the reason if there is none,
    None if the claim is skipped."""
    result = claim["result"]
    if isinstance(result, str) and result.startswith("ctest:"):
        if not build_dir:
            return None
        return ctest_count(build_dir, result[len("ctest:"):], workroot)
    run = runs[run_key(claim)]
    if run.error:
        raise KeyError(run.error)
    if isinstance(result, list):
        missing = [r for r in result if r not in run.results]
        if missing:
            raise KeyError(f"no RESULT line '{missing[0]}'")
        return sum(run.results[r] for r in result)
    if result.startswith("statistics:"):
        _, column, row = result.split(":", 2)
        return statistic(run, column, row)
    if result.startswith("stdout:"):
        m = re.search(result[len("stdout:"):], run.stdout, re.M)
        if not m:
            raise KeyError(f"no match of /{result[len('stdout:'):]}/ in the output")
        return float(m.group(1))
    if result not in run.results:
        raise KeyError(f"no RESULT line '{result}'")
    return run.results[result]


# --- output --------------------------------------------------------------------------

def short(text, width=64):
    text = normalise(text)
    return text if len(text) <= width else text[: width - 1] + "…"


def describe_run(claim):
    if run_key(claim) is None:
        return "ctest -N" + (f" -L {claim['result'][6:]}" if claim["result"][6:] else "")
    settings = "; ".join(claim["set"])
    return claim["prm"] + (f" [{settings}]" if settings else "")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", default=DEFAULT_BINARY,
                        help="contact-stefan launcher (default: build/contact-stefan)")
    parser.add_argument("--claims", default=DEFAULT_CLAIMS, help="the claims table (JSON)")
    parser.add_argument("--only", metavar="FILE", action="append",
                        help="only the claims of this document (repeatable)")
    parser.add_argument("--list", action="store_true", help="print the claims, run nothing")
    parser.add_argument("--jobs", type=int, default=2, help="runs at a time (default 2)")
    parser.add_argument("--build-dir", help="check 'ctest:' claims against this build tree")
    parser.add_argument("--keep", action="store_true", help="keep the runs' work directories")
    args = parser.parse_args()
    print(provenance_line(args.binary), flush=True)

    claims = load_claims(args.claims)
    if args.only:
        wanted = {os.path.normpath(f) for f in args.only}
        claims = [c for c in claims if os.path.normpath(c["file"]) in wanted
                  or os.path.basename(c["file"]) in wanted]
        if not claims:
            sys.exit(f"check_claims.py: no claims for {', '.join(args.only)}")

    if args.list:
        for c in claims:
            what = c["result"] if isinstance(c["result"], str) else " + ".join(c["result"])
            where = describe_run(c)
            tol = c["tolerance"]
            tol = tol if isinstance(tol, str) else ", ".join(f"{k} {v:g}" for k, v in tol.items())
            print(f"{c['file']}: \"{short(c['text'])}\"\n    {what} = {c['expected']} ({tol})"
                  f"  <- {where}")
        print(f"{len(claims)} claims, {len({run_key(c) for c in claims} - {None})} runs")
        return 0

    binary = os.path.abspath(args.binary)
    if not os.access(binary, os.X_OK):
        sys.exit(f"check_claims.py: no executable {binary} (build first, or --binary)")
    version = subprocess.run([binary, "--version"], capture_output=True, text=True).stdout.strip()
    print(f"binary: {binary}\n        {version}")

    start = time.monotonic()
    workroot = tempfile.mkdtemp(prefix="check-claims-")
    try:
        keys = sorted({run_key(c) for c in claims} - {None})
        runs = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            for run in pool.map(lambda k: run_scene(binary, k, workroot), keys):
                runs[run.key] = run

        documents, failed, skipped = {}, 0, 0
        for c in claims:
            if c["file"] not in documents:
                try:
                    with open(os.path.join(ROOT, c["file"]), encoding="utf-8") as f:
                        documents[c["file"]] = f.read()
                except OSError:
                    documents[c["file"]] = None
            document = documents[c["file"]]
            line = locate(document, c["text"]) if document is not None else None
            where = f"{c['file']}:{line}" if line else c["file"]
            text = f"\"{short(c['text'])}\""
            if line is None:
                failed += 1
                print(f"FAIL {where} {text}: the passage is not in the document "
                      f"(update benchmarks/claims.json with the document)")
                continue
            try:
                measured = measure(c, runs, args.build_dir, workroot)
            except KeyError as e:
                failed += 1
                print(f"FAIL {where} {text}: {e.args[0]} ({describe_run(c)})")
                continue
            if measured is None:
                skipped += 1
                print(f"SKIP {where} {text}: needs --build-dir")
                continue
            ok, tolerance = compare(measured, c)
            failed += not ok
            print(f"{'PASS' if ok else 'FAIL'} {where} {text}: measured {measured:.10g}, "
                  f"{tolerance}"
                  + ("" if ok else f"\n     from {describe_run(c)}: {c['result']}"))
        seconds = time.monotonic() - start
        print(f"{len(claims)} claims: {len(claims) - failed - skipped} passed, {failed} failed"
              + (f", {skipped} skipped" if skipped else "")
              + f"; {len(keys)} runs, {seconds:.1f} s")
        if args.keep:
            print(f"work directories kept in {workroot}")
    finally:
        if not args.keep:
            shutil.rmtree(workroot, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
