// What every physics of a run shares, in one object (ASPECT's SimulatorAccess
// is the model): the scene, its materials and functions, the mesh, the timer,
// the screen and how much it says. The coupled problem (or a test) owns the
// objects and hands each field and each part of the report this context; a
// field reads its own parameter subsection beside it, and time and step size
// through its step contract (begin_time_step).
#ifndef contact_stefan_scene_context_h
#define contact_stefan_scene_context_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/parameters.h>
#include <contact-stefan/core/scene_functions.h>

namespace ContactStefan
{
  template <int dim>
  struct SceneContext
  {
    const SceneParameters                           &scene;
    const Materials                                 &materials;
    SceneFunctions<dim>                             &functions;
    const parallel::distributed::Triangulation<dim> &triangulation;
    TimerOutput                                     &timer;
    const ConditionalOStream                        &pcout;
    /** Output/Verbosity: 0 quiet, 1 a line per step, 2 per iteration. */
    unsigned int verbosity;
  };
} // namespace ContactStefan

#endif
