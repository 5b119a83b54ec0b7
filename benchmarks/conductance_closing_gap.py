#!/usr/bin/env python3
"""Closed form of benchmark I4 (doc/benchmarks.md): a gap that thermal expansion
closes, with the conductance following it (tests/scenes/conductance_closing_gap.prm).

Two slabs of one material, held laterally (rollers: plane strain with
e_xx = e_zz = 0), body 0 (0 < y < L0) clamped at its base, body 1
(L0 < y < L0 + L1) clamped at its top, an initial gap g0 between them. The base
is held at T_hot, the top at T_cold = Theta_0 (stress-free). Steady state: the
temperature is linear in each slab, the flux q the same in both and across the
interface, q = h (T1 - T2). Body 0 expands by

    delta = c alpha L0 ((T_hot + T1)/2 - Theta_0),   c = (1 + nu)/(1 - nu),

(body 1 has alpha = 0). Open (delta < g0): the gap is g = g0 - delta and
h = k_gas / (g + g_min). Closed: both slabs are compressed by the uniform stress
p = (delta - g0) / (L0/M + L1/M), M = E (1 - nu) / ((1 + nu)(1 - 2 nu)), and
h = h_c0 + C (p/H)^m + k_gas / g_min. Either way one scalar equation in T1,
monotone, solved by bisection. Standard library only.

    benchmarks/conductance_closing_gap.py [T_HOT]    # default: both cases of the tests
"""
import sys

# The scene's data.
L0, L1, K = 1.0, 1.0, 50.0
E, NU, ALPHA = 1e9, 0.25, 1e-5
G0, K_GAS, G_MIN = 3e-3, 0.05, 1e-4
H_C0, C, HARDNESS, M_EXP = 100.0, 1000.0, 1e6, 1.0
T_COLD = THETA_0 = 0.0


def solve(t_hot):
    c = (1 + NU) / (1 - NU)
    modulus = E * (1 - NU) / ((1 + NU) * (1 - 2 * NU))

    def state(t1):
        q = K * (t_hot - t1) / L0
        t2 = T_COLD + q * L1 / K
        delta = c * ALPHA * L0 * (0.5 * (t_hot + t1) - THETA_0)
        if delta < G0:
            gap, p = G0 - delta, 0.0
            h = K_GAS / (gap + G_MIN)
        else:
            gap, p = 0.0, (delta - G0) / (L0 / modulus + L1 / modulus)
            h = H_C0 + C * (p / HARDNESS) ** M_EXP + K_GAS / G_MIN
        return q, t2, gap, p, h, q - h * (t1 - t2)

    lo, hi = T_COLD, t_hot  # the residual is > 0 at lo, < 0 at hi
    for _ in range(300):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if state(mid)[-1] > 0:
            lo = mid
        else:
            hi = mid
    t1 = 0.5 * (lo + hi)
    q, t2, gap, p, h, _ = state(t1)
    return dict(t_hot=t_hot, q=q, t1=t1, t2=t2, gap=gap, p=p, h=h)


def main():
    cases = [float(sys.argv[1])] if len(sys.argv) > 1 else [150.0, 400.0]
    for t_hot in cases:
        s = solve(t_hot)
        print(f"T_hot = {t_hot!r}: {'open' if s['gap'] > 0 else 'closed'}")
        for key in ("q", "t1", "t2", "gap", "p", "h"):
            print(f"  {key:3s} = {s[key]!r}")
        print("  Exact solution/Function =",
              f"y < {L0!r} ? {t_hot!r} - {s['q']!r}*y/{K!r} : "
              f"{T_COLD!r} + {s['q']!r}*({L0 + L1!r} - y)/{K!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
