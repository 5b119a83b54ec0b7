#!/usr/bin/python3
"""Stefan strip: two-phase Stefan problem with a smoothed enthalpy method, FEniCSx version.

Problem
-------
Melting of a solid strip [0,1] x [0,0.1] heated at x = 0. Both phases have
rho = c = k = 1, latent heat L = 1, melting temperature 0. The exact solution
is Neumann's similarity solution with wall temperature T_L = 1 (liquid side,
x = 0) and initial/far-field temperature T_S = -0.5 (solid):

    xi = x / (2 sqrt(t)),   s(t) = 2 lambda sqrt(t)   (melting front)
    Theta = T_L - T_L erf(xi) / erf(lambda)           for xi < lambda (liquid)
    Theta = T_S - T_S erfc(xi) / erfc(lambda)         for xi > lambda (solid)

where lambda solves the Stefan condition L s'(t) = -Theta_x(s-) + Theta_x(s+),
i.e. (k = c = L = 1)

    T_L exp(-lambda^2) / erf(lambda) + T_S exp(-lambda^2) / erfc(lambda)
        = sqrt(pi) lambda                             (lambda ~ 0.4698).

The run goes from t0 = 0.001 (the exact profile interpolated at the nodes is
the initial condition) to T = 0.1 with Dirichlet data Theta = 1 at x = 0 and
the exact solution at x = 1; the top and bottom are insulated.

Discretisation
--------------
Q1 on NX x NX/10 quadrilaterals (h = 1/NX), backward Euler with constant step
tau = 0.1/NX by default (the last step is shortened to end exactly at T, as in
the C++ code). Enthalpy method with unknown Theta and a smoothed enthalpy

    H_eps(Theta) = Theta + L S_eps(Theta),

S_eps a smoothed Heaviside over the mushy interval [-eps/2, eps/2]:
``--smoothing linear`` (default) is the linear ramp S = clip(Theta/eps + 1/2, 0, 1);
``--smoothing cubic`` is the C^1 ramp S = s^2 (3 - 2 s), s = clip(Theta/eps + 1/2, 0, 1).
eps = 2h by default (``--eps`` overrides). Weak form, for every test function v:

    ((H_eps(Theta) - H_eps(Theta_old)) / tau, v)_lumped + (grad Theta, grad v) = 0,

where (.,.)_lumped is the vertex (2-point Gauss-Lobatto per direction) rule, i.e.
a lumped mass in which H_eps acts on nodal values, and the stiffness term uses
the default (exact, 2x2 Gauss) rule. The nonlinear system of each step is
solved with dolfinx's NewtonSolver (residual test, rtol 1e-10, atol 1e-12) and
a direct LU (MUMPS if available), started from the previous step. Plain
Newton cycles here (nodes jump back and forth across the mushy interval, for
either smoothing), so by default each Newton update is followed by a
backtracking Armijo line search on ||F|| (step halved until
||F(x - a dx)|| <= (1 - 1e-4 a) ||F(x)||), installed through
NewtonSolver.set_update; ``--no-line-search`` switches it off. With the
linear ramp H_eps is piecewise linear in the nodal values, so Newton ends in
one step once every node sits on the right piece (about 1.5 iterations per
step); the cubic ramp needs about 4.

Errors
------
At every step t_n (n >= 1): e_n^2 = int (Theta_h - Theta_exact(t_n))^2 and
norm_n^2 = int Theta_exact(t_n)^2, both with the 3x3 Gauss rule (degree 4)
per cell; the relative space-time L2 error is
sqrt(sum_n tau_n e_n^2 / sum_n tau_n norm_n^2); the relative L2 error is
e_N / norm_N at T. The error evaluation is inside the timed region
(time.perf_counter() from mesh creation to the last step, imports excluded).

Output: ``RESULT <name> = <value>`` lines. If Newton fails at a step the run
stops, prints the RESULT lines available (no error lines) and exits with
status 3.

Run (serial; Debian's Python has dolfinx 0.5):

    /usr/bin/python3 stefan_strip.py --nx 100
    /usr/bin/python3 stefan_strip.py --nx 100 --smoothing cubic --eps 0.01
"""

import argparse
import math
import sys
import time

import numpy as np
import ufl
from dolfinx import fem, mesh
from dolfinx.fem import petsc as fem_petsc
from dolfinx.nls import petsc as nls_petsc
from mpi4py import MPI
from petsc4py import PETSc

try:
    from scipy.optimize import brentq
    from scipy.special import erf as np_erf, erfc as np_erfc
except ImportError:  # pragma: no cover - scipy is expected, but keep a fallback
    brentq = None
    np_erf = np.vectorize(math.erf)
    np_erfc = np.vectorize(math.erfc)

# Physical data of the benchmark (rho = c = k = L = 1, melting temperature 0).
T_HOT = 1.0
T_COLD = -0.5
LATENT = 1.0
T0 = 0.001
T_END = 0.1


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--nx", type=int, default=100,
                   help="cells along x (default 100); NX/10 cells along y")
    p.add_argument("--tau", type=float, default=None,
                   help="time step (default 0.1/NX = h/10)")
    p.add_argument("--eps", type=float, default=None,
                   help="mushy-zone width of the smoothed enthalpy (default 2h)")
    p.add_argument("--smoothing", choices=["linear", "cubic"], default="linear",
                   help="smoothed Heaviside: linear ramp (C^0) or cubic C^1 ramp "
                        "(default linear)")
    p.add_argument("--rtol", type=float, default=1e-10, help="Newton relative residual tolerance")
    p.add_argument("--atol", type=float, default=1e-12, help="Newton absolute residual tolerance")
    p.add_argument("--max-it", type=int, default=50, help="Newton maximum iterations per step")
    p.add_argument("--criterion", choices=["residual", "incremental"], default="residual",
                   help="Newton convergence test (default residual)")
    p.add_argument("--no-line-search", dest="line_search", action="store_false",
                   help="plain Newton steps (no backtracking line search)")
    p.add_argument("--verbose", action="store_true", help="one line per time step")
    return p.parse_args()


def result(name, value):
    if isinstance(value, (int, np.integer)):
        print(f"RESULT {name} = {int(value)}", flush=True)
    else:
        print(f"RESULT {name} = {value:.10e}", flush=True)


def stefan_lambda():
    """Root of T_L e^{-l^2}/erf(l) + T_S e^{-l^2}/erfc(l) - sqrt(pi) l = 0 (k = c = L = 1)."""
    def f(lam):
        g = math.exp(-lam * lam)
        return (T_HOT * g / math.erf(lam) + T_COLD * g / math.erfc(lam)
                - math.sqrt(math.pi) * lam / LATENT)
    a, b = 1e-6, 3.0  # f(a) > 0 (T_HOT > 0), f(b) < 0
    if brentq is not None:
        return brentq(f, a, b, xtol=1e-15, rtol=4 * np.finfo(float).eps, maxiter=200)
    for _ in range(200):
        m = 0.5 * (a + b)
        if f(m) > 0:
            a = m
        else:
            b = m
    return 0.5 * (a + b)


def exact_numpy(x, t, lam):
    xi = x / (2.0 * np.sqrt(t))
    liquid = T_HOT - T_HOT * np_erf(xi) / math.erf(lam)
    solid = T_COLD - T_COLD * np_erfc(xi) / math.erfc(lam)
    return np.where(xi < lam, liquid, solid)


def exact_ufl(x, t, lam):
    xi = x[0] / (2.0 * ufl.sqrt(t))
    liquid = T_HOT - T_HOT * ufl.erf(xi) / math.erf(lam)
    solid = T_COLD - T_COLD * (1.0 - ufl.erf(xi)) / math.erfc(lam)
    return ufl.conditional(ufl.lt(xi, lam), liquid, solid)


def smoothed_heaviside(theta, eps, kind):
    s = theta / eps + 0.5
    s = ufl.conditional(ufl.lt(s, 0.0), 0.0, ufl.conditional(ufl.gt(s, 1.0), 1.0, s))
    if kind == "linear":
        return s
    return s * s * (3.0 - 2.0 * s)


def main():
    args = parse_args()
    comm = MPI.COMM_WORLD
    nx = args.nx
    ny = max(1, round(nx / 10))
    h = 1.0 / nx
    tau_nominal = args.tau if args.tau is not None else 0.1 / nx
    eps_value = args.eps if args.eps is not None else 2.0 * h
    lam = stefan_lambda()

    t_start = time.perf_counter()

    # --- mesh and space ------------------------------------------------------
    msh = mesh.create_rectangle(comm, [np.array([0.0, 0.0]), np.array([1.0, 0.1])],
                                [nx, ny], mesh.CellType.quadrilateral)
    V = fem.FunctionSpace(msh, ("Lagrange", 1))
    x = ufl.SpatialCoordinate(msh)
    coords = V.tabulate_dof_coordinates()[:, 0]

    theta = fem.Function(V, name="temperature")
    theta_old = fem.Function(V)
    v = ufl.TestFunction(V)
    tau = fem.Constant(msh, PETSc.ScalarType(tau_nominal))
    time_c = fem.Constant(msh, PETSc.ScalarType(T0))
    eps = fem.Constant(msh, PETSc.ScalarType(eps_value))

    # --- Dirichlet data: 1 at x = 0, the exact solution at x = 1 ------------
    wall_dofs = fem.locate_dofs_geometrical(
        V, lambda p: np.isclose(p[0], 0.0) | np.isclose(p[0], 1.0))
    g = fem.Function(V)
    bc = fem.dirichletbc(g, wall_dofs)

    def set_boundary_data(t):
        g.x.array[wall_dofs] = exact_numpy(coords[wall_dofs], t, lam)

    # --- weak form -----------------------------------------------------------
    def enthalpy(w):
        return w + LATENT * smoothed_heaviside(w, eps, args.smoothing)

    dx_lumped = ufl.dx(metadata={"quadrature_rule": "GLL", "quadrature_degree": 1})
    residual = ((enthalpy(theta) - enthalpy(theta_old)) / tau * v * dx_lumped
                + ufl.inner(ufl.grad(theta), ufl.grad(v)) * ufl.dx)

    problem = fem_petsc.NonlinearProblem(residual, theta, bcs=[bc])
    solver = nls_petsc.NewtonSolver(comm, problem)
    solver.convergence_criterion = args.criterion
    solver.rtol = args.rtol
    solver.atol = args.atol
    solver.max_it = args.max_it
    solver.error_on_nonconvergence = False
    # Backtracking (Armijo) line search on ||F||, run inside NewtonSolver's
    # update hook. Without it plain Newton cycles (a period-2 cycle already
    # in the first steps): a node outside the mushy interval sees H' = 1,
    # jumps across the interval, and jumps back at the next iteration.
    ls_stats = {"backtracks": 0}
    if args.line_search:
        b_trial = solver.b.duplicate()
        x_start = solver.b.duplicate()

        def residual_norm(vec):
            with b_trial.localForm() as loc:
                loc.set(0.0)
            problem.F(vec, b_trial)
            return b_trial.norm()

        def line_search_update(_solver, dx, xv):
            f0 = solver.b.norm()  # F at the current iterate (before the update)
            xv.copy(x_start)
            alpha = 1.0
            for _ in range(30):
                xv.axpy(-alpha, dx)
                if residual_norm(xv) <= (1.0 - 1e-4 * alpha) * f0:
                    break
                x_start.copy(xv)
                alpha *= 0.5
                ls_stats["backtracks"] += 1
            xv.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)

        solver.set_update(line_search_update)
    ksp = solver.krylov_solver
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    if PETSc.Sys.hasExternalPackage("mumps"):
        ksp.getPC().setFactorSolverType("mumps")

    # --- error functionals (3x3 Gauss per cell) -----------------------------
    dx_error = ufl.dx(metadata={"quadrature_degree": 4})
    exact = exact_ufl(x, time_c, lam)
    error_form = fem.form((theta - exact) ** 2 * dx_error)
    norm_form = fem.form(exact ** 2 * dx_error)
    melt_form = fem.form(smoothed_heaviside(theta, eps, args.smoothing) * dx_lumped)

    def integrate(form):
        return comm.allreduce(fem.assemble_scalar(form), op=MPI.SUM)

    # --- initial condition ---------------------------------------------------
    theta_old.x.array[:] = exact_numpy(coords, T0, lam)
    theta.x.array[:] = theta_old.x.array

    # --- time loop (same step rule as the C++ code) --------------------------
    t = T0
    steps = 0
    newton_total = 0
    failures = 0
    st_error2 = 0.0
    st_norm2 = 0.0
    error2 = norm2 = float("nan")
    slack = 1e-9
    while t < T_END - slack * tau_nominal:
        dt = tau_nominal
        if t + dt > T_END - slack * dt:
            dt = T_END - t
        t_new = t + dt
        tau.value = dt
        time_c.value = t_new
        set_boundary_data(t_new)
        theta.x.array[wall_dofs] = g.x.array[wall_dofs]  # start Newton from the new data
        try:
            its, converged = solver.solve(theta)
        except RuntimeError as err:
            its, converged = solver.max_it, False
            print(f"Newton/linear solver error at t = {t_new}: {err}", file=sys.stderr)
        newton_total += its
        if not converged:
            failures += 1
            print(f"Newton did not converge at step {steps + 1}, t = {t_new:.6g} "
                  f"({its} iterations)", file=sys.stderr)
            break
        t = t_new
        steps += 1
        theta_old.x.array[:] = theta.x.array

        error2 = integrate(error_form)
        norm2 = integrate(norm_form)
        st_error2 += dt * error2
        st_norm2 += dt * norm2
        if args.verbose and comm.rank == 0:
            print(f"step {steps:5d}  t = {t:.6f}  newton {its:2d}  "
                  f"rel L2 error {math.sqrt(error2 / norm2):.4e}", flush=True)

    melt_area = integrate(melt_form)
    wall = time.perf_counter() - t_start

    if comm.rank == 0:
        attempted = steps + failures
        if failures == 0:
            result("relative space-time L2 error temperature", math.sqrt(st_error2 / st_norm2))
            result("relative L2 error temperature", math.sqrt(error2 / norm2))
            result("L2 error temperature", math.sqrt(error2))
            result("front position", melt_area / 0.1)
            result("exact front position", 2.0 * lam * math.sqrt(t))
        result("time steps", steps)
        result("temperature dofs", V.dofmap.index_map.size_global)
        result("mean newton iterations", newton_total / attempted if attempted else 0.0)
        result("newton failures", failures)
        result("line search backtracks", ls_stats["backtracks"])
        result("stefan lambda", lam)
        result("mushy width", eps_value)
        result("wall time", wall)
    if failures:
        sys.exit(3)


if __name__ == "__main__":
    main()
