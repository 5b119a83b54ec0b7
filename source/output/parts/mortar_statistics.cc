// Part 'mortar statistics' (scenes with a Discretisation = mortar interface,
// doc/contact.md): per mortar interface, which side is the slave, how many
// slave nodes carry a condition, how many slave-master segments were
// integrated, how much of the slave side faces no master edge, and the force
// balance of the coupling over the run.
//
// The force balance: the condition of slave node j pushes the slave side with
// -lambda_j n_j (lambda_j = D_j p_j, the nodal force) and, through the
// condensation, each master node m with +w_jm lambda_j n_j (w_jm = M_jm /
// D_j). Their sum is -sum_j lambda_j n_j (1 - sum_m w_jm): zero exactly when
// the mortar integrals are consistent (D_j = sum_m M_jm), on any interface,
// curved or not. Reported as the largest |F_slave + F_master| / |F_slave|
// over the steps (0 while nothing presses).
#include <boost/serialization/map.hpp>
#include <boost/serialization/string.hpp>

#include <contact-stefan/output/part.h>

#include <cmath>

namespace ContactStefan
{
  namespace
  {
    struct MortarState
    {
      std::map<std::string, double> max_imbalance;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &max_imbalance;
      }
    };

    template <int dim>
    class MortarStatistics : public PartWithState<dim, MortarState>
    {
    public:
      using PartWithState<dim, MortarState>::PartWithState;
      using Slot = ResultLines::Slot;

      void update(const StepData &) override
      {
        const MechanicalField<dim> &field = *this->run.mechanical;
        const auto                 &owned = field.get_dof_handler().locally_owned_dofs();
        for (const auto &[group, summary] : field.get_mortar_summary())
          {
            // F_slave (x, y), F_master (x, y) on this rank.
            std::vector<double> forces(4, 0.);
            for (const auto &c : field.get_normal_conditions())
              if (c.mortar && c.group == group && owned.is_element(c.dofs_k[0]))
                {
                  const double lambda = field.contact_pressure(c) * c.weight;
                  double       w_sum  = 0;
                  for (const auto &[dofs, w] : c.masters)
                    w_sum += w;
                  for (unsigned int d = 0; d < dim; ++d)
                    {
                      forces[d] -= lambda * c.normal[d];
                      forces[dim + d] += w_sum * lambda * c.normal[d];
                    }
                }
            Utilities::MPI::sum(forces, this->run.mpi_communicator, forces);
            const double slave = std::hypot(forces[0], forces[1]);
            const double sum   = std::hypot(forces[0] + forces[2], forces[1] + forces[3]);
            double      &max   = this->state.max_imbalance[group];
            if (slave > 0)
              max = std::max(max, sum / slave);
          }
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const MechanicalField<dim> &field = *this->run.mechanical;
        const auto                 &owned = field.get_dof_handler().locally_owned_dofs();
        for (const auto &[group, summary] : field.get_mortar_summary())
          {
            unsigned int nodes = 0;
            for (const auto &c : field.get_normal_conditions())
              nodes += c.mortar && c.group == group && owned.is_element(c.dofs_k[0]);
            results.add(Slot::mortar, "mortar slave body " + group, summary.slave_body);
            results.add(Slot::mortar,
                        "mortar slave nodes " + group,
                        Utilities::MPI::sum(nodes, this->run.mpi_communicator));
            results.add(Slot::mortar, "mortar segments " + group, summary.segments);
            results.add(Slot::mortar,
                        "mortar uncovered slave length " + group,
                        summary.uncovered_length);
            const auto it = this->state.max_imbalance.find(group);
            results.add(Slot::mortar,
                        "mortar force balance " + group,
                        it == this->state.max_imbalance.end() ? 0. : it->second);
          }
      }
    };
  } // namespace



  PartInfo mortar_statistics_part()
  {
    PartInfo info;
    info.name        = "mortar statistics";
    info.description = "Per mortar interface: the slave body, its slave nodes and segments, "
                       "the slave length no master edge faces, and the largest relative force "
                       "imbalance of the coupling over the run (a 'Discretisation' = mortar "
                       "interface).";
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
