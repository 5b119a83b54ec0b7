// Helpers of the field-level tests: a scene read from a parameter file, its mesh
// and the objects a field needs, without CoupledProblem, so that each field can
// be driven through its step contract alone.
#ifndef contact_stefan_field_test_tools_h
#define contact_stefan_field_test_tools_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/scene_functions.h>
#include <contact-stefan/coupling/all_parameters.h>
#include <contact-stefan/mesh/mesh.h>

#include <iostream>
#include <memory>
#include <string>

namespace FieldTest
{
  using namespace ContactStefan;
  using Vector = ContactStefan::Vector;

  // Everything the fields share, for one parameter file. `adjust` may change the
  // parameters after reading (e.g. the refinement level) and before use.
  struct Scene
  {
    template <typename Adjust>
    Scene(const std::string &filename, const Adjust &adjust)
      : pcout(std::cout, false)
      , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
      , triangulation(MPI_COMM_WORLD)
    {
      prm.read(filename);
      adjust(prm);
      materials = std::make_unique<Materials>(prm);
      functions = std::make_unique<SceneFunctions<2>>(prm, prm.exact_temperature());
      make_mesh(prm, prm.refinement, triangulation);
    }

    // The context the fields and parts take (core/scene_context.h).
    SceneContext<2> context()
    {
      return {prm, *materials, *functions, triangulation, timer, pcout, prm.output.verbosity};
    }

    AllParameters                           prm;
    ConditionalOStream                      pcout;
    TimerOutput                             timer;
    parallel::distributed::Triangulation<2> triangulation;
    std::unique_ptr<Materials>              materials;
    std::unique_ptr<SceneFunctions<2>>      functions;
  };

  // max_i |a_i - b_i| and max_i |a_i| over the owned entries, on every rank
  // (a NaN wins: core/common.h).
  using ContactStefan::max_abs;
  using ContactStefan::max_difference;
} // namespace FieldTest

#endif
