// Declaration and parsing of the shared linear-solver entries
// (linear_algebra/linear_solver_parameters.h).
#include <deal.II/base/mpi.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/linear_algebra/linear_solver_parameters.h>

#include <Amesos.h>

namespace ContactStefan
{
  namespace Parameters
  {
    using namespace Input;

    void LinearSolvers::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      prm.declare_entry("Linear solver",
                        "automatic",
                        Patterns::Selection("automatic|direct|cg-amg"),
                        "'direct': a sparse direct solver ('Direct solver type'); 'cg-amg': conjugate "
                        "gradients preconditioned by ML algebraic multigrid (for elasticity "
                        "built for the rigid-body modes); 'automatic': direct for a system "
                        "with fewer unknowns than Automatic direct limit (the heat system "
                        "on one MPI rank: Automatic direct limit for heat), cg-amg "
                        "otherwise, decided per system.");
      prm.declare_entry("Automatic direct limit",
                        "20000",
                        Patterns::Integer(0),
                        "Linear solver = automatic: systems with fewer unknowns are solved "
                        "directly. Measured on the contact block of doc/results.md: equal "
                        "at 8 450 DoFs, CG + AMG 2.7 times faster at 33 282, 8.2 times at "
                        "132 098 (commit 240dff8, 2026-11-22, 2-core development VM; "
                        "KLU then). The heat system on one MPI rank has its own limit.");
      prm.declare_entry("Automatic direct limit for heat",
                        "100000",
                        Patterns::Integer(0),
                        "Linear solver = automatic, one MPI rank: heat (enthalpy) systems "
                        "with fewer unknowns are solved directly (by CHOLMOD unless "
                        "'Direct solver type' names another); on several ranks 'Automatic "
                        "direct limit' applies (KLU). A scalar system's "
                        "factor fills far less per unknown than an elasticity system's. "
                        "Measured with CHOLMOD against CG + AMG (2026-11-28, 2-core "
                        "development VM, hand runs at bdd4940): the linear heat equation on "
                        "the thermoelastic plate, 100 steps, 2.1 times faster at 21 025 "
                        "unknowns, 1.8 at 83 521, 1.4 at 187 489; the Stefan strip "
                        "(nx = 800, 64 881 unknowns, 490 factorisations) 39.3 s against "
                        "57.0 s.");
      prm.declare_entry("Direct solver type",
                        "automatic",
                        Patterns::Selection(
                          "automatic|cholmod|Amesos_Klu|Amesos_Mumps|Amesos_Superludist"),
                        "Back end of the direct solver: 'cholmod', SuiteSparse's sparse "
                        "Cholesky factorisation (our systems are symmetric positive definite; "
                        "one MPI rank only; it keeps its ordering and symbolic analysis while "
                        "only the active set changes), or an Amesos one this Trilinos was "
                        "built with (Debian's has KLU and MUMPS; a missing one is refused). "
                        "'automatic': cholmod on one MPI rank, Amesos_Klu on several.");
      prm.declare_entry("Kept factorisations",
                        "2",
                        Patterns::Integer(0, 100),
                        "The enthalpy step keeps this many factorisations (direct solvers) "
                        "or AMG hierarchies (with 'AMG update' = recompute, the enthalpy system's "
                        "automatic choice) of earlier active sets "
                        "besides the current one, the least recently used being replaced: a "
                        "set that recurs, as the set without plateau nodes does each time a "
                        "melting front passes a row of nodes, is solved without factorising "
                        "or recomputing again. Each costs the memory of one factor or "
                        "hierarchy. 0: keep none. (cholmod: a factor it modifies row by row, "
                        "'Row update limit', is modified in place and not kept.)");
      prm.declare_entry(
        "Row update limit",
        "0.5",
        Patterns::Double(0),
        "cholmod: when a new active set changes only some rows and columns "
        "of the matrix (nodes entering or leaving a plateau or the contact "
        "set), the factor is modified row by row (CHOLMOD's row deletion "
        "and addition, Davis & Hager 2005) instead of being refactorised, "
        "if the estimated work of the modifications is below this fraction "
        "of a factorisation's. The first solve with a modified factor is "
        "checked against 'Refactorisation backward error' and the matrix is "
        "factorised afresh if it fails. 0: always refactorise. The Stefan strip "
        "at nx = 400 (doc/performance.md; hand runs at 6eeef6a) took 3.13-3.17 s with the default "
        "against 4.45-4.63 s with 0; limits of 1 and 2 measured the same as "
        "0.5 within the runs' spread.");
      prm.declare_entry(
        "Reordering cost",
        "1000",
        Patterns::Double(0),
        "cholmod: the fill-reducing ordering is CHOLMOD's choice (AMD on our "
        "matrices), whose deep elimination trees make row modifications "
        "expensive; nested dissection (METIS) makes them cheap but costs "
        "more to compute. Once the factorisations of one matrix pattern that "
        "'Row update limit' could not replace by row modifications have cost "
        "this many flops per stored matrix entry, the matrix is reordered by "
        "nested dissection (once per analysis, which a new mesh, time step or "
        "conductivity starts; only changes of fewer than a "
        "tenth of the rows count, as no ordering makes larger ones cheap). "
        "The default is what the "
        "analysis costs in factorisation flops (a timed build by hand, doc/performance.md): 48 ms for the 80 881 stored "
        "entries of the Stefan strip at nx = 400, whose factorisation of "
        "2.3e7 flops took 13 ms (2026-11-28, development VM). 0: never reorder by "
        "nested dissection ('Front layers ordered last' still orders the rows "
        "about a front last afresh).");
      prm.declare_entry("Front layers ordered last",
                        "2",
                        Patterns::Integer(0, 1000),
                        "cholmod: the rows an active set changes next are ordered after all "
                        "others (CAMD), when a matrix is first analysed and again whenever "
                        "they have moved away and a row modification became too expensive "
                        "('Row update limit'): the nodes a moving front fixes and frees are "
                        "then replaced at the end of the factor. Enthalpy step: the nodes of "
                        "a phase front (on a plateau, or next to a node of the same material "
                        "in another phase) and this many layers of matrix neighbours around "
                        "them. The Stefan strip took 8-12 % (nx = 400) and 10-16 % "
                        "(nx = 800) less time with 2 than with 0, Neumann case A at level 4 "
                        "14-15 % less, its adaptive run 4-6 % less; 1 and 3 layers measured "
                        "within 4 % of 2 (hand runs, doc/performance.md, 2026-11-28). 0: "
                        "CHOLMOD's own ordering, then "
                        "nested dissection ('Reordering cost').");
      prm.declare_entry("CG tolerance",
                        "1e-12",
                        Patterns::Double(0),
                        "Relative residual reduction of CG. Also the relative residual "
                        "(free rows) below which the displacement and the temperature the "
                        "fixed point's block correction hands the contact and the enthalpy "
                        "step are taken as their solutions, without a linear solve (on the "
                        "direct path too).");
      prm.declare_entry("AMG rebuild ratio",
                        "1.5",
                        Patterns::Double(1),
                        "An AMG hierarchy kept across active sets (recomputed on its "
                        "aggregates) is rebuilt from scratch when CG needs more than this "
                        "times (plus 0.5) the iterations per decade of residual reduction "
                        "of the first solve after the last build. Within a solve, CG on a hierarchy made "
                        "for other values (once that rate is measured) stops after 3 x this ratio x those "
                        "iterations per decade x the decades to go (at least 1) + 10, and goes on fresh.");
      prm.declare_entry("AMG update",
                        "automatic",
                        Patterns::Selection("automatic|reuse|recompute|rebuild"),
                        "What happens to an AMG hierarchy when only the active set (contact "
                        "or phase) changed the matrix: 'reuse' keeps it as the preconditioner "
                        "of the new matrix, 'recompute' recomputes it on its aggregates (about "
                        "half a build), 'rebuild' builds it afresh. Any of them is rebuilt "
                        "when CG slows down by 'AMG rebuild ratio', and CG that fails or "
                        "exceeds its budget on a kept one goes on with a fresh one. "
                        "'automatic': 'reuse' for the elasticity system (a contact set "
                        "changes boundary rows only: 24 % faster on the contact block at "
                        "N = 256, same CG time) and 'recompute' for the enthalpy system (a "
                        "phase front changes interior rows: 'reuse' was 12 % slower on the "
                        "Stefan strip at nx = 800); see doc/performance.md.");
      prm.declare_entry("Refactorisation backward error",
                        "1e-10",
                        Patterns::Double(0),
                        "A direct solve that reused the pivot order of an earlier "
                        "factorisation (KLU), or the first solve with a CHOLMOD factor modified "
                        "row by row, is accepted if |b - A x| <= this times "
                        "(|A| |x| + |b|) (max norms); otherwise the matrix is factorised "
                        "afresh with pivoting. Round-off is about 1e-16 times the growth.");
      prm.declare_entry("CG max iterations",
                        "1000",
                        Patterns::Integer(1, 100000),
                        "Iteration limit of CG; hitting it is an error. (At most 100000.)");
      prm.leave_subsection();
    }



    void LinearSolvers::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      const std::string solver = prm.get("Linear solver");
      linear_solver            = solver == "direct"    ? LinearSolverType::direct :
                                 solver == "automatic" ? LinearSolverType::automatic :
                                                         LinearSolverType::cg_amg;
      automatic_direct_limit   = prm.get_integer("Automatic direct limit");
      automatic_direct_limit_heat = prm.get_integer("Automatic direct limit for heat");
      direct_solver_type       = prm.get("Direct solver type");
      // (Without MPI, --check alone: one process.)
      const unsigned int n_ranks =
        Utilities::MPI::job_supports_mpi() ? Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) : 1;
      if (direct_solver_type == "cholmod")
        require(n_ranks == 1,
                "Solver/Direct solver type",
                "'cholmod' runs on one MPI rank only (this run has " + std::to_string(n_ranks) +
                  ")");
      else if (direct_solver_type != "automatic")
        require(Amesos().Query(direct_solver_type.c_str()),
                "Solver/Direct solver type",
                "'" + direct_solver_type + "' is not available in this Trilinos build");
      kept_factorisations = prm.get_integer("Kept factorisations");
      row_update_limit    = get_finite(prm, "Solver/", "Row update limit");
      reordering_cost     = get_finite(prm, "Solver/", "Reordering cost");
      front_layers_last   = prm.get_integer("Front layers ordered last");
      cg_tolerance        = get_finite(prm, "Solver/", "CG tolerance");
      amg_rebuild_ratio   = get_finite(prm, "Solver/", "AMG rebuild ratio");
      {
        const std::string update = prm.get("AMG update");
        amg_update               = update == "automatic" ? AMGUpdate::automatic :
                                   update == "reuse"     ? AMGUpdate::reuse :
                                   update == "recompute" ? AMGUpdate::recompute :
                                                           AMGUpdate::rebuild;
      }
      refactorisation_backward_error = get_finite(prm, "Solver/", "Refactorisation backward error");
      cg_max_iterations              = prm.get_integer("CG max iterations");
      prm.leave_subsection();
      require(cg_tolerance > 0 && cg_tolerance < 1, "Solver/CG tolerance", "must lie in (0, 1)");
      require(refactorisation_backward_error > 0 && refactorisation_backward_error < 1,
              "Solver/Refactorisation backward error",
              "must lie in (0, 1)");
    }
  } // namespace Parameters
} // namespace ContactStefan
