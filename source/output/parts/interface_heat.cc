// Part 'interface heat' (scenes with a conductance interface,
// doc/interface_heat.md): per conductance interface, the heat rate from side
// k to side l, its terms (constant, contact, gas, radiation, function) where a
// term is present, the mean conductance, and the heat that crossed since t0.
// The rate is the one the step used: sum over the interface nodes of
// w h (Theta_k - Theta_l) at the end of the step, so that tau times it is
// exactly the heat the implicit step moved across.
#include <contact-stefan/output/part.h>

#include <algorithm>

namespace ContactStefan
{
  namespace
  {
    struct InterfaceHeatState
    {
      std::vector<double> crossed; // J/m since t0, per conductance interface

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &crossed;
      }
    };

    std::string column_name(const std::string &interface, const std::string &what)
    {
      std::string name = what + "_" + interface;
      std::replace(name.begin(), name.end(), ' ', '_');
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    }

    template <int dim>
    class InterfaceHeatPart : public PartWithState<dim, InterfaceHeatState>
    {
    public:
      using PartWithState<dim, InterfaceHeatState>::PartWithState;
      using Slot = ResultLines::Slot;

      void update(const StepData &data) override
      {
        heat          = this->run.thermal->interface_heat();
        auto &crossed = this->state.crossed;
        crossed.resize(heat.size(), 0.);
        for (unsigned int i = 0; i < heat.size(); ++i)
          crossed[i] += data.time_step * heat[i].rate;
      }

      void add_columns(StatisticsRow &row, const StepData &) const override
      {
        for (unsigned int i = 0; i < heat.size(); ++i)
          {
            const InterfaceHeat &h = heat[i];
            row.real(column_name(h.name, "heat_rate"),
                     "W/m",
                     "heat rate from the lower to the higher body id across '" + h.name +
                       "', per unit thickness",
                     "%.10e",
                     h.rate);
            for (const auto &[name, value] : terms(h.rates))
              row.real(column_name(h.name, "heat_rate_" + name),
                       "W/m",
                       "the part of it through the " + name + " term of h",
                       "%.10e",
                       value);
            row.real(column_name(h.name, "mean_h"),
                     "W/(m^2 K)",
                     "mean conductance over '" + h.name + "' (length-weighted)",
                     "%.10e",
                     h.mean_conductance);
          }
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        for (unsigned int i = 0; i < heat.size(); ++i)
          {
            results.add(Slot::interface_heat, "heat rate " + heat[i].name, heat[i].rate);
            // Each term that carries heat at the end, by name.
            for (const auto &[name, value] : terms(heat[i].rates))
              if (value != 0)
                results.add(Slot::interface_heat, "heat rate " + name + " " + heat[i].name, value);
            results.add(Slot::interface_heat,
                        "mean conductance " + heat[i].name,
                        heat[i].mean_conductance);
            results.add(Slot::interface_heat,
                        "heat crossed " + heat[i].name,
                        this->state.crossed.at(i));
          }
      }

    private:
      static std::vector<std::pair<std::string, double>> terms(const ConductanceTerms &r)
      {
        return {{"constant", r.constant},
                {"contact", r.contact},
                {"gas", r.gas},
                {"radiation", r.radiation},
                {"function", r.function}};
      }
      std::vector<InterfaceHeat> heat;
    };
  } // namespace



  PartInfo interface_heat_part()
  {
    PartInfo info;
    info.name        = "interface heat";
    info.description = "The heat through each conductance interface: its rate, terms, mean "
                       "conductance and the heat crossed since t0 (a 'Thermal contact' = "
                       "conductance interface).";
    info.parse       = [](ParameterHandler &, const SceneParameters &scene, const bool) {
      bool any = false;
      for (const auto &[pair, law] : scene.interface_pairs)
        any = any || law.thermal_contact == Parameters::InterfacePair::ThermalContact::conductance;
      return scene.physics.thermal && any ? std::make_shared<const PartParameters>() : nullptr;
    };
    info.create = part_factory<InterfaceHeatPart>();
    return info;
  }
} // namespace ContactStefan
