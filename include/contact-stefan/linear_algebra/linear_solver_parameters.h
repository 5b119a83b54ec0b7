// The entries of 'Solver' that every linear solve reads (LinearSolver): which
// solver, the direct back end and what it keeps, CG's tolerance and limit, and
// how an AMG hierarchy follows a changing matrix. The entries for one system
// (its AMG settings, its loose tolerance while an active set changes) belong
// to the field that owns the system: thermal/enthalpy_step_parameters.h,
// mechanics/contact_step_parameters.h.
#ifndef contact_stefan_linear_solver_parameters_h
#define contact_stefan_linear_solver_parameters_h

#include <deal.II/base/parameter_handler.h>

#include <string>

namespace ContactStefan
{
  using namespace dealii;

  namespace Parameters
  {
    /** The settings shared by every linear solve (subsection 'Solver'). */
    struct LinearSolvers
    {
      enum class LinearSolverType
      {
        automatic,
        direct,
        cg_amg
      } linear_solver;
      unsigned int automatic_direct_limit; // automatic: direct below this many unknowns
      // The same for the heat (enthalpy) system on one MPI rank (CHOLMOD):
      // a scalar system's factor fills far less per unknown.
      unsigned int automatic_direct_limit_heat;
      std::string  direct_solver_type;
      // cholmod: factorisations of earlier matrices kept for recall(), by key.
      unsigned int kept_factorisations;
      // cholmod: a factor is modified row by row (rowdel/rowadd) instead of
      // refactorised when the estimated work is below this fraction of a
      // factorisation's; 0: always refactorise.
      double row_update_limit;
      // cholmod: flops-equivalent per stored matrix entry of a nested-
      // dissection analysis; the factorisations row modifications could not
      // replace may cost this much before the matrix is reordered; 0: never.
      double reordering_cost;
      // Solver/Front layers ordered last (0: off).
      unsigned int front_layers_last;
      double       cg_tolerance;
      double       amg_rebuild_ratio;
      // What update() does to an AMG hierarchy when the matrix values change
      // in place: keep it as it is, recompute it on its aggregates, or build
      // it afresh; automatic: each system's measured choice (LinearSolver).
      enum class AMGUpdate
      {
        automatic,
        reuse,
        recompute,
        rebuild
      } amg_update;
      double       refactorisation_backward_error;
      unsigned int cg_max_iterations;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };
  } // namespace Parameters
} // namespace ContactStefan

#endif
