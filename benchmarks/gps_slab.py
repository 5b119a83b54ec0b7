#!/usr/bin/python3
"""The freezing slab of doc/benchmarks.md B1 in generalized plane strain: the
semi-analytic solution, its muparser form for the scene, and a check.

The slab of tests/scenes/birth_freezing_slab.prm (a melt at 1 frozen from the
wall y = 0 held at -1, S1's Neumann problem mirrored: Theta_m = 0, front
s(t) = 2 lambda sqrt t; held laterally, e_xx = 0; sigma_yy = 0) with the
out-of-plane direction free: e_zz = e(t) uniform, no net out-of-plane force.
Every point is born stress-free at Theta_m with the e_zz of its birth, so a
crust point at y carries r(y) = e(t_b(y)), t_b = (y / (2 lambda))^2, and a melt
point the melt's reference (e_zz = 0 at Theta_m). With sigma_yy = 0 and one
Poisson ratio, E' = E / (1 - nu^2) and k = (1 + nu) alpha,

    sigma_zz = E' (e(t) - r(y) - k Theta),   sigma_xx = E' (nu (e(t) - r(y)) - k Theta),

and int_0^Y sigma_zz dy = 0 is a Volterra equation for e(t) (p = sqrt t):

    e(t) (E_s s + E_l (Y - s)) = E_s 2 lambda int_0^p e(q^2) dq
                                 + k (E_s int_0^s Theta dy + E_l int_s^Y Theta dy),

with e(0) = k (the melt at Theta = 1 referenced to Theta_m). The Theta
integrals are closed forms (int erf = x erf x + (e^{-x^2} - 1)/sqrt pi); the
e-integral is marched with the trapezoidal rule in p (second order; 20000
steps, checked against 40000). e(p) is then interpolated by a polynomial in
x = 2p - 1 at Chebyshev points and written in Horner form, the one thing
muparser can evaluate: the scene's 'Exact solution/Stress'.

Only the Python standard library (the test suite runs it):

    /usr/bin/python3 benchmarks/gps_slab.py              # the numbers and the expression
    /usr/bin/python3 benchmarks/gps_slab.py --check FILE # FILE's Stress is this one
    /usr/bin/python3 benchmarks/gps_slab.py --plot doc/figures/birth_freezing_slab_gps.png
        [--binary build/contact-stefan]   # runs levels 0-2, plots sigma_zz (needs
                                          # python3-matplotlib and python3-meshio)
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SCENE = os.path.join(ROOT, "tests", "scenes", "birth_freezing_slab_gps.prm")
sys.path.insert(0, HERE)
# The slab's data and the mirrored case A's lambda, as in the plane-strain B1.
from birth_slab import ALPHA, E_L, E_S, NU, neumann_lambda  # noqa: E402

Y = 8.0  # the slab's length (the far end held at Theta = 1)
K = (1 + NU) * ALPHA
DEGREE = 24
LAMBDA = neumann_lambda()


def integral_erf(x):
    return x * math.erf(x) + (math.exp(-x * x) - 1) / math.sqrt(math.pi)


def theta_integrals(t):
    """(int_0^s Theta dy, int_s^Y Theta dy) of the Neumann profile."""
    s, c = 2 * LAMBDA * math.sqrt(t), 2 * math.sqrt(t)
    crust = -s + c * integral_erf(LAMBDA) / math.erf(LAMBDA)
    erfc_integral = lambda x: x - integral_erf(x)  # noqa: E731
    melt = (Y - s) - c * (erfc_integral(Y / c) - erfc_integral(LAMBDA)) / math.erfc(LAMBDA)
    return crust, melt


def march(n):
    """e at p = j/n, j = 0..n (p = sqrt t)."""
    h, e, integral = 1.0 / n, [K], 0.0
    for j in range(1, n + 1):
        p = j * h
        s = 2 * LAMBDA * p
        crust, melt = theta_integrals(p * p)
        base = integral + 0.5 * h * e[-1]
        value = (K * (E_S * crust + E_L * melt) + E_S * 2 * LAMBDA * base) / (
            E_S * s + E_L * (Y - s) - E_S * LAMBDA * h)
        integral = base + 0.5 * h * value
        e.append(value)
    return e


def interpolate(values, p):
    n = len(values) - 1
    x = p * n
    j = min(int(x), n - 1)
    w = x - j
    return (1 - w) * values[j] + w * values[j + 1]


def monomial_coefficients(values):
    """Coefficients in x = 2p - 1 of the Chebyshev interpolant of degree DEGREE."""
    m = DEGREE + 1
    nodes = [math.cos(math.pi * (i + 0.5) / m) for i in range(m)]
    f = [interpolate(values, 0.5 * (x + 1)) for x in nodes]
    cheb = [(2.0 if k else 1.0) / m * sum(f[i] * math.cos(math.pi * k * (i + 0.5) / m)
                                           for i in range(m)) for k in range(m)]
    # T_k as monomials: T_0 = 1, T_1 = x, T_{k+1} = 2x T_k - T_{k-1}.
    t_prev, t_cur, coeffs = [1.0], [0.0, 1.0], [0.0] * m
    coeffs[0] += cheb[0]
    for k in range(1, m):
        for i, c in enumerate(t_cur):
            coeffs[i] += cheb[k] * c
        t_next = [0.0] + [2 * c for c in t_cur]
        for i, c in enumerate(t_prev):
            t_next[i] -= c
        t_prev, t_cur = t_cur, t_next
    return coeffs


def horner(coeffs, x):
    text = "%.17g" % coeffs[-1]
    for c in reversed(coeffs[:-1]):
        text = "(%s) * (%s) + %.17g" % (text, x, c)
    return text


def evaluate(coeffs, x):
    value = 0.0
    for c in reversed(coeffs):
        value = value * x + c
    return value


def stress_expression(coeffs):
    lam = "%.10f" % LAMBDA
    eta = "y / (2 * sqrt(t))"
    e_now = horner(coeffs, "2 * sqrt(t) - 1")
    r_crust = horner(coeffs, "y / %s - 1" % lam)
    theta_crust = "(-1 + (1 - erfc(%s)) / (1 - erfc(%s)))" % (eta, lam)
    theta_melt = "(1 - erfc(%s) / erfc(%s))" % (eta, lam)
    crust = "y < 2 * %s * sqrt(t)" % lam
    e_s, e_l = E_S / (1 - NU * NU), E_L / (1 - NU * NU)
    sxx = "if(%s, %.17g * (%g * ((%s) - (%s)) - %g * %s), %.17g * (%g * (%s) - %g * %s))" % (
        crust, e_s, NU, e_now, r_crust, K, theta_crust, e_l, NU, e_now, K, theta_melt)
    szz = "if(%s, %.17g * ((%s) - (%s) - %g * %s), %.17g * ((%s) - %g * %s))" % (
        crust, e_s, e_now, r_crust, K, theta_crust, e_l, e_now, K, theta_melt)
    return "%s; 0; 0; %s" % (sxx, szz)


def solution():
    fine, finer = march(20000), march(40000)
    coeffs = monomial_coefficients(fine)
    march_error = max(abs(fine[j] - finer[2 * j]) for j in range(0, 20001, 50))
    fit_error = max(abs(evaluate(coeffs, 2 * j / 20000 - 1) - fine[j]) for j in range(20001))
    return fine, coeffs, march_error, fit_error


def exact_sigma_zz(values, y, t=1.0):
    """sigma_zz of the semi-analytic solution at y (values: e on the p grid)."""
    eta = y / (2 * math.sqrt(t))
    e_now = interpolate(values, math.sqrt(t))
    if y < 2 * LAMBDA * math.sqrt(t):
        theta = -1 + math.erf(eta) / math.erf(LAMBDA)
        r = interpolate(values, y / (2 * LAMBDA))
        return E_S / (1 - NU * NU) * (e_now - r - K * theta)
    theta = 1 - math.erfc(eta) / math.erfc(LAMBDA)
    return E_L / (1 - NU * NU) * (e_now - K * theta)


def plot(values, binary, path):
    sys.path.insert(0, HERE)
    from ladder import set_path  # noqa: E402
    from plot_run import plt, read_pvd  # noqa: E402
    import meshio  # noqa: E402
    import xml.etree.ElementTree as ET  # noqa: E402
    fig, ax = plt.subplots(figsize=(7, 4.2))
    ys = [1.4 * i / 600 for i in range(601)]
    ax.plot(ys, [exact_sigma_zz(values, y) for y in ys], "k-", lw=1.5,
            label="semi-analytic (born at $\\Theta_m$ with its $e_{zz}$)")
    tmp = tempfile.mkdtemp(prefix="gps-slab-")
    for level, style in zip(range(3), ["o", "s", "^"]):
        text = open(SCENE).read()
        for key, value in {"Mesh refinement/Initial global refinements": str(level),
                           "Time stepping/Time step": repr(0.125 / 2**level),
                           "Output/VTU interval": "100000",
                           "Output/Directory": "output"}.items():
            text = set_path(text, key, value)
        workdir = os.path.join(tmp, "level%d" % level)
        os.makedirs(workdir)
        with open(os.path.join(workdir, "scene.prm"), "w") as f:
            f.write(text)
        out = subprocess.run([binary, "scene.prm"], cwd=workdir, capture_output=True, text=True)
        if out.returncode != 0:
            sys.exit("level %d failed:\n%s" % (level, out.stderr))
        directory = os.path.join(workdir, "output")
        last = read_pvd(os.path.join(directory, "solution.pvd"))[-1][1]
        points = []
        for piece in ET.parse(os.path.join(directory, last)).getroot().iter("Piece"):
            m = meshio.read(os.path.join(directory, piece.get("Source")))
            # Cell data are written as constant point data on each cell's own vertices.
            for quad in m.cells_dict["quad"]:
                y = m.points[quad, 1].mean()
                if y < 1.4:
                    points.append((y, m.point_data["cell_stress_zz"][quad[0]]))
        points.sort()
        ax.plot([p[0] for p in points], [p[1] for p in points], style, ms=3.5, mfc="none",
                label="level %d (%d cells)" % (level, 32 * 4**level))
    ax.axvline(2 * LAMBDA, color="0.6", ls=":", lw=1)
    ax.set_xlabel("distance from the cold wall y")
    ax.set_ylabel("$\\sigma_{zz}$ at the cell centres, t = 1")
    ax.set_title("Freezing slab, generalized plane strain: residual stress of the births")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    print("wrote", path)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", metavar="FILE",
                        help="fail unless FILE's 'Stress' entry is this expression")
    parser.add_argument("--plot", metavar="PNG", help="run levels 0-2 and plot sigma_zz")
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "contact-stefan"))
    args = parser.parse_args()
    values, coeffs, march_error, fit_error = solution()
    scale = max(abs(v) for v in values)
    print("lambda = %.10f" % LAMBDA)
    print("e(t): t = 0: %.10e, 1/4: %.10e, 1: %.10e" % (values[0], values[10000], values[-1]))
    print("march error (20000 vs 40000 steps) %.2e, interpolation error %.2e (of max |e| %.2e)"
          % (march_error, fit_error, scale))
    if march_error > 1e-6 * scale or fit_error > 1e-6 * scale:
        sys.exit("the semi-analytic solution is not accurate to 1e-6")
    expression = stress_expression(coeffs)
    if args.plot:
        plot(values, args.binary, args.plot)
        return
    if args.check:
        text = open(args.check).read()
        m = re.search(r"^\s*set Stress\s*=\s*(.+)$", text, re.M)
        if not m:
            sys.exit("%s has no 'set Stress' line" % args.check)
        theirs = [float(x) for x in re.findall(r"[-+]?\d+\.\d+(?:e[-+]?\d+)?", m.group(1))]
        ours = [float(x) for x in re.findall(r"[-+]?\d+\.\d+(?:e[-+]?\d+)?", expression)]
        if len(theirs) != len(ours) or any(abs(a - b) > 1e-12 * max(1.0, abs(b))
                                           for a, b in zip(theirs, ours)):
            sys.exit("%s: its 'Stress' is not the semi-analytic solution of "
                     "benchmarks/gps_slab.py (run it and paste the expression)" % args.check)
        print("%s: Stress is the semi-analytic solution (%d numbers agree)"
              % (args.check, len(ours)))
        return
    print("set Stress = " + expression)


if __name__ == "__main__":
    main()
