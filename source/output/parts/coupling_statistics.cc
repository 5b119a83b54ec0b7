// Part 'coupling statistics' (scenes with both fields): the coupling's columns
// of the statistics table (passes per step, thermoelastic heat, cells
// re-stiffened for a phase change) and its RESULT lines over the run.
#include <contact-stefan/output/part.h>

namespace ContactStefan
{
  namespace
  {
    struct CouplingState
    {
      unsigned int total_iterations = 0, max_iterations = 0, reassembled_cells = 0;
      double       total_thermoelastic_heat = 0;
      // The block correction: whether the run has one, and its counts over the
      // run (carried over a restart, as every count of the report).
      bool         block_correction     = false;
      unsigned int block_corrections    = 0;
      unsigned int block_factorisations = 0;
      unsigned int block_ldlt            = 0;
      unsigned int guesses_accepted     = 0;
      unsigned int heat_guesses_accepted = 0;
      // Material points born anew (solidification history), over the run.
      unsigned int births = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &total_iterations &max_iterations &reassembled_cells &total_thermoelastic_heat
          &block_correction &block_corrections &block_factorisations &block_ldlt &guesses_accepted
            &heat_guesses_accepted &births;
      }
    };

    template <int dim>
    class CouplingStatistics : public PartWithState<dim, CouplingState>
    {
    public:
      using PartWithState<dim, CouplingState>::PartWithState;
      using Slot = ResultLines::Slot;

      void update(const StepData &data) override
      {
        CouplingState &s = this->state;
        s.total_iterations += data.coupling.iterations;
        s.max_iterations = std::max(s.max_iterations, data.coupling.iterations);
        s.reassembled_cells += data.coupling.reassembled_cells;
        s.total_thermoelastic_heat += data.thermal.thermoelastic_heat;
        s.block_correction |= data.coupling.block_correction;
        s.block_corrections += data.coupling.block_corrections;
        s.block_factorisations += data.coupling.block_factorisations;
        s.block_ldlt += data.coupling.block_ldlt;
        s.guesses_accepted += data.coupling.guesses_accepted;
        s.heat_guesses_accepted += data.coupling.heat_guesses_accepted;
        s.births += data.coupling.births;
      }

      void add_columns(StatisticsRow &row, const StepData &data) const override
      {
        row.count("coupling_iterations",
                  "passes of contact and enthalpy step (1: staggered)",
                  data.coupling.iterations);
        row.real("thermoelastic_heat",
                 "J/m",
                 "heat released by the step's strain increment, per unit thickness (> 0 under "
                 "compression)",
                 "%.10e",
                 data.thermal.thermoelastic_heat);
        row.count("restiffened_cells",
                  "cells whose stiffness was re-assembled for a phase change",
                  data.coupling.reassembled_cells);
        if (this->run.scene.solidification_history_active())
          row.count("births",
                    "material points (cell corners) born anew at the step's start: frozen or "
                    "molten over the step before (doc/solidification.md)",
                    data.coupling.births);
      }

      void
      add_results(ResultLines &results, const unsigned int n_steps, const double) const override
      {
        const CouplingState &s = this->state;
        results.add(Slot::coupling, "max coupling iterations", s.max_iterations);
        results.add(Slot::coupling,
                    "mean coupling iterations",
                    n_steps > 0 ? double(s.total_iterations) / n_steps : 0.);
        results.add(Slot::coupling, "total thermoelastic heat", s.total_thermoelastic_heat);
        results.add(Slot::coupling, "cells re-stiffened for a phase change", s.reassembled_cells);
        if (this->run.scene.solidification_history_active())
          results.add(Slot::coupling, "material points born", s.births);
        if (s.block_correction)
          {
            results.add(Slot::block_correction, "block corrections", s.block_corrections);
            results.add(Slot::block_correction, "block factorisations", s.block_factorisations);
            results.add(Slot::block_correction,
                        "block factorisations by LDLT (constant Theta_0)",
                        s.block_ldlt);
            results.add(Slot::block_correction,
                        "elasticity solves answered by the corrected guess",
                        s.guesses_accepted);
            results.add(Slot::block_correction,
                        "heat solves answered by the corrected guess",
                        s.heat_guesses_accepted);
          }
      }
    };
  } // namespace



  PartInfo coupling_statistics_part()
  {
    PartInfo info;
    info.name        = "coupling statistics";
    info.description = "The coupling's columns and RESULT lines (Physics/Thermal and Mechanics).";
    info.parse       = [](ParameterHandler &, const SceneParameters &scene, const bool) {
      return scene.physics.thermal && scene.physics.mechanics ?
                     std::make_shared<const PartParameters>() :
                     nullptr;
    };
    info.create = part_factory<CouplingStatistics>();
    return info;
  }
} // namespace ContactStefan
