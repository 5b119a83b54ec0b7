// Part 'thermal statistics' (scenes with Physics/Thermal): the enthalpy step's
// columns of the statistics table, and its RESULT lines over the run:
// iterations, fallbacks, the energy balance, factorisations, the melt area
// and the nodes whose enthalpy ended outside H(Theta).
#include <contact-stefan/output/part.h>

namespace ContactStefan
{
  namespace
  {
    struct ThermalState
    {
      unsigned int total_active_set_iterations = 0, steps_with_fallback = 0;
      unsigned int steps_with_truncated_newton = 0, inconsistent_enthalpy_nodes = 0;
      unsigned int           enthalpy_factorisations = 0;
      double                 max_energy_residual     = 0;
      LinearSolverStatistics enthalpy_linear;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &total_active_set_iterations &steps_with_fallback &steps_with_truncated_newton
          &inconsistent_enthalpy_nodes &enthalpy_factorisations &max_energy_residual
            &enthalpy_linear;
      }
    };

    template <int dim>
    class ThermalStatistics : public PartWithState<dim, ThermalState>
    {
    public:
      using PartWithState<dim, ThermalState>::PartWithState;
      using Slot = ResultLines::Slot;

      void update(const StepData &data) override
      {
        ThermalState             &s      = this->state;
        const EnthalpyStepReport &report = data.thermal;
        s.total_active_set_iterations += report.active_set_iterations;
        s.steps_with_fallback += (report.relaxation_iterations > 0);
        s.steps_with_truncated_newton += report.truncated_newton;
        s.max_energy_residual = max_with_nan(s.max_energy_residual, report.energy_residual);
        s.inconsistent_enthalpy_nodes += report.inconsistent_nodes;
        s.enthalpy_factorisations += report.factorisations;
        s.enthalpy_linear += report.linear;
        // The melt area is collective: computed here, written by add_columns().
        melt_area = this->run.thermal->melt_area();
      }

      void add_columns(StatisticsRow &row, const StepData &data) const override
      {
        const EnthalpyStepReport &report = data.thermal;
        row.count("dofs",
                  "temperature degrees of freedom",
                  static_cast<unsigned int>(this->run.thermal->get_dof_handler().n_dofs()));
        row.count("pdas_iterations",
                  "active-set iterations (linear solves) of the enthalpy step",
                  report.active_set_iterations);
        row.count("state_changes",
                  "nodal phase-state changes, summed over the iterations",
                  report.state_changes);
        row.count("damped_steps",
                  "enthalpy iterations whose Newton step was shortened",
                  report.damped_steps);
        row.count("fallback_iterations",
                  "iterations of the relaxation fallback (0: not needed)",
                  report.relaxation_iterations);
        row.count("plateau_nodes",
                  "nodes on a transition plateau (mushy) at the end of the step",
                  report.plateau_nodes);
        row.real("liquid_area",
                 "m^2",
                 "melt area: lumped-mass weighted liquid fraction through the last transition, "
                 "per unit thickness",
                 "%.10e",
                 melt_area);
        row.real("energy_residual",
                 "1",
                 "enthalpy balance of the step relative to the size of its terms (doc/coupling.md "
                 "6)",
                 "%.2e",
                 report.energy_residual);
      }

      void
      add_results(ResultLines &results, const unsigned int n_steps, const double) const override
      {
        const ThermalState &s = this->state;
        results.add(Slot::thermal, "time steps", n_steps);
        results.add(Slot::thermal,
                    "temperature dofs",
                    this->run.thermal->get_dof_handler().n_dofs());
        results.add(Slot::thermal,
                    "mean active-set iterations",
                    n_steps > 0 ? double(s.total_active_set_iterations) / n_steps : 0.);
        results.add(Slot::thermal, "steps with relaxation fallback", s.steps_with_fallback);
        // Only where it ran: the active-set method's large-step mode or its
        // hand-over at its iteration limit, or 'Enthalpy solver = truncated-newton'.
        if (s.steps_with_truncated_newton > 0)
          results.add(Slot::thermal,
                      "steps solved by the truncated Newton method",
                      s.steps_with_truncated_newton);
        results.add(Slot::thermal, "max energy-balance residual", s.max_energy_residual);
        results.add(Slot::thermal, "enthalpy matrix factorisations", s.enthalpy_factorisations);
        results.add(Slot::thermal, "melt area", this->run.thermal->melt_area());
        // The iterative path's work, where it ran, and of the factorisations
        // above how many were modifications of an earlier factor row by row
        // (Solver/Row update limit). Not compared with a reference by the
        // regression tests ('... solver: ' lines).
        const LinearSolverStatistics &linear = s.enthalpy_linear;
        if (linear.cg_solves > 0)
          {
            results.add(Slot::thermal, "enthalpy solver: CG solves", linear.cg_solves);
            results.add(Slot::thermal,
                        "enthalpy solver: mean CG iterations per solve",
                        double(linear.cg_iterations) / linear.cg_solves);
          }
        if (linear.row_updates > 0)
          {
            results.add(Slot::thermal,
                        "enthalpy solver: CHOLMOD factorisations",
                        linear.cholmod_factorisations);
            results.add(Slot::thermal,
                        "enthalpy solver: factors modified row by row",
                        linear.row_updates);
            results.add(Slot::thermal,
                        "enthalpy solver: rows replaced",
                        static_cast<double>(linear.replaced_rows));
            results.add(Slot::thermal,
                        "enthalpy solver: reorderings (front last or nested dissection)",
                        linear.reorderings);
          }
        results.add(Slot::thermal_consistency,
                    "nodes with h outside H(Theta)",
                    s.inconsistent_enthalpy_nodes);
      }

      void add_failures(std::vector<std::string> &failed) const override
      {
        if (this->state.inconsistent_enthalpy_nodes > 0)
          failed.push_back(std::to_string(this->state.inconsistent_enthalpy_nodes) +
                           " node-steps ended with an enthalpy outside H(Theta) (must be 0; see "
                           "doc/algorithms.md): the enthalpy step did not converge to a solution");
      }

    private:
      double melt_area = 0;
    };
  } // namespace



  PartInfo thermal_statistics_part()
  {
    PartInfo info;
    info.name        = "thermal statistics";
    info.description = "The enthalpy step's columns and RESULT lines (Physics/Thermal).";
    info.parse       = [](ParameterHandler &, const SceneParameters &scene, const bool) {
      return scene.physics.thermal ? std::make_shared<const PartParameters>() : nullptr;
    };
    info.create = part_factory<ThermalStatistics>();
    return info;
  }
} // namespace ContactStefan
