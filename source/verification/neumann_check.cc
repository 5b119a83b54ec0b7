// The Neumann solution as the verification part of a scene
// (verification/neumann_check.h).
#include <contact-stefan/core/materials.h>
#include <contact-stefan/verification/neumann_check.h>

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
      NeumannFunction(const NeumannSolution &solution, const double origin)
        : solution(solution)
        , origin(origin)
      {}
      double value(const Point<dim> &p, const unsigned int = 0) const override
      {
        return solution.temperature(p[0] - origin, this->get_time());
      }

    private:
      const NeumannSolution &solution;
      const double           origin;
    };
  } // namespace



  NeumannSolution neumann_solution(const SceneParameters &prm)
  {
    const Material      m(prm.materials.at(prm.exact_solution.body));
    const EnthalpyLaw  &law = m.enthalpy_law;
    std::vector<double> k, c, rho_L, T;
    for (unsigned int p = 0; p <= law.n_transitions(); ++p)
      {
        // Isotropic: the shape tensor is a multiple of the identity.
        k.push_back(m.conductivity(p) * m.conductivity_shape[0][0]);
        c.push_back(law.heat_capacity(p));
      }
    for (unsigned int j = 0; j < law.n_transitions(); ++j)
      {
        rho_L.push_back(law.latent_heat(j));
        T.push_back(law.transition_temperature(j));
      }
    return NeumannSolution(
      k, c, T, rho_L, prm.exact_solution.hot_temperature, prm.exact_solution.cold_temperature);
  }



  void check_neumann_scene(const SceneParameters &prm)
  {
    const std::string path = "Exact solution/Body";
    require(prm.materials.count(prm.exact_solution.body) == 1,
            path,
            "body " + std::to_string(prm.exact_solution.body) + " is not in Bodies/Body ids");
    const auto &m = prm.materials.at(prm.exact_solution.body);
    require(!m.transition_temperatures.empty(),
            path,
            "the Neumann solution needs a material with a phase transition");
    require(prm.exact_solution.hot_temperature > m.transition_temperatures.back(),
            "Exact solution/Hot temperature",
            "must exceed the highest transition temperature");
    require(prm.exact_solution.cold_temperature <= m.transition_temperatures.front(),
            "Exact solution/Cold temperature",
            "must not exceed the lowest transition temperature");
    require(conductivity_is_isotropic(m),
            "Materials/Body " + std::to_string(prm.exact_solution.body) +
              "/Conductivity anisotropy",
            "the Neumann solution needs an isotropic conductivity");
    require(prm.geometry.mesh_type == Parameters::Geometry::MeshType::rectangle,
            "Exact solution/Type",
            "'neumann' needs Geometry/Mesh = rectangle (a strip along x)");
    require(prm.exact_solution.origin <= prm.geometry.lower_left[0],
            "Exact solution/Origin",
            "must not lie inside the rectangle");
    require(prm.body_ids.size() == 1,
            "Bodies/Body ids",
            "the Neumann solution is for a single body");
    require(prm.time.start_time > 0,
            "Time stepping/Start time",
            "must be > 0 for the Neumann solution (it is singular at t = 0)");
    // Build the solution once here, so that data without a similarity
    // solution is rejected before any work.
    try
      {
        neumann_solution(prm);
      }
    catch (const std::exception &e)
      {
        throw InputError("Exact solution/Type", std::string("no Neumann solution: ") + e.what());
      }
  }



  template <int dim>
  std::function<std::unique_ptr<Function<dim>>()>
  neumann_temperature(const NeumannSolution &solution, const double origin)
  {
    return [&solution, origin]() -> std::unique_ptr<Function<dim>> {
      return std::make_unique<NeumannFunction<dim>>(solution, origin);
    };
  }



  template std::function<std::unique_ptr<Function<2>>()>
  neumann_temperature<2>(const NeumannSolution &, const double);
} // namespace ContactStefan
