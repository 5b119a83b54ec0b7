#!/usr/bin/python3
"""h -> infinity (doc/interface_heat.md, benchmark I2 of doc/benchmarks.md): the
transient of tests/scenes/conductance_transient.prm (heat through an interface
into a melting body) with a growing constant conductance h, against the same
scene in perfect thermal contact on the same mesh and steps. Prints, per h,
the difference of the melt area at the end (a functional of the whole
temperature history) from the perfect-contact run, its ratio to the last h's
and the observed rate in 1/h, and the wall time (one run each, the same
machine; compare ratios). Standard library only.

    benchmarks/conductance_limit.py [BUILD_DIR]
"""
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SCENE = os.path.join(ROOT, "tests/scenes/conductance_transient.prm")


def run(binary, work, name, settings):
    scene = os.path.join(work, name + ".prm")
    shutil.copy(SCENE, scene)
    subprocess.run([os.path.join(ROOT, "tests/apply_settings.sh"), scene,
                    "SET:Output/Directory=" + name, "SET:Time stepping/End time=0.5"] + settings,
                   check=True, stdout=subprocess.DEVNULL)
    start = time.time()
    out = subprocess.run([binary, scene], cwd=work, check=True, capture_output=True,
                         text=True).stdout
    elapsed = time.time() - start
    area = float(re.search(r"^RESULT melt area = (\S+)", out, re.M).group(1))
    return area, elapsed


def main():
    build = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build")
    binary = os.path.abspath(os.path.join(build, "contact-stefan"))
    with tempfile.TemporaryDirectory() as work:
        perfect, t_perfect = run(binary, work, "perfect",
                                 ["SET:Contact/Interface 0-1/Thermal contact=perfect"])
        print(f"perfect contact: melt area {perfect:.10f} m^2, {t_perfect:.2f} s")
        print("          h  |area - perfect|   ratio   rate in 1/h   wall [s]")
        last = None
        for h in [1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7]:
            area, elapsed = run(binary, work, f"h{h:g}",
                                [f"SET:Contact/Interface 0-1/Conductance/Constant={h:g}"])
            diff = abs(area - perfect)
            ratio = last / diff if last and diff > 0 else float("nan")
            rate = math.log10(ratio) if ratio == ratio else float("nan")
            print(f"{h:11.0e}  {diff:15.3e}  {ratio:7.2f}  {rate:12.3f}  {elapsed:9.2f}")
            last = diff
    return 0


if __name__ == "__main__":
    sys.exit(main())
