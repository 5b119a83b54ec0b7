#!/usr/bin/python3
"""Contact block: nodal Signorini problem on the unit square, FEniCSx/PETSc version.

Problem
-------
Linear elasticity (plane strain, E = 1, nu = 0.3) on the unit square [0,1]^2,
discretised with Q1 (bilinear, vector-valued) elements on an N x N mesh of
quadrilaterals. Boundary conditions:

* top, y = 1:      Dirichlet u = (0, -0.1 x) (the block is pressed down,
                   harder on the right);
* sides x = 0, 1:  traction free;
* bottom, y = 0:   frictionless contact with a rigid flat floor, imposed
                   nodally: u_y >= -0.05 at every bottom node; u_x is free
                   there (the rigid x-translation is fixed by the top).

The discrete problem is the bound-constrained quadratic programme

    minimise 1/2 u^T K u   subject to   u_y(node) >= -0.05 at bottom nodes,
                                        u = g at the top nodes,

solved with PETSc's reduced-space variational-inequality Newton method
(SNES "vinewtonrsls", bounds via SNES.setVariableBounds). The linear solver
inside is a direct LU factorisation (MUMPS if available) or, with
``--ksp cg-gamg``, conjugate gradients preconditioned by GAMG.

Reported quantities (one ``RESULT <name> = <value>`` line each):

* contact force: total vertical reaction of the floor, the sum over the
  bottom y-dofs of (K u)_i with K the stiffness matrix without any boundary
  condition (K u is the nodal force the floor exerts on the body; > 0 for
  compression);
* active contact nodes: bottom nodes with u_y <= -0.05 + 1e-12;
* dofs, snes iterations, wall time (time.perf_counter() from mesh creation to
  the last quantity, imports excluded).

Run (serial; Debian's Python has dolfinx 0.5):

    /usr/bin/python3 contact_block.py --n 64
    /usr/bin/python3 contact_block.py --n 64 --ksp cg-gamg
"""

import argparse
import sys
import time

import numpy as np
import ufl
from dolfinx import fem, mesh
from dolfinx.fem import petsc as fem_petsc
from mpi4py import MPI
from petsc4py import PETSc


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--n", type=int, default=64, help="cells per direction (default 64)")
    p.add_argument("--ksp", choices=["lu", "cg-gamg"], default="lu",
                   help="linear solver inside the SNES: direct LU (MUMPS if available) "
                        "or CG + GAMG (default lu)")
    p.add_argument("--E", type=float, default=1.0, help="Young's modulus (default 1)")
    p.add_argument("--nu", type=float, default=0.3, help="Poisson ratio (default 0.3)")
    p.add_argument("--gap", type=float, default=0.05,
                   help="floor distance: u_y >= -gap at bottom nodes (default 0.05)")
    p.add_argument("--push", type=float, default=0.1,
                   help="top displacement u = (0, -push * x) (default 0.1)")
    p.add_argument("--rtol", type=float, default=1e-10, help="SNES relative tolerance")
    p.add_argument("--atol", type=float, default=1e-13, help="SNES absolute tolerance")
    p.add_argument("--max-it", type=int, default=100, help="SNES maximum iterations")
    p.add_argument("--verbose", action="store_true", help="SNES monitor")
    return p.parse_args()


def result(name, value):
    if isinstance(value, (int, np.integer)):
        print(f"RESULT {name} = {int(value)}", flush=True)
    else:
        print(f"RESULT {name} = {value:.12e}", flush=True)


class SignoriniProblem:
    """Residual F(u) = K u (rows of the Dirichlet dofs replaced by u - g) and Jacobian K."""

    def __init__(self, residual_form, jacobian_form, u, bcs):
        self.F = fem.form(residual_form)
        self.J = fem.form(jacobian_form)
        self.u = u
        self.bcs = bcs

    def residual(self, snes, x, b):
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        x.copy(self.u.vector)
        self.u.vector.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        with b.localForm() as b_local:
            b_local.set(0.0)
        fem_petsc.assemble_vector(b, self.F)
        fem_petsc.apply_lifting(b, [self.J], bcs=[self.bcs], x0=[x], scale=-1.0)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        fem_petsc.set_bc(b, self.bcs, x, -1.0)

    def jacobian(self, snes, x, A, P):
        A.zeroEntries()
        fem_petsc.assemble_matrix(A, self.J, bcs=self.bcs)
        A.assemble()


class FreshGAMG:
    """Python PC context that builds a new GAMG preconditioner at every set-up.

    vinewtonrsls solves on the inactive set, whose size changes between
    Newton iterations; PETSc 3.18's PCGAMG refuses to be set up again with
    operators of a different size ("Cannot change local size of Amat after
    use"), so the GAMG object is recreated for each reduced operator. The
    rigid-body modes (near-null space) are restricted to the inactive set,
    which is recomputed here with the rule of PETSc's SNESVIGetActiveSetIS
    (dof i is active if it sits within 1e-8 of its lower bound with
    F_i > 0, or of its upper bound with F_i < 0); if the count does not match
    the reduced operator, GAMG runs without them.
    """

    def __init__(self, snes, lower, upper, rigid_modes):
        self.snes = snes
        self.lower = lower
        self.upper = upper
        self.rigid_modes = rigid_modes  # owned entries, shape (n_owned, 3)
        self.inner = None
        self.without_modes = 0  # set-ups where the inactive set could not be matched

    def _inactive(self, n_reduced):
        n_full = self.rigid_modes.shape[0]
        if n_reduced == n_full:
            return np.arange(n_full)
        x = self.snes.getSolution().array_r
        f = self.snes.getFunction()[0].array_r
        xl = self.lower.array_r
        xu = self.upper.array_r
        inactive = ((x > xl + 1e-8) | (f < 0.0)) & ((x < xu - 1e-8) | (f > 0.0))
        idx = np.flatnonzero(inactive)
        return idx if idx.size == n_reduced else None

    def setUp(self, pc):
        A, P = pc.getOperators()
        idx = self._inactive(P.getLocalSize()[0])
        if idx is None:
            self.without_modes += 1
        else:
            vecs = []
            for k in range(self.rigid_modes.shape[1]):
                w = P.createVecLeft()
                w.array_w[:] = self.rigid_modes[idx, k]
                vecs.append(w)
            for k, w in enumerate(vecs):  # Gram-Schmidt (MatNullSpace wants orthonormal)
                for q in vecs[:k]:
                    w.axpy(-w.dot(q), q)
                w.normalize()
            P.setNearNullSpace(PETSc.NullSpace().create(vectors=vecs, comm=P.comm))
        if self.inner is not None:
            self.inner.destroy()
        self.inner = PETSc.PC().create(pc.comm)
        self.inner.setType("gamg")
        self.inner.setOperators(A, P)
        self.inner.setUp()

    def apply(self, pc, x, y):
        self.inner.apply(x, y)

    def reset(self, pc):
        if self.inner is not None:
            self.inner.destroy()
            self.inner = None


def main():
    args = parse_args()
    comm = MPI.COMM_WORLD
    t_start = time.perf_counter()

    # --- mesh, space, material --------------------------------------------
    msh = mesh.create_unit_square(comm, args.n, args.n, mesh.CellType.quadrilateral)
    V = fem.VectorFunctionSpace(msh, ("Lagrange", 1))
    tdim = msh.topology.dim
    fdim = tdim - 1

    lam = args.E * args.nu / ((1.0 + args.nu) * (1.0 - 2.0 * args.nu))  # plane strain
    mu = args.E / (2.0 * (1.0 + args.nu))

    def sigma(w):
        e = ufl.sym(ufl.grad(w))
        return 2.0 * mu * e + lam * ufl.tr(e) * ufl.Identity(2)

    u = fem.Function(V, name="displacement")
    du = ufl.TrialFunction(V)
    v = ufl.TestFunction(V)
    internal_force = ufl.inner(sigma(u), ufl.sym(ufl.grad(v))) * ufl.dx
    stiffness = ufl.inner(sigma(du), ufl.sym(ufl.grad(v))) * ufl.dx

    # --- boundaries ----------------------------------------------------------
    top_facets = mesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[1], 1.0))
    bottom_facets = mesh.locate_entities_boundary(msh, fdim, lambda x: np.isclose(x[1], 0.0))

    g = fem.Function(V)
    g.interpolate(lambda x: np.vstack((np.zeros_like(x[0]), -args.push * x[0])))
    top_dofs = fem.locate_dofs_topological(V, fdim, top_facets)
    bcs = [fem.dirichletbc(g, top_dofs)]

    # y-components of the bottom nodes, as (block-unrolled) indices into V;
    # keep the owned ones for the bounds, the force and the active count.
    bs = V.dofmap.index_map_bs
    n_owned = V.dofmap.index_map.size_local * bs
    bottom_y = fem.locate_dofs_topological(V.sub(1), fdim, bottom_facets)
    bottom_y = bottom_y[bottom_y < n_owned]

    # --- bounds --------------------------------------------------------------
    lower = u.vector.copy()
    upper = u.vector.copy()
    lower.set(PETSc.NINFINITY)
    upper.set(PETSc.INFINITY)
    lower.array_w[bottom_y] = -args.gap
    lower.assemble()
    upper.assemble()

    # --- SNES VI -------------------------------------------------------------
    problem = SignoriniProblem(internal_force, stiffness, u, bcs)
    b = fem_petsc.create_vector(problem.F)
    A = fem_petsc.create_matrix(problem.J)

    snes = PETSc.SNES().create(comm)
    snes.setType("vinewtonrsls")
    snes.setFunction(problem.residual, b)
    snes.setJacobian(problem.jacobian, A)
    snes.setVariableBounds(lower, upper)
    snes.setTolerances(rtol=args.rtol, atol=args.atol, stol=0.0, max_it=args.max_it)
    ksp = snes.getKSP()
    pc = ksp.getPC()
    if args.ksp == "lu":
        ksp.setType("preonly")
        pc.setType("lu")
        if PETSc.Sys.hasExternalPackage("mumps"):
            pc.setFactorSolverType("mumps")
    else:
        ksp.setType("cg")
        pc.setType(PETSc.PC.Type.PYTHON)
        # Rigid-body modes of the plane: two translations and one rotation.
        xy = V.tabulate_dof_coordinates()[: n_owned // bs, :2]
        modes = np.zeros((n_owned, 3))
        modes[0::2, 0] = 1.0
        modes[1::2, 1] = 1.0
        modes[0::2, 2] = -xy[:, 1]
        modes[1::2, 2] = xy[:, 0]
        gamg_context = FreshGAMG(snes, lower, upper, modes)
        pc.setPythonContext(gamg_context)
        ksp.setTolerances(rtol=1e-12, atol=1e-15, max_it=1000)
    if args.verbose:
        opts = PETSc.Options()
        opts["snes_monitor"] = None
        opts["snes_converged_reason"] = None
        opts["ksp_converged_reason"] = None
    snes.setFromOptions()

    # Initial guess: zero, with the Dirichlet values set (feasible: 0 >= -gap).
    x = u.vector.copy()
    x.set(0.0)
    fem_petsc.set_bc(x, bcs)
    x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
    snes.solve(None, x)
    reason = snes.getConvergedReason()
    iterations = snes.getIterationNumber()
    x.copy(u.vector)
    u.vector.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)

    # --- contact force and active set ----------------------------------------
    # K u without boundary conditions: at a bottom y-dof this is the nodal force
    # that the floor exerts on the body (zero at inactive nodes up to the
    # solver tolerance), > 0 for compression.
    Ku = fem_petsc.assemble_vector(problem.F)
    Ku.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    force = comm.allreduce(float(np.sum(Ku.array_r[bottom_y])), op=MPI.SUM)
    # Consistency checks (informational): global vertical equilibrium (the top
    # reaction balances the floor), no tension and no force at free nodes.
    top_y = fem.locate_dofs_topological(V.sub(1), fdim, top_facets)
    top_y = top_y[top_y < n_owned]
    top_force = comm.allreduce(float(np.sum(Ku.array_r[top_y])), op=MPI.SUM)
    bottom_Ku = Ku.array_r[bottom_y]
    uy_bottom = u.vector.array_r[bottom_y]
    active = comm.allreduce(int(np.count_nonzero(uy_bottom <= -args.gap + 1e-12)), op=MPI.SUM)
    min_uy = comm.allreduce(float(np.min(uy_bottom)) if uy_bottom.size else np.inf, op=MPI.MIN)

    wall = time.perf_counter() - t_start

    if comm.rank == 0:
        note = ""
        if args.ksp == "cg-gamg":
            note = f" (GAMG set-ups without rigid-body modes: {gamg_context.without_modes})"
        print(f"SNES converged reason {reason}, linear solver {args.ksp}{note}, "
              f"min bottom u_y = {min_uy:.6e}", flush=True)
        if args.verbose:
            free = uy_bottom > -args.gap + 1e-12
            print(f"top vertical reaction (K u summed over top y-dofs) = {top_force:.12e}; "
                  f"floor + top = {force + top_force:.3e}; min nodal floor force = "
                  f"{bottom_Ku.min():.3e}; max |K u| at free bottom y-dofs = "
                  f"{np.abs(bottom_Ku[free]).max() if free.any() else 0.0:.3e}", flush=True)
        result("contact force", force)
        result("active contact nodes", active)
        result("dofs", V.dofmap.index_map.size_global * bs)
        result("snes iterations", iterations)
        result("wall time", wall)
    if reason <= 0:
        if comm.rank == 0:
            print(f"SNES did not converge (reason {reason})", file=sys.stderr)
        sys.exit(3)


if __name__ == "__main__":
    main()
