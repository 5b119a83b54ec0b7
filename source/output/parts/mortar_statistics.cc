// Part 'mortar statistics' (scenes with a Discretisation = mortar interface,
// doc/contact.md): per mortar interface, which side is the slave, how many
// slave nodes carry a condition, how many slave-master segments were
// integrated, how much of the slave side faces no master edge, and the weight
// defect of the coupling over the run.
//
// The weight defect: the condition of slave node j pushes the slave side with
// -lambda_j n_j and, through the condensation, the master nodes with
// w_jm lambda_j n_j (w_jm = M_jm / D_j), in all sum_m w_jm lambda_j n_j. The
// largest |1 - sum_m w_jm| over the slave nodes and the steps is therefore the
// relative force imbalance the coupling itself introduces: round-off when the
// mortar integrals are consistent (D_j = sum_m M_jm), on any interface, curved
// or not. It checks the integrals on the run's own meshes; it does not see a
// force that another condition at the same node adds (such nodes are refused,
// MechanicalField::check_mortar_junctions).
//
// With large sliding (Mortar sliding = large) also how often the sides were
// coupled again and the largest relative change of the total enthalpy that a
// new coupling made: in perfect thermal contact the slave side's enthalpies
// are those its new masters interpolate (the slave surface takes the
// temperature of the master surface it now faces), which the energy balance
// of a step does not see, as with an adaptation. And the largest slide of a
// step (every step but the last, which is not followed): how far a slave
// node's facing point on the master mesh moved along the master side in one
// step, in the shortest master edge at the master nodes it is paired with. A
// step is paired at its start only, so a slide of more than an edge is
// linearised about a pairing the step has left: the first such step of a run
// (also across a restart) prints one warning line.
#include <deal.II/base/mpi.h>

#include <contact-stefan/output/part.h>

#include <cmath>
#include <iostream>
#include <stdexcept>
#include <string>

namespace ContactStefan
{
  namespace
  {
    struct MortarState
    {
      std::map<std::string, double> max_defect;
      unsigned int                  sliding_couplings  = 0;
      double                        max_sliding_change = 0;
      std::map<std::string, double> max_slide; // by interface, in master edges

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &max_defect &sliding_couplings &max_sliding_change &max_slide;
      }
    };

    template <int dim>
    class MortarStatistics : public PartWithState<dim, MortarState>
    {
    public:
      using PartWithState<dim, MortarState>::PartWithState;
      using Slot = ResultLines::Slot;

      // The coupling is built once per mesh (the summary holds its defect);
      // the largest over the meshes of the run is kept.
      void update(const StepData &) override
      {
        for (const auto &[group, summary] : this->run.mechanical->get_mortar_summary())
          {
            double &max = this->state.max_defect[group];
            max         = std::max(max, summary.weight_defect);
          }
      }

      void record_sliding(const unsigned int                   step,
                          const double                         relative_enthalpy_change,
                          const std::map<std::string, double> &slide) override
      {
        // One warning per run, also across a restart (the state is
        // checkpointed): the first step that slides more than an edge.
        double before = 0;
        for (const auto &[group, edges] : this->state.max_slide)
          before = std::max(before, edges);
        for (const auto &[group, edges] : slide)
          {
            if (edges > 1 && before <= 1 &&
                Utilities::MPI::this_mpi_process(this->run.mpi_communicator) == 0)
              std::cerr << "contact-stefan: warning: Contact/I" << group.substr(1)
                        << "/Mortar sliding: step " << step << " slid the sides by " << edges
                        << " master edges (the shortest at the nodes paired); a step is paired "
                           "at its start only, so a slide of more than an edge is linearised "
                           "about a pairing it has left: take smaller time steps"
                        << std::endl;
            before      = std::max(before, edges);
            double &max = this->state.max_slide[group];
            max         = std::max(max, edges);
          }
        if (!std::isfinite(relative_enthalpy_change))
          throw std::runtime_error("the total enthalpy is not finite after the sliding "
                                   "interfaces were coupled again before step " +
                                   std::to_string(this->state.sliding_couplings + 1));
        ++this->state.sliding_couplings;
        this->state.max_sliding_change =
          std::max(this->state.max_sliding_change, std::abs(relative_enthalpy_change));
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const MechanicalField<dim> &field = *this->run.mechanical;
        if (field.large_sliding())
          {
            results.add(Slot::mortar, "mortar sliding couplings", this->state.sliding_couplings);
            if (this->run.thermal)
              results.add(Slot::mortar,
                          "max relative enthalpy change through sliding",
                          this->state.max_sliding_change);
          }
        for (const auto &[group, summary] : field.get_mortar_summary())
          {
            results.add(Slot::mortar, "mortar slave body " + group, summary.slave_body);
            if (summary.large_sliding)
              {
                const auto it = this->state.max_slide.find(group);
                results.add(Slot::mortar,
                            "mortar max slide per step in master edges " + group,
                            it == this->state.max_slide.end() ? 0. : it->second);
              }
            results.add(Slot::mortar, "mortar slave nodes " + group, summary.slave_nodes);
            results.add(Slot::mortar, "mortar segments " + group, summary.segments);
            results.add(Slot::mortar,
                        "mortar uncovered slave length " + group,
                        summary.uncovered_length);
            const auto it = this->state.max_defect.find(group);
            results.add(Slot::mortar,
                        "mortar weight defect " + group,
                        it == this->state.max_defect.end() ? 0. : it->second);
          }
      }
    };
  } // namespace



  PartInfo mortar_statistics_part()
  {
    PartInfo info;
    info.name        = "mortar statistics";
    info.description =
      "Per mortar interface: the slave body, its slave nodes and segments, "
      "the slave length no master edge faces, and the largest |1 - sum_m "
      "M_jm / D_j| over the run, the coupling's own relative force imbalance; with "
      "large sliding the couplings, the enthalpy change they made and the "
      "largest slide of a step in master edges (warned above 1) (a "
      "'Discretisation' = mortar interface).";
    info.parse       = [](ParameterHandler &, const SceneParameters &scene, const bool) {
      bool any = false;
      for (const auto &[pair, law] : scene.interface_pairs)
        any = any || law.discretisation == Parameters::InterfacePair::Discretisation::mortar;
      return scene.physics.mechanics && any ? std::make_shared<const PartParameters>() : nullptr;
    };
    info.create = part_factory<MortarStatistics>();
    return info;
  }
} // namespace ContactStefan
