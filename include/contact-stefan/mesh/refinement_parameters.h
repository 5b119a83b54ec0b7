// Subsection 'Mesh refinement': the initial mesh's refinement and the
// adaptive refinement during the run (mesh/mesh.h, mesh/mesh_adaptation.h,
// doc/adaptivity.md).
#ifndef contact_stefan_refinement_parameters_h
#define contact_stefan_refinement_parameters_h

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

namespace ContactStefan
{
  using namespace dealii;

  namespace Parameters
  {
    struct Refinement
    {
      unsigned int initial_global_refinements;
      // Geometric pre-refinement: after the global refinements, refine the cells
      // whose centre lies within radius of center, this many times.
      Point<2>     prerefinement_center;
      double       prerefinement_radius;
      unsigned int prerefinement_steps;
      unsigned int max_cells;

      // Adaptive refinement during the time loop (doc/adaptivity.md).
      enum class Strategy
      {
        fixed_fraction,
        fixed_number
      };
      unsigned int adaptive_interval; // steps; 0: the mesh stays fixed
      unsigned int initial_adaptive_refinements;
      Strategy     strategy;
      double       refine_fraction, coarsen_fraction;
      unsigned int min_level, max_level; // min_level is resolved against the global refinements
      double       temperature_weight, displacement_weight;
      bool         mark_fronts, mark_contact;
      unsigned int front_buffer, contact_buffer; // in cells
      // in finest cells; 0: adapt at every interval
      unsigned int front_margin;
      unsigned int longest_wait; // in intervals, with a front margin

      bool adaptive() const
      {
        return adaptive_interval > 0 || initial_adaptive_refinements > 0;
      }

      static void declare(ParameterHandler &prm);
      void        parse(ParameterHandler &prm);
    };
  } // namespace Parameters
} // namespace ContactStefan

#endif
