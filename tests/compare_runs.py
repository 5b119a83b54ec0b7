"""Shared by tests/compare_acceleration.py, tests/compare_mortar.py and
tests/compare_mortar_casting.py: run a scene and read its RESULT lines and
statistics table, compare two runs column by column and RESULT line by RESULT
line, and report."""
import os
import subprocess
import sys


def run_scene(binary, text, directory, np, what):
    """Writes text as directory/scene.prm and runs it on np ranks (its
    Output/Directory must be directory/output). Returns (RESULT lines by name,
    statistics columns by name, stdout); exits naming `what` if the run fails."""
    os.makedirs(directory)
    scene = os.path.join(directory, "scene.prm")
    with open(scene, "w") as f:
        f.write(text)
    command = [binary, scene]
    if np > 1:
        command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(np)] + command
    result = subprocess.run(command, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit("the %s run failed (exit %d): %s"
                 % (what, result.returncode, result.stderr.strip()[-300:]))
    results = {}
    for line in result.stdout.splitlines():
        if line.startswith("RESULT ") and " = " in line:
            name, value = line[len("RESULT "):].rsplit(" = ", 1)
            results[name] = value.strip()
    with open(os.path.join(directory, "output", "statistics.txt")) as f:
        lines = [l.split() for l in f if not l.startswith("#")]
    columns = {name: [float(row[k]) for row in lines[1:]] for k, name in enumerate(lines[0])}
    return results, columns, result.stdout


def compare(a, b, tolerance, work, names, missing_results_fail, absolute=0.0):
    """Compares runs a and b ((results, columns, ...) of run_scene): every
    statistics column not matching the regex `work` (nor step, time) at every
    step within tolerance of the column's largest value (plus `absolute`),
    and every numeric RESULT line within tolerance relative (plus
    `absolute`). A RESULT line of a
    missing from b fails only if missing_results_fail. Returns (number
    compared, failures)."""
    failures, compared = [], 0
    for name, values in a[1].items():
        if work.search(name) or name in ("step", "time"):
            continue
        other = b[1].get(name)
        if other is None or len(other) != len(values):
            failures.append("column %s: missing or of another length in the %s run"
                            % (name, names[1]))
            continue
        scale = max(abs(v) for v in values) or 1.0
        worst = max(abs(x - y) for x, y in zip(values, other)) / scale
        compared += 1
        if not worst <= tolerance + absolute / scale:
            failures.append("column %s differs by %.3g of its largest value" % (name, worst))
    for name, value in a[0].items():
        if work.search(name):
            continue
        if name not in b[0]:
            if missing_results_fail:
                failures.append("RESULT %s: missing in the %s run" % (name, names[1]))
            continue
        try:
            x, y = float(value), float(b[0][name])
        except ValueError:
            continue
        compared += 1
        if not abs(x - y) <= tolerance * max(abs(x), abs(y), 1e-300) + absolute:
            failures.append("RESULT %s: %s (%s) against %s (%s)"
                            % (name, value, names[0], b[0][name], names[1]))
    return compared, failures


def report(summary, failures):
    """Prints the summary line and one line per failure; the exit status."""
    print(summary)
    for failure in failures:
        print("FAILED: " + failure)
    return 1 if failures else 0
