// Part 'mesh statistics' (scenes whose mesh adapts): the cells and the
// enthalpy change of the last adaptation as columns, and over the run the
// adaptations, the time-averaged DoFs and the largest enthalpy changes through
// refinement and through coarsening.
#include <contact-stefan/mesh/refinement_parameters.h>
#include <contact-stefan/output/part.h>

namespace ContactStefan
{
  namespace
  {
    struct MeshState
    {
      // The number of adaptations, the largest enthalpy changes through pure
      // refinement and through adaptations that coarsened, the change of the
      // adaptation before the next statistics row, and the integral of the
      // number of DoFs over time (the time-averaged DoFs) since start_time.
      unsigned int n_adaptations         = 0;
      double       max_refinement_change = 0, max_coarsening_change = 0, pending_change = 0;
      double       dof_time_integral = 0, start_time = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &n_adaptations &max_refinement_change &max_coarsening_change &pending_change
          &dof_time_integral &start_time;
      }
    };

    template <int dim>
    class MeshStatistics : public PartWithState<dim, MeshState>
    {
    public:
      using PartWithState<dim, MeshState>::PartWithState;
      using Slot = ResultLines::Slot;

      void update(const StepData &data) override
      {
        const RunContext<dim> &run = this->run;
        if (data.step == 0)
          this->state.start_time = data.time;
        this->state.dof_time_integral +=
          data.time_step *
          (run.thermal ? run.thermal->get_dof_handler() : run.mechanical->get_dof_handler())
            .n_dofs();
      }

      void record_adaptation(const double relative_enthalpy_change, const bool coarsened) override
      {
        MeshState &s = this->state;
        if (!std::isfinite(relative_enthalpy_change))
          throw std::runtime_error("the total enthalpy is not finite after mesh adaptation " +
                                   std::to_string(s.n_adaptations + 1));
        ++s.n_adaptations;
        s.pending_change = relative_enthalpy_change;
        double &largest  = coarsened ? s.max_coarsening_change : s.max_refinement_change;
        largest          = std::max(largest, std::abs(relative_enthalpy_change));
      }

      void add_columns(StatisticsRow &row, const StepData &) const override
      {
        row.count("cells",
                  "active cells",
                  static_cast<unsigned int>(this->run.triangulation.n_global_active_cells()));
        row.real("adapt_enthalpy_change",
                 "1",
                 "relative change of sum m_i h_i by the adaptation before the step",
                 "%.2e",
                 this->state.pending_change);
      }

      void write(const StepData &) override
      {
        this->state.pending_change = 0;
      }

      void add_results(ResultLines &results, const unsigned int, const double time) const override
      {
        const MeshState &s = this->state;
        results.add(Slot::adaptation,
                    "final cells",
                    this->run.triangulation.n_global_active_cells());
        results.add(Slot::adaptation, "mesh adaptations", s.n_adaptations);
        if (time > s.start_time)
          results.add(Slot::adaptation,
                      "time-averaged dofs",
                      s.dof_time_integral / (time - s.start_time));
        results.add(Slot::adaptation,
                    "max relative enthalpy change through refinement",
                    s.max_refinement_change);
        results.add(Slot::adaptation,
                    "max relative enthalpy change through coarsening",
                    s.max_coarsening_change);
      }
    };
  } // namespace



  PartInfo mesh_statistics_part()
  {
    PartInfo info;
    info.name        = "mesh statistics";
    info.description = "The adaptive mesh's columns and RESULT lines (Mesh refinement/Adaptive "
                       "refinement interval > 0 or Initial adaptive refinements > 0).";
    // The mesh adapts as the refinement's own entries say (the run's context
    // holds the same answer: RunContext::adaptive).
    info.parse = [](ParameterHandler &prm, const SceneParameters &, const bool) {
      Parameters::Refinement refinement;
      refinement.parse(prm);
      return refinement.adaptive() ? std::make_shared<const PartParameters>() : nullptr;
    };
    info.create = [](const RunContext<2> &run, const PartParameters &) {
      AssertThrow(run.adaptive, ExcInternalError());
      return std::unique_ptr<Part<2>>(std::make_unique<MeshStatistics<2>>(run));
    };
    return info;
  }
} // namespace ContactStefan
