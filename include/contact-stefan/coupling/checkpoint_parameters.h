// Subsection 'Checkpoint': when the coupled problem writes a checkpoint and
// whether it resumes from one (coupling/coupled_problem.h, doc/adaptivity.md).
#ifndef contact_stefan_checkpoint_parameters_h
#define contact_stefan_checkpoint_parameters_h

#include <deal.II/base/parameter_handler.h>

namespace ContactStefan
{
  using namespace dealii;

  namespace Parameters
  {
    /** Checkpoint/restart (doc/adaptivity.md). */
    struct Checkpoint
    {
      unsigned int interval_steps;   // 0: none by step count
      double       interval_minutes; // 0: none by wall-clock time
      bool         resume;

      bool enabled() const
      {
        return interval_steps > 0 || interval_minutes > 0;
      }

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };
  } // namespace Parameters
} // namespace ContactStefan

#endif
