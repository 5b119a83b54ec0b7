#!/usr/bin/python3
"""An independent 1D reference for benchmark I5 (doc/benchmarks.md): freezing
against a mould whose contact conductance depends on the phase of the metal at
the wall (tests/scenes/conductance_phase.prm).

Body 0, the mould (0 < y < 1; k = 1, rho c = 1, no phase change), is held at
-1 at y = 0; body 1, the metal (1 < y < 2; k = 1, c = 1 in both phases,
melting at 0 with latent heat 1), starts liquid at 0.5 and is insulated at
y = 2. Between them the phase-aware contact conductance

    h = (1 - f) h_s + f h_L,  h_s = 2, h_L = 20,

with f the liquid fraction of the metal at the wall (the larger of the two
sides'; the mould has none). The wall freezes, and h drops from 20 to 2.

The method is not the program's: explicit Euler in time on a uniform
finite-volume grid in space (nodes at the ends and on both sides of the
interface, the interface flux h (T_0 - T_1) between the two wall nodes), with
the enthalpy as unknown, run on grids of 50 to 800 cells per body with the
time step at 0.4 of the stability limit. Prints the heat that crossed the
interface and the melt area at t = 0.5 on each grid and the differences
between successive grids (first order in the mesh width, from the wall node's
mass), and the Richardson extrapolation of the two finest. Needs numpy
(Debian's /usr/bin/python3 has it).

    benchmarks/conductance_phase_reference.py              # the reference (minutes)
    benchmarks/conductance_phase_reference.py --program BUILD_DIR
        # the program on 32 to 256 cells per body (tau = 0.032/N) against the
        # reference the first form printed (REFERENCE below)
"""
import os
import re
import shutil
import subprocess
import tempfile
import sys

import numpy as np

K, C, LATENT = 1.0, 1.0, 1.0
H_S, H_L = 2.0, 20.0
T_COLD, T_METAL, T_END = -1.0, 0.5, 0.5
# What the reference mode printed (Richardson of 400 and 800 cells per body).
REFERENCE = (-0.487805278553, 0.910735313234)
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def temperature(h, melting):
    """T(H): the metal's law where melting, the mould's (H = c T) elsewhere."""
    t = h / C
    t = np.where(melting & (h >= 0) & (h <= LATENT), 0.0, t)
    return np.where(melting & (h > LATENT), (h - LATENT) / C, t)


def solve(n):
    """n cells per body; returns (heat crossed from mould to metal, melt area)."""
    dx = 1.0 / n
    # Nodes 0..n: the mould (node 0 held at T_COLD); n+1..2n+1: the metal.
    mass = np.full(2 * n + 2, dx)
    mass[[0, n, n + 1, 2 * n + 1]] = dx / 2
    melting = np.arange(2 * n + 2) > n
    h = np.where(melting, LATENT + C * T_METAL, C * T_COLD)
    dt = 0.4 * (dx / 2) / (2 * K / dx + H_L) / 2
    steps = int(np.ceil(T_END / dt))
    dt = T_END / steps
    crossed = 0.0
    for _ in range(steps):
        t = temperature(h, melting)
        flux = np.zeros(2 * n + 2)
        inner = K * (t[1:] - t[:-1]) / dx  # between neighbours
        inner[n] = 0.0  # (no conduction across the interface: the conductance below)
        flux[:-1] += inner
        flux[1:] -= inner
        f = min(max(h[n + 1] / LATENT, 0.0), 1.0)
        q = ((1 - f) * H_S + f * H_L) * (t[n] - t[n + 1])  # mould -> metal
        flux[n] -= q
        flux[n + 1] += q
        flux[0] = 0.0  # held
        h += dt * flux / mass
        crossed += dt * q
    f = np.clip(h[melting] / LATENT, 0.0, 1.0)
    area = float(np.sum(mass[melting] * f))
    return crossed, area


def program(build):
    """The scene at N cells per body (a strip 1/N wide), per unit width."""
    binary = os.path.abspath(os.path.join(build, "contact-stefan"))
    print("cells/body  heat crossed  error      melt area  error      wall [s]")
    with tempfile.TemporaryDirectory() as work:
        for n in [32, 64, 128, 256]:
            scene = os.path.join(work, f"n{n}.prm")
            shutil.copy(os.path.join(ROOT, "tests/scenes/conductance_phase.prm"), scene)
            subprocess.run([os.path.join(ROOT, "tests/apply_settings.sh"), scene,
                            f"SET:Geometry/Upper right corner={1 / n!r}, 2",
                            f"SET:Geometry/Subdivisions=1, {2 * n}",
                            f"SET:Time stepping/Time step={0.032 / n!r}",
                            f"SET:Output/Directory=out{n}"], check=True,
                           stdout=subprocess.DEVNULL)
            out = subprocess.run([binary, scene], cwd=work, check=True, capture_output=True,
                                 text=True).stdout
            value = lambda name: float(re.search(r"^RESULT " + name + r" = (\S+)", out,
                                                 re.M).group(1))
            crossed = value("heat crossed interface 0-1") * n
            area = value("melt area") * n
            print(f"{n:10d}  {crossed:12.6f}  {crossed - REFERENCE[0]:9.2e}  {area:9.6f}"
                  f"  {area - REFERENCE[1]:9.2e}  {value('wall time'):8.2f}")
    return 0


def main():
    if len(sys.argv) > 2 and sys.argv[1] == "--program":
        return program(sys.argv[2])
    print("cells/body   heat crossed (J/m)    melt area (m^2)    differences")
    last, results = None, []
    for n in [50, 100, 200, 400, 800]:
        crossed, area = solve(n)
        results.append((crossed, area))
        diff = "" if last is None else f"{crossed - last[0]:11.3e} {area - last[1]:11.3e}"
        print(f"{n:10d}  {crossed:19.12f}  {area:17.12f}    {diff}")
        last = (crossed, area)
    (c1, a1), (c2, a2) = results[-2], results[-1]
    print(f"Richardson (first order): heat crossed {2 * c2 - c1:.10f} J/m, "
          f"melt area {2 * a2 - a1:.10f} m^2")
    return 0


if __name__ == "__main__":
    sys.exit(main())
