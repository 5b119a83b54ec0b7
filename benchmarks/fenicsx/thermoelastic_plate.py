#!/usr/bin/python3
"""Thermoelastic plate: fully coupled linear thermoelasticity, FEniCSx/PETSc version.

Problem
-------
The scene benchmarks/scenes/thermoelastic_plate.prm of contact-stefan (issue 33):
the unit square, one body, plane strain, dimensionless units, rho = c = k = 1,
E = 1000, nu = 0.25 (lambda = mu = 400), alpha = 0.01, so
beta = (3 lambda + 2 mu) alpha = 20 (beta = 20 I), reference temperature
Theta_0 = 1. Quasi-static mechanics with thermal stress and the heat equation
with thermoelastic heating,

    -div sigma = 0,          sigma = C : e(u) - beta (Theta - Theta_0) I,
    rho c dTheta/dt + Theta_0 beta div(du/dt) - div(k grad Theta) = 0.

u = 0 on y = 0 (clamped), traction free elsewhere; Theta = 2 on x = 0 from
t = 0 on, insulated elsewhere; Theta = Theta_0 = 1 at t = 0 (also at x = 0: the
initial state is uniform). The initial displacement is the equilibrium with
the initial temperature, which is u = 0 here (Theta^0 = Theta_0 everywhere).
tau = 0.002, 100 steps to t = 0.2.

Discretisation (the same discrete problem as contact-stefan)
------------------------------------------------------------
Q1 displacement and Q1 temperature on the same N x N quadrilateral mesh. Two
cell quadrature rules:

* G: 2 x 2 Gauss ("quadrature_degree": 2) for the stiffness C e(u) : e(v) and
  the conductivity k grad Theta . grad psi (exact on this mesh anyway);
* V: the vertex (trapezoidal) rule, {"quadrature_rule": "GLL",
  "quadrature_degree": 1}: basix's Gauss-Lobatto rule with 2 x 2 points, the
  4 reference vertices with weights 1/4 each (``--check-mass`` verifies that
  it gives the lumped mass h^2/4 per cell vertex), for every term that
  contact-stefan evaluates by the vertex rule: the lumped mass, the
  thermal-stress load and the heating term.

With B(i, v) = sum_K w_v beta : e(phi_i)(x_v) (the code's cell operator,
doc/coupling.md section 2) one backward-Euler step, fully implicit in (u, Theta),
is

    K u - B (Theta - Theta_0)                                  = 0
    M (Theta - Theta_old)/tau + A Theta + Theta_0 B^T (u - u_old)/tau = 0

(M the lumped mass, A the conductivity matrix; the second line is the code's
m_v (h_v - h_v^old) + tau (A Theta)_v + G_v = 0 divided by tau, with
G_v = Theta_0 sum_i B(i, v)(u - u_old)_i; the sign makes compression heat and
Theta_0 B^T is the transpose of the thermal-stress operator, the discrete
energy identity). contact-stefan's 'fixed point' scheme iterates the two
lines to this solution; here it is one monolithic linear system on the mixed
space Q1^2 x Q1 with the weak form

    a = (C e(u), e(v))_G - (beta Theta, div v)_V
        + (rho c Theta + Theta_0 beta div u, psi)_V / tau + (k grad Theta, grad psi)_G
    L = -(beta Theta_0, div v)_V + (rho c Theta_old + Theta_0 beta div u_old, psi)_V / tau

The matrix is assembled and LU-factorised once (KSP preonly + LU: MUMPS if
available, or with ``--lu petsc`` PETSc's own LU with nested-dissection
ordering, whose triangular solves are about twice as fast here); every step
re-assembles the right-hand side (with the lifting of the Dirichlet data) and
does one forward/backward substitution with the stored factors.

Output
------
``RESULT <name> = <value>`` lines: dofs, linear solves, factorisations, max |u|,
max |Theta - Theta_0|, total thermoelastic heat (-sum_v G_v over all steps, the
code's RESULT of the same name), elastic energy at the end (1/2 int
sigma : C^-1 : sigma, in-plane components, over the material points as the
code takes it: the strain at the 2 x 2 Gauss points, the temperature of each
quadrant's vertex; the code's RESULT), and the timings:

* time imports: from the first line of this script to the end of the imports
  (interpreter start-up is not included; measure the process from outside);
* time setup: mesh, spaces, forms (FFCx JIT compilation, or loading from the
  cache in ~/.cache/fenics on a second run), boundary conditions;
* time assembly + factorisation: the matrix and its LU factors;
* time step loop: right-hand-side assembly and solve, all steps;
* time total in script: from the first line to the end of the loop;
* wall time: from mesh creation to the end of the loop (imports excluded, as
  ``wall time`` in contact_block.py and stefan_strip.py).

``--write FILE`` writes the final nodal u_x, u_y, Theta with the coordinates
(.npz: arrays x, y, u_x, u_y, theta; otherwise a text table). ``--compare VTU``
reads a contact-stefan VTU piece (meshio; zlib compressed is fine) and prints
the largest nodal differences, matched by coordinates (after the timed region;
deal.II writes single precision, so the floor is about 6e-8 relative).

Verified against contact-stefan 62eb648 (Scheme = fixed point, tolerance
1e-10) at N = 16, 32 and 144: the final nodal u and Theta agree to the single
precision of the VTU (max differences 4.7e-10 in u = 3.9e-8 max |u| and 6.0e-8
in Theta; at N = 16 and 32 every value rounded to single precision is the
VTU's, at N = 144 97.9 %), total thermoelastic heat and elastic energy to 1e-9
relative (the code's double-precision RESULT lines).

Run (serial; Debian's Python has dolfinx 0.5):

    /usr/bin/python3 thermoelastic_plate.py --n 144
    /usr/bin/python3 thermoelastic_plate.py --n 144 --lu petsc
    /usr/bin/python3 thermoelastic_plate.py --n 32 --compare out/solution_00100.0.vtu
"""

import time

T_SCRIPT = time.perf_counter()

import argparse  # noqa: E402
import sys  # noqa: E402

import numpy as np  # noqa: E402
import ufl  # noqa: E402
from dolfinx import fem, mesh  # noqa: E402
from dolfinx.fem import petsc as fem_petsc  # noqa: E402
from mpi4py import MPI  # noqa: E402
from petsc4py import PETSc  # noqa: E402

T_IMPORTS = time.perf_counter()

# Data of benchmarks/scenes/thermoelastic_plate.prm.
E_MOD = 1000.0
NU = 0.25
ALPHA = 0.01
RHO_C = 1.0
KAPPA = 1.0
THETA_REF = 1.0   # Theta_0 (dimensionless scale: the absolute value as it is)
THETA_INIT = 1.0
THETA_LEFT = 2.0


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--n", type=int, default=144, help="cells per side (default 144)")
    p.add_argument("--steps", type=int, default=100, help="time steps (default 100)")
    p.add_argument("--tau", type=float, default=0.002, help="time step (default 0.002)")
    p.add_argument("--lu", choices=["mumps", "petsc"], default="mumps",
                   help="sparse LU: MUMPS (if PETSc has it) or PETSc's own LU with "
                        "nested-dissection ordering (default mumps)")
    p.add_argument("--write", metavar="FILE", default=None,
                   help="write the final nodal x, y, u_x, u_y, theta (.npz or text)")
    p.add_argument("--compare", metavar="VTU", default=None,
                   help="compare the final fields with a contact-stefan VTU piece")
    p.add_argument("--check-mass", action="store_true",
                   help="check that the vertex rule reproduces the lumped mass h^2/4 per "
                        "cell vertex (outside the timed region)")
    return p.parse_args()


def result(name, value):
    if isinstance(value, (int, np.integer)):
        print(f"RESULT {name} = {int(value)}", flush=True)
    else:
        print(f"RESULT {name} = {value:.12e}", flush=True)


def nodal_fields(w, W, n):
    """Final nodal values (x, y, u_x, u_y, theta) of the mixed function w, ordered
    by vertex (i, j) of the n x n mesh, x = i/n, y = j/n, index i (n + 1) + j."""
    out = np.full((5, (n + 1) ** 2), np.nan)
    for sub, comps in ((0, (2, 3)), (1, (4,))):
        V, dof_map = W.sub(sub).collapse()
        n_local = V.dofmap.index_map.size_local
        bs = V.dofmap.index_map_bs
        xy = V.tabulate_dof_coordinates()[:n_local, :2]
        key = np.rint(xy[:, 0] * n).astype(np.int64) * (n + 1) + np.rint(xy[:, 1] * n).astype(np.int64)
        values = w.x.array[np.asarray(dof_map)[: n_local * bs]].reshape(n_local, bs)
        out[0, key] = xy[:, 0]
        out[1, key] = xy[:, 1]
        for c, row in enumerate(comps):
            out[row, key] = values[:, c]
    return tuple(out)


def material_point_energy(fields, n, lam, mu, beta):
    """1/2 int sigma : C^-1 : sigma (in-plane) as contact-stefan takes it
    (MechanicalField::elastic_statistics): over the material points, the cell
    corners; corner q of a cell has weight h^2/4, the strain of the bilinear
    displacement at the quadrant's 2 x 2 Gauss point and vertex q's temperature."""
    _, _, ux, uy, theta = fields
    h = 1.0 / n
    node = lambda i, j: i * (n + 1) + j  # noqa: E731
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    corners = [node(i, j), node(i + 1, j), node(i, j + 1), node(i + 1, j + 1)]
    g = (0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0))
    energy = 0.0
    for q in range(4):
        xi, eta = g[q % 2], g[q // 2]
        grad = []
        for f in (ux, uy):
            v = [f[c] for c in corners]
            grad.append((((v[1] - v[0]) * (1 - eta) + (v[3] - v[2]) * eta) / h,
                         ((v[2] - v[0]) * (1 - xi) + (v[3] - v[1]) * xi) / h))
        exx, eyy, exy = grad[0][0], grad[1][1], 0.5 * (grad[0][1] + grad[1][0])
        excess = theta[corners[q]] - THETA_REF
        sxx = lam * (exx + eyy) + 2 * mu * exx - beta * excess
        syy = lam * (exx + eyy) + 2 * mu * eyy - beta * excess
        sxy = 2 * mu * exy
        k = lam / (2 * lam + 2 * mu)
        cxx = (sxx - k * (sxx + syy)) / (2 * mu)
        cyy = (syy - k * (sxx + syy)) / (2 * mu)
        energy += float(np.sum(0.5 * (sxx * cxx + syy * cyy + 2 * sxy * sxy / (2 * mu)))) * h * h / 4
    return energy


def compare_vtu(path, n, fields):
    """Largest nodal differences to a contact-stefan VTU piece, by coordinates."""
    import meshio

    x, y, ux, uy, theta = fields
    m = meshio.read(path)
    pts = m.points.astype(np.float64)
    ref_u = m.point_data["displacement"][:, :2].astype(np.float64)
    ref_t = m.point_data["temperature"].astype(np.float64)

    def key(px, py):
        return np.rint(px * n).astype(np.int64) * (n + 1) + np.rint(py * n).astype(np.int64)

    ours = np.full((n + 1) ** 2, -1)
    ours[key(x, y)] = np.arange(x.size)
    idx = ours[key(pts[:, 0], pts[:, 1])]
    if np.any(idx < 0):
        raise RuntimeError(f"{path}: points that are not vertices of the {n} x {n} mesh")
    if np.unique(idx).size != x.size:
        raise RuntimeError(f"{path}: covers {np.unique(idx).size} of {x.size} nodes")
    du = np.abs(np.column_stack((ux, uy))[idx] - ref_u)
    dt = np.abs(theta[idx] - ref_t)
    u_scale = np.max(np.hypot(ux, uy))
    t_scale = np.max(np.abs(theta - THETA_REF))
    # The VTU holds single-precision values: the best possible agreement is that
    # our values rounded to single precision are the VTU's, bit for bit.
    ours32 = np.column_stack((ux, uy, theta)).astype(np.float32)[idx]
    ref32 = np.column_stack((m.point_data["displacement"][:, :2], m.point_data["temperature"]))
    same = np.mean(ours32 == ref32.astype(np.float32))
    print(f"compare with {path}: {pts.shape[0]} VTU points on {x.size} nodes "
          f"(single precision data; {100.0 * same:.2f} % of the values equal ours rounded "
          f"to single precision)", flush=True)
    result("compare max |u - u_ref|", float(du.max()))
    result("compare max |u - u_ref| / max |u|", float(du.max() / u_scale))
    result("compare max |Theta - Theta_ref|", float(dt.max()))
    result("compare max |Theta - Theta_ref| / max |Theta - Theta_0|", float(dt.max() / t_scale))


def main():
    args = parse_args()
    comm = MPI.COMM_WORLD
    if comm.size > 1 and comm.rank == 0:
        print("note: written for a serial run; --write/--compare use rank 0's nodes only, "
              "and the elastic energy is NaN on several ranks",
              file=sys.stderr)

    # --- set-up: mesh, spaces, forms (JIT), boundary conditions ------------
    t_setup = time.perf_counter()
    n = args.n
    msh = mesh.create_unit_square(comm, n, n, mesh.CellType.quadrilateral)
    cell = msh.ufl_cell()
    W = fem.FunctionSpace(msh, ufl.MixedElement([ufl.VectorElement("Lagrange", cell, 1),
                                                 ufl.FiniteElement("Lagrange", cell, 1)]))

    lam = E_MOD * NU / ((1.0 + NU) * (1.0 - 2.0 * NU))  # plane strain: 400
    mu = E_MOD / (2.0 * (1.0 + NU))                     # 400
    beta = (3.0 * lam + 2.0 * mu) * ALPHA               # 20 (beta = E alpha / (1 - 2 nu))

    dx_gauss = ufl.dx(metadata={"quadrature_degree": 2})  # 2 x 2 Gauss
    # Gauss-Lobatto-Legendre of degree 1 on the quadrilateral (basix): the 4
    # vertices, weight 1/4 each, i.e. the trapezoidal rule (--check-mass).
    dx_vertex = ufl.dx(metadata={"quadrature_rule": "GLL", "quadrature_degree": 1})

    def eps(w):
        return ufl.sym(ufl.grad(w))

    def sigma_mech(w):
        return 2.0 * mu * eps(w) + lam * ufl.tr(eps(w)) * ufl.Identity(2)

    tau = fem.Constant(msh, PETSc.ScalarType(args.tau))
    theta_ref = fem.Constant(msh, PETSc.ScalarType(THETA_REF))
    u, theta = ufl.TrialFunctions(W)
    v, psi = ufl.TestFunctions(W)
    w = fem.Function(W)       # solution at the new time level
    w_old = fem.Function(W)   # previous time level
    u_old, theta_old = ufl.split(w_old)

    a = (ufl.inner(sigma_mech(u), eps(v)) * dx_gauss
         - beta * theta * ufl.div(v) * dx_vertex
         + (RHO_C * theta + theta_ref * beta * ufl.div(u)) * psi / tau * dx_vertex
         + KAPPA * ufl.inner(ufl.grad(theta), ufl.grad(psi)) * dx_gauss)
    L = (-beta * theta_ref * ufl.div(v) * dx_vertex
         + (RHO_C * theta_old + theta_ref * beta * ufl.div(u_old)) * psi / tau * dx_vertex)
    a_form = fem.form(a)
    L_form = fem.form(L)

    fdim = msh.topology.dim - 1
    bottom = mesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[1], 0.0))
    left = mesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[0], 0.0))
    Vu, _ = W.sub(0).collapse()
    Vt, map_t = W.sub(1).collapse()
    u_zero = fem.Function(Vu)
    theta_left = fem.Function(Vt)
    theta_left.x.array[:] = THETA_LEFT
    bcs = [fem.dirichletbc(u_zero, fem.locate_dofs_topological((W.sub(0), Vu), fdim, bottom),
                           W.sub(0)),
           fem.dirichletbc(theta_left, fem.locate_dofs_topological((W.sub(1), Vt), fdim, left),
                           W.sub(1))]

    # Initial state: Theta^0 = 1 (also on x = 0), u^0 = the equilibrium with
    # Theta^0 = Theta_0, i.e. 0.
    w_old.x.array[:] = 0.0
    w_old.x.array[np.asarray(map_t)] = THETA_INIT
    w.x.array[:] = w_old.x.array
    t_assemble = time.perf_counter()

    # --- matrix, factorisation (once) ---------------------------------------
    A = fem_petsc.assemble_matrix(a_form, bcs=bcs)
    A.assemble()
    ksp = PETSc.KSP().create(comm)
    ksp.setOperators(A)
    ksp.setType("preonly")
    pc = ksp.getPC()
    pc.setType("lu")
    solver_type = "petsc"
    if args.lu == "mumps" and PETSc.Sys.hasExternalPackage("mumps"):
        solver_type = "mumps"
    pc.setFactorSolverType(solver_type)
    if solver_type == "petsc":
        pc.setFactorOrdering("nd")
    ksp.setFromOptions()  # PETSC_OPTIONS may override, e.g. "-mat_mumps_icntl_7 5"
    ksp.setUp()  # the LU factorisation
    b = fem_petsc.create_vector(L_form)
    t_loop = time.perf_counter()

    # --- time steps -----------------------------------------------------------
    solves = 0
    for _ in range(args.steps):
        with b.localForm() as b_local:
            b_local.set(0.0)
        fem_petsc.assemble_vector(b, L_form)
        fem_petsc.apply_lifting(b, [a_form], bcs=[bcs])
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(b, bcs)
        ksp.solve(b, w.vector)
        solves += 1
        reason = ksp.getConvergedReason()
        if reason < 0:
            print(f"linear solve failed (KSP reason {reason})", file=sys.stderr)
            sys.exit(3)
        w.x.scatter_forward()
        w_old.x.array[:] = w.x.array
    t_end = time.perf_counter()

    # --- results (outside the timed region) ----------------------------------
    # initial displacement u^0 = 0, so the total heat is -(Theta_0 beta div u^N, 1)_V.
    u_end, _ = ufl.split(w)
    heat = fem.assemble_scalar(fem.form(-theta_ref * beta * ufl.div(u_end) * dx_vertex))
    heat = comm.allreduce(heat, op=MPI.SUM)
    fields = nodal_fields(w, W, n)
    # At the material points, as the code takes it (a serial run's nodes).
    energy = material_point_energy(fields, n, lam, mu, beta)
    x, y, ux, uy, th = fields
    u_max = comm.allreduce(float(np.max(np.hypot(ux, uy))), op=MPI.MAX)
    t_max = comm.allreduce(float(np.max(np.abs(th - THETA_REF))), op=MPI.MAX)

    if comm.rank == 0:
        print(f"FEniCSx thermoelastic plate: {n} x {n} Q1 cells, {args.steps} steps of "
              f"tau = {args.tau}, monolithic LU ({solver_type}) factorised once", flush=True)
        result("dofs", W.dofmap.index_map.size_global * W.dofmap.index_map_bs)
        result("temperature dofs", Vt.dofmap.index_map.size_global)
        result("displacement dofs", Vu.dofmap.index_map.size_global * Vu.dofmap.index_map_bs)
        result("time steps", args.steps)
        result("linear solves", solves)
        result("factorisations", 1)
        result("max |u|", u_max)
        result("max |Theta - Theta_0|", t_max)
        result("total thermoelastic heat", heat)
        result("elastic energy", energy)
        result("time imports", T_IMPORTS - T_SCRIPT)
        result("time setup (mesh, forms incl. JIT, bcs)", t_assemble - t_setup)
        result("time assembly + factorisation", t_loop - t_assemble)
        result("time step loop", t_end - t_loop)
        result("time total in script", t_end - T_SCRIPT)
        result("wall time", t_end - t_setup)

    if args.check_mass:
        # The vertex rule must give the lumped mass: h^2/4 per cell at each of its
        # vertices, i.e. h^2 inside, h^2/2 on an edge, h^2/4 at a corner.
        tt, ss = ufl.TrialFunction(Vt), ufl.TestFunction(Vt)
        Mv = fem_petsc.assemble_matrix(fem.form(tt * ss * dx_vertex))
        Mv.assemble()
        diag = Mv.getDiagonal().array
        xt = Vt.tabulate_dof_coordinates()[: diag.size]
        h = 1.0 / n
        on_x = np.isclose(xt[:, 0], 0.0) | np.isclose(xt[:, 0], 1.0)
        on_y = np.isclose(xt[:, 1], 0.0) | np.isclose(xt[:, 1], 1.0)
        expected = h * h / (2.0 ** on_x * 2.0 ** on_y)
        off = Mv.norm(PETSc.NormType.FROBENIUS) ** 2 - np.sum(diag ** 2)
        result("lumped mass check: max |m_v - expected| / h^2",
               float(np.max(np.abs(diag - expected)) / h ** 2))
        result("lumped mass check: off-diagonal Frobenius norm^2", max(off, 0.0))

    if args.write and comm.rank == 0:
        if args.write.endswith(".npz"):
            np.savez(args.write, x=x, y=y, u_x=ux, u_y=uy, theta=th)
        else:
            np.savetxt(args.write, np.column_stack(fields), fmt="%.17e",
                       header="x y u_x u_y theta")
    if args.compare and comm.rank == 0:
        compare_vtu(args.compare, n, fields)


if __name__ == "__main__":
    main()
