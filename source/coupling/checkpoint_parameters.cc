// Declaration and parsing of 'Checkpoint' (coupling/checkpoint_parameters.h).
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/coupling/checkpoint_parameters.h>

namespace ContactStefan
{
  namespace Parameters
  {
    using namespace Input;

    void Checkpoint::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Checkpoint");
      prm.declare_entry("Interval (steps)",
                        "0",
                        Patterns::Integer(0),
                        "Write a checkpoint (mesh, primary state, time, statistics, "
                        "accumulated errors, output records) into Output/Directory/checkpoint "
                        "after every this many steps; 0: not by step count.");
      prm.declare_entry("Interval (minutes)",
                        "0",
                        Patterns::Double(0),
                        "... and/or whenever this much wall-clock time has passed since the "
                        "last one; 0: not by time. A checkpoint is written to a new directory "
                        "and then renamed, so a crash while writing leaves the previous one.");
      prm.declare_entry("Resume",
                        "false",
                        Patterns::Bool(),
                        "Continue from the checkpoint in Output/Directory (the same as the "
                        "command-line option --resume): statistics and PVD records are kept up "
                        "to the checkpoint and appended to.");
      prm.leave_subsection();
    }

    void Checkpoint::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Checkpoint");
      interval_steps   = prm.get_integer("Interval (steps)");
      interval_minutes = get_finite(prm, "Checkpoint/", "Interval (minutes)");
      resume           = prm.get_bool("Resume");
      prm.leave_subsection();
    }
  } // namespace Parameters
} // namespace ContactStefan
