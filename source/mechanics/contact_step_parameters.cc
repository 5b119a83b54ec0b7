// Declaration and parsing of the contact step's solver entries
// (mechanics/contact_step_parameters.h).
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/mechanics/contact_step_parameters.h>

namespace ContactStefan
{
  namespace Parameters
  {
    using namespace Input;

    void ContactStep::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      prm.declare_entry("Complementarity constant",
                        "1",
                        Patterns::Double(0),
                        "c of the active-set test lambda + c d > 0, in units of the diagonal "
                        "stiffness of the node's normal displacement (so 1 balances force and "
                        "gap); > 0. The fixed point does not depend on it.");
      prm.declare_entry("Max iterations",
                        "50",
                        Patterns::Integer(1, 10000),
                        "Limit of active-set iterations per contact step; reaching it is an error. "
                        "(At most 10000.)");
      prm.declare_entry("Tolerance",
                        "1e-10",
                        Patterns::Double(0),
                        "Activity test threshold, relative to the largest |lambda| + c |d| of "
                        "the step: guards against round-off flipping grazing nodes. A converged "
                        "set whose nodes violate the contact conditions (c at full size) by more "
                        "than 10 times this is an error.");
      prm.declare_entry("Roller corner angle",
                        "20",
                        Patterns::Double(0, 90),
                        "A roller vertex whose face normals differ from their average by more "
                        "than this (degrees) is a corner of the roller boundary: both "
                        "displacement components are fixed there.");
      prm.declare_entry("Rigid mode tolerance",
                        "1e-10",
                        Patterns::Double(0),
                        "Before each contact solve every body must be held against rigid "
                        "motion by its constraints (incl. the active contact set): the "
                        "smallest pivot of the Gram matrix of the rigid modes' constraint "
                        "residuals (modes scaled to unit size) must exceed this; else the "
                        "run stops with a message naming the body and the free motion.");
      prm.declare_entry(
        "Max c reductions",
        "6",
        Patterns::Integer(0, 30),
        "How often per step the cycling remedy may divide c by ten before the "
        "step is declared failed. c starts at full size in every step. (At most 30.)");
      prm.declare_entry(
        "Max set repetitions",
        "1",
        Patterns::Integer(1, 100),
        "Cycling guard: when an active set recurs this often, c is divided by "
        "ten (the dual update then dominates) and the count restarts. (At most 100.)");
      prm.leave_subsection();
      prm.enter_subsection("Solver");
      prm.declare_entry("Elasticity AMG aggregation threshold",
                        "0",
                        Patterns::Double(0, 1),
                        "ML's 'aggregation: threshold' for the elasticity system: matrix "
                        "entries weaker than this (relative to the diagonal) do not join "
                        "nodes in one aggregate. 0 aggregates over every entry: on the "
                        "contact block at N = 256, 82 CG iterations and 0.79 s of AMG builds "
                        "against 88 and 0.92 s with deal.II's 1e-4 (doc/performance.md).");
      prm.declare_entry("Elasticity AMG smoother sweeps",
                        "2",
                        Patterns::Integer(1, 10),
                        "ML's 'smoother: sweeps' for the elasticity system: the degree of "
                        "the Chebyshev smoother before and after each coarse correction "
                        "(deal.II's default).");
      prm.declare_entry("Elasticity AMG reuse limit",
                        "16",
                        Patterns::Integer(0),
                        "With 'AMG update' = reuse for the elasticity system (and automatic): "
                        "the number of contact-set changes (conditions entering or leaving "
                        "the active set) an AMG hierarchy is kept across before it is "
                        "recomputed on its aggregates for the current set. A hierarchy kept "
                        "across m changed rows costs CG a number of extra iterations that "
                        "grows with m, not with the mesh: a limit independent of the mesh "
                        "keeps CG iterations per solve bounded as it is refined, where a "
                        "set change can grow with the mesh (on the contact block the first "
                        "one after the cold start activates half the floor nodes: at most "
                        "16 CG iterations per solve for N = 32 ... 1024, against 18 ... 47 "
                        "without the limit; doc/performance.md). 0: no limit.");
      prm.declare_entry("CG tolerance while the contact set changes",
                        "1e-6",
                        Patterns::Double(0),
                        "Relative residual reduction of CG in the contact step's "
                        "active-set iterations before the set has settled (the "
                        "set's next guess needs only the sign pattern of the "
                        "solution); the settled set is then solved to 'CG "
                        "tolerance' and checked again. On the contact block of "
                        "doc/performance.md (N = 256) it saves half the CG "
                        "iterations. Unused by the direct solver.");
      prm.leave_subsection();
    }



    void ContactStep::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Contact");
      complementarity_constant = get_finite(prm, "Contact/", "Complementarity constant");
      max_iterations           = prm.get_integer("Max iterations");
      tolerance                = get_finite(prm, "Contact/", "Tolerance");
      max_set_repetitions      = prm.get_integer("Max set repetitions");
      max_c_reductions         = prm.get_integer("Max c reductions");
      rigid_mode_tolerance     = get_finite(prm, "Contact/", "Rigid mode tolerance");
      corner_angle             = get_finite(prm, "Contact/", "Roller corner angle");
      prm.leave_subsection();
      require(complementarity_constant > 0, "Contact/Complementarity constant", "must be > 0");

      prm.enter_subsection("Solver");
      elasticity_amg_threshold = get_finite(prm, "Solver/", "Elasticity AMG aggregation threshold");
      elasticity_amg_sweeps    = prm.get_integer("Elasticity AMG smoother sweeps");
      elasticity_amg_reuse_limit = prm.get_integer("Elasticity AMG reuse limit");
      cg_contact_set_tolerance =
        get_finite(prm, "Solver/", "CG tolerance while the contact set changes");
      prm.leave_subsection();
      require(cg_contact_set_tolerance > 0 && cg_contact_set_tolerance < 1,
              "Solver/CG tolerance while the contact set changes",
              "must lie in (0, 1)");
    }
  } // namespace Parameters
} // namespace ContactStefan
