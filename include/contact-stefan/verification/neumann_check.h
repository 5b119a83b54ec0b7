// The Neumann similarity solution as the verification part of a scene
// (Exact solution/Type = neumann, doc/benchmarks.md S1): built from the
// scene's parameters, checked against them before any work is done, and
// provided to the scene as its exact temperature. The core does not know it:
// the coupled problem hands the temperature to SceneFunctions and the
// solution to the Postprocessor.
#ifndef contact_stefan_neumann_check_h
#define contact_stefan_neumann_check_h

#include <deal.II/base/function.h>

#include <contact-stefan/core/parameters.h>
#include <contact-stefan/verification/neumann_solution.h>

#include <functional>
#include <memory>

namespace ContactStefan
{
  using namespace dealii;

  /** The Neumann solution of the exact-solution body's material. */
  NeumannSolution neumann_solution(const SceneParameters &prm);

  /**
   * What a Neumann scene requires of the rest of the file (one body with a
   * phase transition and isotropic conductivity, a rectangle beside the
   * origin, t0 > 0, boundary temperatures across the transitions) and that the
   * similarity solution exists; throws InputError naming the parameter.
   */
  void check_neumann_scene(const SceneParameters &prm);

  /**
   * The exact temperature Theta(x - origin, t) as fresh deal.II functions
   * (each user sets its own time); solution must outlive them.
   */
  template <int dim>
  std::function<std::unique_ptr<Function<dim>>()>
  neumann_temperature(const NeumannSolution &solution, const double origin);
} // namespace ContactStefan

#endif
