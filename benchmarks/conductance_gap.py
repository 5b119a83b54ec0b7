#!/usr/bin/env python3
"""Closed form of benchmark I3 (doc/benchmarks.md): steady conduction through
two slabs separated by a prescribed gap g that conducts by gas and radiation.

Slab 0 (0 < y < L0, conductivity k0) is held at T_hot at y = 0, slab 1
(L0 < y < L0 + L1, k1) at T_cold at the top. The flux q through the stack
is the same in both slabs and across the gap:

    q = k0 (T_hot - T1) / L0 = k1 (T2 - T_cold) / L1
      = k_gas / (g + g_min) (T1 - T2) + sigma eps (T1^4 - T2^4),
    eps = 1 / (1/eps_k + 1/eps_l - 1),

with T1, T2 the temperatures of the two faces of the gap (kelvin). The
residual is monotone in T1, so bisection finds it to the last bit. Prints q,
T1, T2 and the piecewise-linear exact temperature as a muparser expression
for 'Exact solution/Function'. Standard library only.

    benchmarks/conductance_gap.py            # the numbers of the scene
"""
import sys

SIGMA = 5.670374419e-8  # W/(m^2 K^4), CODATA 2018 (exact)

# The scene tests/scenes/conductance_gap.prm.
K0, L0, K1, L1 = 200.0, 1.0, 100.0, 2.0
T_HOT, T_COLD = 1200.0, 300.0
K_GAS, GAP, G_MIN = 0.05, 1e-2, 1e-6
EPS_K, EPS_L = 0.8, 0.6


def solve():
    eps = 1.0 / (1.0 / EPS_K + 1.0 / EPS_L - 1.0)
    h_gas = K_GAS / (GAP + G_MIN)

    def residual(t1):
        q = K0 * (T_HOT - t1) / L0
        t2 = T_COLD + q * L1 / K1
        return q - (h_gas * (t1 - t2) + SIGMA * eps * (t1 ** 4 - t2 ** 4))

    lo, hi = T_COLD, T_HOT  # residual(lo) > 0 > residual(hi)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if residual(mid) > 0:
            lo = mid
        else:
            hi = mid
    t1 = 0.5 * (lo + hi)
    q = K0 * (T_HOT - t1) / L0
    t2 = T_COLD + q * L1 / K1
    return q, t1, t2


def main():
    q, t1, t2 = solve()
    print(f"q  = {q!r} W/m^2")
    print(f"T1 = {t1!r} K (side 0 of the gap)")
    print(f"T2 = {t2!r} K (side 1 of the gap)")
    eps = 1.0 / (1.0 / EPS_K + 1.0 / EPS_L - 1.0)
    print(f"q_gas       = {K_GAS / (GAP + G_MIN) * (t1 - t2)!r} W/m^2")
    print(f"q_radiation = {SIGMA * eps * (t1 ** 4 - t2 ** 4)!r} W/m^2")
    print("Exact solution/Function =",
          f"y < {L0!r} ? {T_HOT!r} - {q!r}*y/{K0!r} : {T_COLD!r} + {q!r}*({L0 + L1!r} - y)/{K1!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
