// The entries the enthalpy step reads (ThermalField::solve and its set-up):
// which method solves the step, its limits and tolerances, the line search,
// the relaxation fallback, and the enthalpy system's AMG settings. They sit
// in subsection 'Solver' beside the shared linear-solver entries
// (linear_algebra/linear_solver_parameters.h); doc/algorithms.md explains them.
#ifndef contact_stefan_enthalpy_step_parameters_h
#define contact_stefan_enthalpy_step_parameters_h

#include <deal.II/base/parameter_handler.h>

namespace ContactStefan
{
  using namespace dealii;

  namespace Parameters
  {
    /** The enthalpy step's solver settings (subsection 'Solver'). */
    struct EnthalpyStep
    {
      // The enthalpy step's CG tolerance while its set changes (0: tight).
      double cg_enthalpy_set_tolerance;
      // ML's aggregation threshold and smoother sweeps (Chebyshev degree).
      double       enthalpy_amg_threshold;
      unsigned int enthalpy_amg_sweeps;
      unsigned int max_active_set_iterations;
      // The active-set method's large-step mode: the solves after which a step
      // is handed over to the truncated Newton method, which then also solves
      // the following steps until one needs at most hand_back solves (0: the
      // hand-over only at max_active_set_iterations, for that step alone).
      unsigned int truncated_newton_hand_over, active_set_hand_back;
      enum class EnthalpySolver
      {
        active_set,
        truncated_newton,
        relaxation
      } enthalpy_solver;
      unsigned int gauss_seidel_sweeps;
      double       active_set_step_tolerance;
      double       line_search_sufficient_decrease;
      double       line_search_min_step;
      bool         extrapolate_active_set;
      double       relaxation_parameter_fraction;
      double       relaxation_tolerance;
      unsigned int relaxation_max_iterations;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };
  } // namespace Parameters
} // namespace ContactStefan

#endif
