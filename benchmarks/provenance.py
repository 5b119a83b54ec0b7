"""The line every benchmark script prints first: what produced its numbers.

    # run: contact-stefan <commit> <date>[, with uncommitted changes] (<compiler>,
    #      <build type>, deal.II <version>); host <name>, <CPU model>, <n> cores;
    #      2026-11-26 05:40 UTC

Issue 32: every number quoted in README.md and doc/ names the machine, commit and
date of the run that produced it; a table pasted from a script's output carries
this line with it. Only the standard library is needed.
"""
import datetime
import os
import platform
import subprocess


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def provenance_line(binary):
    """'# run: <version>; host ...; <UTC date>' for the binary that is measured."""
    try:
        version = subprocess.run([binary, "--version"], capture_output=True, text=True,
                                 timeout=30).stdout.strip() or "unknown version"
    except (OSError, subprocess.SubprocessError):
        version = "unknown version (%s did not answer --version)" % binary
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    return "# run: %s; host %s, %s, %d cores; %s" % (version, platform.node(), cpu_model(),
                                                      os.cpu_count() or 0, now)
