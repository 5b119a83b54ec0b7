// The entries the contact step reads (MechanicalField::solve and its set-up):
// the primal-dual active-set method's constant, limits and guards in
// subsection 'Contact', and the elasticity system's AMG settings and loose CG
// tolerance in subsection 'Solver'. What an interface is (contact or tied, its
// gap) is the scene's (core/parameters.h); doc/contact.md explains the method.
#ifndef contact_stefan_contact_step_parameters_h
#define contact_stefan_contact_step_parameters_h

#include <deal.II/base/parameter_handler.h>

namespace ContactStefan
{
  using namespace dealii;

  namespace Parameters
  {
    /** The contact step's solver settings (subsections 'Contact' and 'Solver'). */
    struct ContactStep
    {
      double       complementarity_constant;
      unsigned int max_iterations;
      double       tolerance;
      unsigned int max_set_repetitions;
      unsigned int max_c_reductions;
      double       rigid_mode_tolerance;
      double       corner_angle; // degrees: where a roller boundary has a corner
      double       cg_contact_set_tolerance;
      // ML's aggregation threshold and smoother sweeps (Chebyshev degree).
      double       elasticity_amg_threshold;
      unsigned int elasticity_amg_sweeps;
      // Contact-set changes an elasticity AMG hierarchy is kept across before
      // it is recomputed on its aggregates (0: no limit).
      unsigned int elasticity_amg_reuse_limit;

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };
  } // namespace Parameters
} // namespace ContactStefan

#endif
