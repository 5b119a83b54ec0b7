#include <deal.II/base/function_parser.h>

#include <contact-stefan/materials.h>
#include <contact-stefan/scene_functions.h>

namespace ContactStefan
{
  namespace
  {
    // A muparser expression (or one per component) of x, y and t, with pi.
    template <int dim>
    std::unique_ptr<Function<dim>> parse(const std::vector<std::string> &expressions)
    {
      auto f = std::make_unique<FunctionParser<dim>>(expressions.size());
      f->initialize("x,y,t", expressions, {{"pi", numbers::PI}}, true);
      return f;
    }

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



  template <int dim>
  SceneFunctions<dim>::SceneFunctions(const AllParameters &prm)
    : prm(prm)
  {
    assert_two_dimensional<dim>();
    using Exact = Parameters::ExactSolution::Type;
    if (prm.exact_solution.type == Exact::neumann)
      neumann_solution = std::make_unique<NeumannSolution>(ContactStefan::neumann_solution(prm));
    if (prm.exact_solution.type == Exact::neumann || prm.exact_solution.type == Exact::function)
      exact = make_exact();

    for (const auto &[id, m] : prm.materials)
      {
        heat_sources[id] = parse<dim>({m.heat_source});
        heat_load |= !is_zero_expression(m.heat_source);
        body_forces[id] = parse<dim>({m.body_force[0], m.body_force[1]});
        mechanical_load |=
          !is_zero_expression(m.body_force[0]) || !is_zero_expression(m.body_force[1]);
      }
    for (const auto &[id, bc] : prm.thermal_boundaries)
      {
        thermal_boundaries[id] = function_or_exact(bc.value);
        heat_load |=
          bc.type == Parameters::ThermalBoundary::Type::flux && !is_zero_expression(bc.value);
      }
    initial = function_or_exact(prm.initial_condition.function);

    using Mechanical = Parameters::MechanicalBoundary::Type;
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      {
        mechanical_values[id] = parse<dim>({bc.value[0], bc.value[1]});
        if (bc.type == Mechanical::obstacle)
          obstacle_gaps[id] = parse<dim>({bc.gap});
        mechanical_load |= bc.type == Mechanical::traction &&
                           (!is_zero_expression(bc.value[0]) || !is_zero_expression(bc.value[1]));
      }
    interface = parse<dim>({prm.contact.interface_gap});
  }



  template <int dim>
  std::unique_ptr<Function<dim>> SceneFunctions<dim>::make_exact() const
  {
    if (neumann_solution)
      return std::make_unique<NeumannFunction<dim>>(*neumann_solution, prm.exact_solution.origin);
    return parse<dim>({prm.exact_solution.function});
  }



  template <int dim>
  std::unique_ptr<Function<dim>>
  SceneFunctions<dim>::function_or_exact(const std::string &expression) const
  {
    return is_exact_keyword(expression) ? make_exact() : parse<dim>({expression});
  }



  template class SceneFunctions<2>;
} // namespace ContactStefan
