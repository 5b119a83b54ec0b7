// Declaration and parsing of the enthalpy step's solver entries
// (thermal/enthalpy_step_parameters.h).
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/thermal/enthalpy_step_parameters.h>

namespace ContactStefan
{
  namespace Parameters
  {
    using namespace Input;

    void EnthalpyStep::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      prm.declare_entry("Enthalpy AMG aggregation threshold",
                        "1e-4",
                        Patterns::Double(0, 1),
                        "ML's 'aggregation: threshold' for the enthalpy system (deal.II's "
                        "default; the Stefan strip ladder of doc/performance.md was measured "
                        "with it).");
      prm.declare_entry("Enthalpy AMG smoother sweeps",
                        "1",
                        Patterns::Integer(1, 10),
                        "ML's 'smoother: sweeps' for the enthalpy system: the degree of the "
                        "Chebyshev smoother. The heat operator needs fewer: on the Stefan "
                        "strip at nx = 800, 1 took 8 % less wall time than deal.II's 2 "
                        "(31.3 s against 34.1 s, same results; commit 957f390, 2026-11-24, "
                        "2-core development VM; doc/performance.md).");
      prm.declare_entry("CG tolerance while the enthalpy set changes",
                        "1e-4",
                        Patterns::Double(0),
                        "Relative residual reduction of CG in the enthalpy step's "
                        "active-set iterations while the set of plateau nodes still "
                        "changes (after the first, or from the first where the warm "
                        "start moved nodes to another piece): such a solve only decides "
                        "the next set, so it runs on the AMG hierarchy at hand instead of "
                        "one recomputed for its matrix. The set it settles on is then "
                        "solved to 'CG tolerance' and checked again; a set that recurs "
                        "switches to tight solves. On the Stefan strip at nx = 800: 209 "
                        "AMG recomputations instead of 491, 29.8 s instead of 34.1 s with "
                        "the same smoother (40.0 s with two sweeps), the same results to "
                        "10 digits (commit 9779a99, 2026-11-24, 2-core development VM; "
                        "doc/performance.md). 0: every solve to 'CG "
                        "tolerance'. Unused by the direct solver.");
      prm.declare_entry("Max active-set iterations",
                        "50",
                        Patterns::Integer(1, 10000),
                        "Limit of linear solves per enthalpy step of the active-set iteration "
                        "and of the truncated Newton method. An active-set iteration that "
                        "reaches it hands the step to the truncated Newton method (and one "
                        "that the large-step mode handed over to it, back to the active-set "
                        "iteration); a step neither solves goes to the relaxation fallback. "
                        "(At most 10000.)");
      prm.declare_entry("Enthalpy solver",
                        "active-set",
                        Patterns::Selection("active-set|truncated-newton|relaxation"),
                        "'active-set': the primal-dual active-set (semismooth Newton) method "
                        "with an Armijo line search in h; should it reach 'Max active-set "
                        "iterations', the step is solved by the truncated Newton method, "
                        "then by the relaxation iteration. 'truncated-newton': nonlinear "
                        "Gauss-Seidel sweeps, a Newton step with the nodes at a transition "
                        "temperature held there, and an exact line search on the step's "
                        "convex functional in Theta; its solves per step do not grow with "
                        "tau/h^2 (the choice for large time steps and adaptive meshes, see "
                        "doc/algorithms.md); falls back to the relaxation iteration. "
                        "'relaxation': the nonlinear relaxation iteration alone (slow; a "
                        "baseline for comparisons).");
      prm.declare_entry("Truncated Newton hand-over",
                        "8",
                        Patterns::Integer(0, 10000),
                        "With 'Enthalpy solver = active-set': a step whose active-set "
                        "iteration has not converged in this many linear solves is solved by "
                        "the truncated Newton method (from the step's start), and so are the "
                        "following steps until one of them needs at most 'Active set "
                        "hand-back' solves. Where the front crosses several cells per step "
                        "(tau >> h^2/kappa, or the fine cells of an adaptive mesh) the "
                        "active-set iteration needs about two solves per crossed cell and "
                        "the truncated Newton method about five in all: on Neumann case A "
                        "at tau = 1000 h^2/kappa 5.53 solves per step instead of 17.27 "
                        "(doc/performance.md). Below 8 it also takes over steps of 300 h^2, "
                        "where the two methods cost the same. Every pass of a coupling loop "
                        "uses the method of the step's first pass. 0: the hand-over happens "
                        "only at 'Max active-set iterations', for that step alone.");
      prm.declare_entry("Active set hand-back",
                        "2",
                        Patterns::Integer(1, 10000),
                        "A step solved by the truncated Newton method after a hand-over "
                        "('Truncated Newton hand-over') in at most this many linear solves "
                        "(its first coupling pass) hands the following steps back to the "
                        "active-set method (the front then crosses about a cell per step or "
                        "less, where the active-set method needs fewer solves). Must be "
                        "below 'Truncated Newton hand-over'.");
      prm.declare_entry("Gauss-Seidel sweeps",
                        "1",
                        Patterns::Integer(0, 100),
                        "Nonlinear Gauss-Seidel sweeps before every Newton step but the "
                        "first of 'Enthalpy solver = truncated-newton'. They are what lets "
                        "a node leave a plateau. (At most 100.)");
      prm.declare_entry("Active-set step tolerance",
                        "1e-12",
                        Patterns::Double(0, 1),
                        "The active-set iteration also stops when a Newton step changes no "
                        "nodal enthalpy by more than this times (the largest |h| plus the "
                        "largest latent heat or heat capacity): the round-off level, reached "
                        "where the solution sits exactly on a kink of H.");
      prm.declare_entry("Line search sufficient decrease",
                        "1e-4",
                        Patterns::Double(0, 0.5),
                        "Armijo constant sigma of the line search that guards the "
                        "active-set (semismooth Newton) iteration against cycling: a step "
                        "is accepted when the step's convex functional falls by at least "
                        "sigma times the step length times its directional derivative.");
      prm.declare_entry("Line search minimum step",
                        "1e-6",
                        Patterns::Double(0, 1),
                        "The line search halves the Newton step at most down to this length.");
      prm.declare_entry("Extrapolate active set",
                        "true",
                        Patterns::Bool(),
                        "Start each step's active-set iteration from the phase states of "
                        "the nodal enthalpy extrapolated linearly in time (true) or from "
                        "the previous step's states (false).");
      prm.declare_entry("Relaxation parameter",
                        "1",
                        Patterns::Double(0),
                        "Fallback: nonlinear relaxation (Berger-Brezis-Rogers) with "
                        "alpha = this fraction of the smallest volumetric heat capacity; "
                        "it converges for values in (0, 1].");
      prm.declare_entry(
        "Relaxation tolerance",
        "1e-10",
        Patterns::Double(0),
        "Relaxation stops when the largest nodal residual of the step "
        "equations, |m_i (h_i - h_i^old) + tau (A Theta - F)_i|, falls below "
        "this times the largest |m_i (h_i - h_i^old)| + tau |F_i| + tau |(A Theta)_i|.");
      prm.declare_entry("Relaxation max iterations",
                        "2000",
                        Patterns::Integer(1, 100000),
                        "Relaxation iteration limit; hitting it is an error. (At most 100000: "
                        "the limit bounds the work of a step.)");
      prm.leave_subsection();
    }



    void EnthalpyStep::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Solver");
      enthalpy_amg_threshold = get_finite(prm, "Solver/", "Enthalpy AMG aggregation threshold");
      enthalpy_amg_sweeps    = prm.get_integer("Enthalpy AMG smoother sweeps");
      cg_enthalpy_set_tolerance =
        get_finite(prm, "Solver/", "CG tolerance while the enthalpy set changes");
      max_active_set_iterations  = prm.get_integer("Max active-set iterations");
      truncated_newton_hand_over = prm.get_integer("Truncated Newton hand-over");
      active_set_hand_back       = prm.get_integer("Active set hand-back");
      {
        const std::string solver = prm.get("Enthalpy solver");
        enthalpy_solver          = solver == "relaxation"       ? EnthalpySolver::relaxation :
                                   solver == "truncated-newton" ? EnthalpySolver::truncated_newton :
                                                                  EnthalpySolver::active_set;
      }
      gauss_seidel_sweeps       = prm.get_integer("Gauss-Seidel sweeps");
      active_set_step_tolerance = get_finite(prm, "Solver/", "Active-set step tolerance");
      line_search_sufficient_decrease =
        get_finite(prm, "Solver/", "Line search sufficient decrease");
      line_search_min_step          = get_finite(prm, "Solver/", "Line search minimum step");
      extrapolate_active_set        = prm.get_bool("Extrapolate active set");
      relaxation_parameter_fraction = get_finite(prm, "Solver/", "Relaxation parameter");
      relaxation_tolerance          = get_finite(prm, "Solver/", "Relaxation tolerance");
      relaxation_max_iterations     = prm.get_integer("Relaxation max iterations");
      prm.leave_subsection();
      require(cg_enthalpy_set_tolerance >= 0 && cg_enthalpy_set_tolerance < 1,
              "Solver/CG tolerance while the enthalpy set changes",
              "must lie in [0, 1)");
      require(truncated_newton_hand_over == 0 || active_set_hand_back < truncated_newton_hand_over,
              "Solver/Active set hand-back",
              "must be below 'Solver/Truncated Newton hand-over' = " +
                std::to_string(truncated_newton_hand_over) +
                " (or the methods would trade every step)");
      require(relaxation_parameter_fraction > 0 && relaxation_parameter_fraction <= 1,
              "Solver/Relaxation parameter",
              "must lie in (0, 1]");
      require(relaxation_tolerance > 0, "Solver/Relaxation tolerance", "must be > 0");
      require(line_search_sufficient_decrease > 0 && line_search_sufficient_decrease < 0.5,
              "Solver/Line search sufficient decrease",
              "must lie in (0, 0.5)");
      require(line_search_min_step > 0 && line_search_min_step < 1,
              "Solver/Line search minimum step",
              "must lie in (0, 1)");
    }
  } // namespace Parameters
} // namespace ContactStefan
