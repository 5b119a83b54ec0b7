// Part 'neumann' (Exact solution/Type = neumann, doc/benchmarks.md S1): the
// Neumann similarity solution of one body's (multi-)phase Stefan problem on
// x > Origin, melting from x = Origin. It checks the scene against what the
// solution requires before any work is done, gives the scene its exact
// temperature (the keyword 'exact' in boundary values and the initial
// condition), reports the temperature errors and, per transition, the front
// position against the exact one.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/verification/neumann_solution.h>
#include <contact-stefan/verification/temperature_errors.h>

#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    // The Neumann solution as a deal.II function of (x, y) at the function's time.
    template <int dim>
    class NeumannFunction : public Function<dim>
    {
    public:
      NeumannFunction(const std::shared_ptr<const NeumannSolution> &solution, const double origin)
        : solution(solution)
        , origin(origin)
      {}
      double value(const Point<dim> &p, const unsigned int = 0) const override
      {
        return solution->temperature(p[0] - origin, this->get_time());
      }

    private:
      const std::shared_ptr<const NeumannSolution> solution;
      const double           origin;
    };

    struct NeumannParameters : PartParameters
    {
      unsigned int body;
      double       hot_temperature, cold_temperature, origin;
      // Built once from the body's material, when the file is read.
      std::shared_ptr<const NeumannSolution> solution;

      // (Each function shares the solution: it outlives these parameters.)
      std::function<std::unique_ptr<Function<2>>()> exact_temperature() const override
      {
        const std::shared_ptr<const NeumannSolution> s = solution;
        const double                                 x = origin;
        return [s, x]() -> std::unique_ptr<Function<2>> {
          return std::make_unique<NeumannFunction<2>>(s, x);
        };
      }
    };

    // The similarity solution of the body's material (isotropic: the shape
    // tensor of the conductivity is a multiple of the identity).
    NeumannSolution make_solution(const Material &m, const double hot, const double cold)
    {
      const EnthalpyLaw  &law = m.enthalpy_law;
      std::vector<double> k, c, rho_L, T;
      for (unsigned int p = 0; p <= law.n_transitions(); ++p)
        {
          k.push_back(m.conductivity(p) * m.conductivity_shape[0][0]);
          c.push_back(law.heat_capacity(p));
        }
      for (unsigned int j = 0; j < law.n_transitions(); ++j)
        {
          rho_L.push_back(law.latent_heat(j));
          T.push_back(law.transition_temperature(j));
        }
      return NeumannSolution(k, c, T, rho_L, hot, cold);
    }

    // What a Neumann scene requires of the rest of the file (one body with a
    // phase transition and isotropic conductivity, a rectangle beside the
    // origin, t0 > 0, boundary temperatures across the transitions) and that
    // the similarity solution exists.
    void check_scene(const SceneParameters &prm, NeumannParameters &p)
    {
      require(prm.physics.thermal, "Exact solution/Type", "'neumann' needs Physics/Thermal = true");
      const std::string path = "Exact solution/Body";
      require(prm.materials.count(p.body) == 1,
              path,
              "body " + std::to_string(p.body) + " is not in Bodies/Body ids");
      const auto &m = prm.materials.at(p.body);
      require(!m.transition_temperatures.empty(),
              path,
              "the Neumann solution needs a material with a phase transition");
      require(p.hot_temperature > m.transition_temperatures.back(),
              "Exact solution/Hot temperature",
              "must exceed the highest transition temperature");
      require(p.cold_temperature <= m.transition_temperatures.front(),
              "Exact solution/Cold temperature",
              "must not exceed the lowest transition temperature");
      require(conductivity_is_isotropic(m),
              "Materials/Body " + std::to_string(p.body) + "/Conductivity anisotropy",
              "the Neumann solution needs an isotropic conductivity");
      require(prm.geometry.mesh_type == Parameters::Geometry::MeshType::rectangle,
              "Exact solution/Type",
              "'neumann' needs Geometry/Mesh = rectangle (a strip along x)");
      require(p.origin <= prm.geometry.lower_left[0],
              "Exact solution/Origin",
              "must not lie inside the rectangle");
      require(prm.body_ids.size() == 1,
              "Bodies/Body ids",
              "the Neumann solution is for a single body");
      require(prm.time.start_time > 0,
              "Time stepping/Start time",
              "must be > 0 for the Neumann solution (it is singular at t = 0)");
      // Built here, so that data without a similarity solution is rejected
      // before any work.
      try
        {
          p.solution = std::make_shared<const NeumannSolution>(
            make_solution(Material(m), p.hot_temperature, p.cold_temperature));
        }
      catch (const std::exception &e)
        {
          throw InputError("Exact solution/Type", std::string("no Neumann solution: ") + e.what());
        }
    }

    template <int dim>
    class NeumannCheck : public TemperatureErrors<dim>
    {
    public:
      NeumannCheck(const RunContext<dim> &run, const NeumannParameters &parameters)
        : TemperatureErrors<dim>(run, true)
        , parameters(parameters)
      {}

      // The temperature errors (slot 'temperature'), then the fronts: from
      // the melt area of each transition (a strip of height Y), the computed
      // and exact front and the error in mesh widths.
      void add_results(ResultLines       &results,
                       const unsigned int n_steps,
                       const double       time) const override
      {
        TemperatureErrors<dim>::add_results(results, n_steps, time);
        const RunContext<dim> &run    = this->run;
        const auto            &g      = run.scene.geometry;
        const double           h      = mesh_width(run.triangulation);
        const double           height = g.upper_right[1] - g.lower_left[1];
        const auto            &law    = run.materials[parameters.body].enthalpy_law;
        const auto             add    = [&](const std::string &name, const double value) {
          results.add(ResultLines::Slot::fronts, name, value);
        };
        for (unsigned int j = 0; j < law.n_transitions(); ++j)
          {
            const std::string suffix = law.n_transitions() == 1 ? "" : " " + std::to_string(j);
            const double      s_h =
              g.lower_left[0] + run.thermal->liquid_area(law.transition_temperature(j)) / height;
            const double s = parameters.origin + parameters.solution->front_position(j, time);
            add("front position" + suffix, s_h);
            add("exact front position" + suffix, s);
            add("front position error" + suffix, std::abs(s_h - s));
            add("front position error in mesh widths" + suffix, std::abs(s_h - s) / h);
            if (run.adaptive)
              add("front position error in local mesh widths" + suffix,
                  std::abs(s_h - s) / widest_cell_at(s));
          }
      }

    private:
      // The widest cell the abscissa s crosses (0: none; then the error is 0).
      double widest_cell_at(const double s) const
      {
        double local = 0;
        for (const auto &cell : this->run.triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const auto box = cell->bounding_box();
              if (box.lower_bound(0) <= s && s <= box.upper_bound(0))
                local = std::max(local, cell->extent_in_direction(0));
            }
        local = Utilities::MPI::max(local, this->run.mpi_communicator);
        return local > 0 ? local : HUGE_VAL;
      }

      const NeumannParameters &parameters;
    };
  } // namespace



  PartInfo neumann_part()
  {
    PartInfo info;
    info.name           = "neumann";
    info.exact_solution    = true;
    info.gives_temperature = true;
    info.description =
      "the similarity solution of the (multi-)phase Stefan problem of one body's material on "
      "x > Origin with Theta = Hot temperature at x = Origin and Cold temperature initially (a "
      "rectangle; front positions are reported too).";
    info.declare = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Hot temperature",
                        "1",
                        Patterns::Double(),
                        "T_L, above the highest transition temperature.");
      prm.declare_entry("Cold temperature",
                        "-1",
                        Patterns::Double(),
                        "T_S, at or below the lowest transition temperature.");
      prm.declare_entry("Origin", "0", Patterns::Double(), "x coordinate of the hot wall.");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool chosen) {
      auto p = std::make_shared<NeumannParameters>();
      prm.enter_subsection("Exact solution");
      p->body             = prm.get_integer("Body");
      p->hot_temperature  = get_finite(prm, "Exact solution/", "Hot temperature");
      p->cold_temperature = get_finite(prm, "Exact solution/", "Cold temperature");
      p->origin           = get_finite(prm, "Exact solution/", "Origin");
      prm.leave_subsection();
      if (!chosen)
        return std::shared_ptr<const PartParameters>();
      check_scene(scene, *p);
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<NeumannCheck, NeumannParameters>();
    return info;
  }
} // namespace ContactStefan
