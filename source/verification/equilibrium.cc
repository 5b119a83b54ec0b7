// Part 'equilibrium' (Exact solution/Type = equilibrium, doc/benchmarks.md):
// an insulated system without sources tends to the uniform temperature T_f
// with sum_b |body b| H_b(T_f) = its initial enthalpy. The run reports T_f,
// how far the temperature is from it at the end, and the change of the total
// enthalpy.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/part.h>

#include <cmath>
#include <map>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct EquilibriumState
    {
      double initial_total_enthalpy = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &initial_total_enthalpy;
      }
    };

    template <int dim>
    class EquilibriumCheck : public PartWithState<dim, EquilibriumState>
    {
    public:
      using PartWithState<dim, EquilibriumState>::PartWithState;

      void update(const StepData &data) override
      {
        if (data.step == 0)
          this->state.initial_total_enthalpy = this->run.thermal->total_enthalpy();
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const RunContext<dim> &run = this->run;
        const double           E_0 = this->state.initial_total_enthalpy;
        // T_f from the body laws and the body areas alone (no nodal mixtures):
        // sum_b |body b| H_b(T_f) = E(0), by bisection on the monotone left side.
        std::map<unsigned int, double> area;
        for (const auto &cell : run.triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            area[cell->material_id()] += cell->measure();
        std::vector<std::pair<double, const EnthalpyLaw *>> bodies;
        for (const unsigned int id : run.scene.body_ids)
          bodies.emplace_back(Utilities::MPI::sum(area[id], run.mpi_communicator),
                              &run.materials[id].enthalpy_law);
        const auto total = [&](const double T) {
          double E = 0;
          for (const auto &[A, l] : bodies)
            E += A * l->enthalpy(T);
          return E;
        };
        double lo = -1, hi = 1;
        while (total(lo) > E_0)
          lo *= 2;
        while (total(hi) < E_0)
          hi *= 2;
        for (unsigned int i = 0; i < 200 && hi - lo > 0; ++i)
          {
            const double mid             = 0.5 * (lo + hi);
            (total(mid) < E_0 ? lo : hi) = mid;
          }
        const double  T_f         = 0.5 * (lo + hi);
        const Vector &temperature = run.thermal->get_temperature();
        double        deviation   = 0;
        for (const auto dof : run.thermal->get_dof_handler().locally_owned_dofs())
          deviation = max_with_nan(deviation, std::abs(temperature[dof] - T_f));
        const double E_end = run.thermal->total_enthalpy();
        const auto   add   = [&](const std::string &name, const double value) {
          results.add(ResultLines::Slot::equilibrium, name, value);
        };
        add("equilibrium temperature", T_f);
        add("max deviation from equilibrium temperature",
            global_max_with_nan(deviation, run.mpi_communicator));
        if (E_0 != 0)
          add("relative change of total enthalpy", std::abs(E_end - E_0) / std::abs(E_0));
        else
          add("change of total enthalpy", std::abs(E_end - E_0));
      }
    };
  } // namespace



  PartInfo equilibrium_part()
  {
    PartInfo info;
    info.name           = "equilibrium";
    info.exact_solution = true;
    info.description =
      "an insulated system without sources tends to the uniform temperature T_f with "
      "sum_b |body b| H_b(T_f) = its initial enthalpy; the run reports how far it is from T_f "
      "at the end.";
    info.parse = [](ParameterHandler &, const SceneParameters &scene, const bool chosen) {
      if (!chosen)
        return std::shared_ptr<const PartParameters>();
      for (const auto &[id, bc] : scene.thermal_boundaries)
        require(bc.type == Parameters::ThermalBoundary::Type::flux && is_zero_expression(bc.value),
                "Exact solution/Type",
                "'equilibrium' needs insulated boundaries (boundary " + std::to_string(id) +
                  " is not)");
      for (const auto &[id, m] : scene.materials)
        require(is_zero_expression(m.heat_source),
                "Exact solution/Type",
                "'equilibrium' needs no heat source (body " + std::to_string(id) + " has one)");
      require(scene.physics.thermal,
              "Exact solution/Type",
              "'equilibrium' needs Physics/Thermal = true");
      return std::make_shared<const PartParameters>();
    };
    info.create = part_factory<EquilibriumCheck>();
    return info;
  }
} // namespace ContactStefan
