#include <deal.II/base/function_parser.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/scene_functions.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <mutex>
#include <sstream>
#include <unordered_map>

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

    // An expression of x, y, interface_distance and t: the parser sees the
    // point (x, y, d) with d the signed distance to the dipping interface.
    template <int dim>
    class WithInterfaceDistance : public Function<dim>
    {
    public:
      WithInterfaceDistance(const std::vector<std::string>         &expressions,
                            std::shared_ptr<const DippingInterface> interface)
        : Function<dim>(expressions.size())
        , parser(expressions.size())
        , interface(std::move(interface))
      {
        parser.initialize("x,y,interface_distance,t", expressions, {{"pi", numbers::PI}}, true);
      }
      void set_time(const double t) override
      {
        Function<dim>::set_time(t);
        parser.set_time(t);
      }
      double value(const Point<dim> &p, const unsigned int component = 0) const override
      {
        return parser.value(lifted(p), component);
      }
      void vector_value(const Point<dim> &p, dealii::Vector<double> &values) const override
      {
        parser.vector_value(lifted(p), values);
      }

    private:
      Point<3> lifted(const Point<dim> &p) const
      {
        return Point<3>(p[0], p[1], interface->signed_distance(Point<2>(p[0], p[1])));
      }
      FunctionParser<3>                       parser;
      std::shared_ptr<const DippingInterface> interface;
    };

    // A function whose every returned value is checked for finiteness.
    template <int dim>
    class Checked : public Function<dim>
    {
    public:
      // used: the components that matter (all if empty); e.g. a displacement
      // condition on y alone never uses its x expression.
      Checked(std::unique_ptr<Function<dim>>                 function,
              const std::string                             &parameter,
              typename SceneFunctions<dim>::NonFiniteRecord &record,
              const std::vector<bool>                       &used)
        : Function<dim>(function->n_components)
        , function(std::move(function))
        , parameter(parameter)
        , record(record)
        , used(used.empty() ? std::vector<bool>(this->n_components, true) : used)
      {}
      void set_time(const double t) override
      {
        Function<dim>::set_time(t);
        function->set_time(t);
      }
      double value(const Point<dim> &p, const unsigned int component = 0) const override
      {
        const double v = function->value(p, component);
        if (!std::isfinite(v) && used[component])
          record.note(parameter, p, this->get_time(), v);
        return v;
      }
      void vector_value(const Point<dim> &p, dealii::Vector<double> &values) const override
      {
        function->vector_value(p, values);
        for (unsigned int c = 0; c < values.size(); ++c)
          if (!std::isfinite(values[c]) && used[c])
            record.note(parameter, p, this->get_time(), values[c]);
      }

    private:
      const std::unique_ptr<Function<dim>>           function;
      const std::string                              parameter;
      typename SceneFunctions<dim>::NonFiniteRecord &record;
      const std::vector<bool>                        used;
    };

    // A scalar function of the point and the time that remembers its values.
    // The reference temperature Theta_0 is evaluated at the vertices of every
    // cell, by both fields, after every mesh adaptation (the cells' references,
    // the heating coefficient, and the test whether it jumps where bodies
    // meet): about sixteen times per vertex and adaptation, and almost every
    // vertex survives an adaptation. In a scene whose Theta_0 names
    // interface_distance (the default scene), each evaluation measures the
    // distance to a curved interface: these evaluations took about 3 s of its
    // 21 s. A remembered value is the value the function returned for the
    // same point and time (bit for bit), so nothing the run computes changes
    // (but for an expression with rand(), which now draws once per point).
    template <int dim>
    class Remembered : public Function<dim>
    {
      static_assert(dim == 2, "the key holds x and y only");

    public:
      explicit Remembered(std::unique_ptr<Function<dim>> function)
        : Function<dim>(1)
        , function(std::move(function))
      {
        AssertThrow(this->function->n_components == 1, ExcInternalError());
      }
      void set_time(const double t) override
      {
        Function<dim>::set_time(t);
        function->set_time(t);
      }
      double value(const Point<dim> &p, const unsigned int component = 0) const override
      {
        AssertIndexRange(component, 1);
        const Key key = {{bits(p[0]), bits(p[1]), bits(this->get_time())}};
        {
          std::lock_guard<std::mutex> lock(mutex);
          if (const auto it = values.find(key); it != values.end())
            return it->second;
        }
        const double v = function->value(p, component);
        std::lock_guard<std::mutex> lock(mutex);
        // A bound on the memory (about 80 bytes per point with the table):
        // forget all and start again, rather than grow without limit on a
        // long adaptive run.
        if (values.size() >= max_entries)
          values.clear();
        values.emplace(key, v);
        return v;
      }

    private:
      using Key = std::array<std::uint64_t, 3>;
      struct Hash
      {
        std::size_t operator()(const Key &k) const
        {
          // splitmix64's finaliser on each word: the low bits of a
          // coordinate's mantissa (the ones that differ between neighbouring
          // vertices) reach every bit of the hash.
          std::uint64_t h = 0;
          for (const std::uint64_t w : k)
            {
              std::uint64_t z = h + w + 0x9e3779b97f4a7c15ULL;
              z               = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
              z               = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
              h               = z ^ (z >> 31);
            }
          return static_cast<std::size_t>(h);
        }
      };
      static std::uint64_t bits(const double x)
      {
        std::uint64_t b;
        std::memcpy(&b, &x, sizeof b);
        return b;
      }
      static constexpr std::size_t                  max_entries = std::size_t(1) << 20;
      const std::unique_ptr<Function<dim>>          function;
      mutable std::mutex                            mutex;
      mutable std::unordered_map<Key, double, Hash> values;
    };
  } // namespace



  template <int dim>
  void SceneFunctions<dim>::NonFiniteRecord::note(const std::string &parameter,
                                                  const Point<dim>  &point,
                                                  const double       time,
                                                  const double       value)
  {
    std::lock_guard<std::mutex> lock(mutex);
    if (found)
      return;
    found = true;
    std::ostringstream s;
    s << "parameter '" << parameter << "': evaluates to " << value << " at (x, y) = (" << point[0]
      << ", " << point[1] << "), t = " << time;
    message = s.str();
  }



  template <int dim>
  void SceneFunctions<dim>::check_finite_values(const MPI_Comm mpi_communicator) const
  {
    throw_collectively<InputError>(record->found ? record->message : std::string(),
                                   mpi_communicator);
  }



  template <int dim>
  std::unique_ptr<Function<dim>>
  SceneFunctions<dim>::checked(std::unique_ptr<Function<dim>> function,
                               const std::string             &parameter,
                               const std::vector<bool>       &used) const
  {
    return std::make_unique<Checked<dim>>(std::move(function), parameter, *record, used);
  }



  template <int dim>
  SceneFunctions<dim>::SceneFunctions(const SceneParameters &prm, ExactTemperature provided)
    : prm(prm)
    , record(std::make_unique<NonFiniteRecord>())
    , provided_exact(std::move(provided))
  {
    assert_two_dimensional<dim>();
    if (prm.geometry.mesh_type == Parameters::Geometry::MeshType::dipping_interface)
      dipping_interface = std::make_shared<const DippingInterface>(prm.geometry);
    if (provided_exact)
      exact = checked(make_exact(), "Exact solution/Function");

    for (const auto &[id, m] : prm.materials)
      {
        const std::string body = "Materials/Body " + std::to_string(id) + "/";
        heat_sources[id]       = checked_expression({m.heat_source}, body + "Heat source");
        heat_load |= !is_zero_expression(m.heat_source);
        body_forces[id] =
          checked_expression({m.body_force[0], m.body_force[1]}, body + "Body force");
        mechanical_load |=
          !is_zero_expression(m.body_force[0]) || !is_zero_expression(m.body_force[1]);
      }
    for (const auto &[id, bc] : prm.thermal_boundaries)
      {
        const std::string parameter =
          "Boundary conditions/Thermal boundary " + std::to_string(id) + "/Value";
        thermal_boundaries[id] = checked(function_or_exact(bc.value, parameter), parameter);
        heat_load |=
          bc.type == Parameters::ThermalBoundary::Type::flux && !is_zero_expression(bc.value);
      }
    initial =
      checked(function_or_exact(prm.initial_condition.function, "Initial conditions/Function"),
              "Initial conditions/Function");

    using Mechanical = Parameters::MechanicalBoundary::Type;
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      {
        const std::string section =
          "Boundary conditions/Mechanical boundary " + std::to_string(id) + "/";
        mechanical_values[id] =
          checked_expression({bc.value[0], bc.value[1]},
                             section + "Value",
                             bc.type == Mechanical::displacement ?
                               std::vector<bool>{bc.components[0], bc.components[1]} :
                               std::vector<bool>());
        if (bc.type == Mechanical::obstacle)
          obstacle_gaps[id] = checked_expression({bc.gap}, section + "Gap");
        mechanical_load |= bc.type == Mechanical::traction &&
                           (!is_zero_expression(bc.value[0]) || !is_zero_expression(bc.value[1]));
      }
    for (const auto &[pair, law] : prm.interface_pairs)
      {
        const std::string parameter =
          !law.own_gap ?
            std::string("Contact/Interface gap") :
            "Contact/" + Parameters::InterfacePair::section(pair.first, pair.second) + "/Gap";
        interface_gaps[pair] = checked_expression({law.gap}, parameter);
      }
    reference = std::make_unique<Remembered<dim>>(
      checked(parsed({prm.coupling.reference_temperature}, "Coupling/Reference temperature"),
              "Coupling/Reference temperature"));
    reference->set_time(prm.time.start_time);
  }



  template <int dim>
  std::unique_ptr<Function<dim>> SceneFunctions<dim>::make_exact() const
  {
    AssertThrow(provided_exact, ExcMessage("'exact' is used without an exact temperature"));
    return provided_exact();
  }



  template <int dim>
  std::unique_ptr<Function<dim>>
  SceneFunctions<dim>::checked_expression(const std::vector<std::string> &expressions,
                                          const std::string              &parameter,
                                          const std::vector<bool>        &used) const
  {
    return checked(parsed(expressions, parameter), parameter, used);
  }



  template <int dim>
  std::unique_ptr<Function<dim>>
  SceneFunctions<dim>::expression(const std::vector<std::string> &expressions)
  {
    return parse<dim>(expressions);
  }



  template <int dim>
  std::unique_ptr<Function<dim>>
  SceneFunctions<dim>::function_or_exact(const std::string &expression,
                                         const std::string &parameter) const
  {
    return is_exact_keyword(expression) ? make_exact() : parsed({expression}, parameter);
  }



  template <int dim>
  std::unique_ptr<Function<dim>>
  SceneFunctions<dim>::parsed(const std::vector<std::string> &expressions,
                              const std::string              &parameter) const
  {
    if (std::none_of(expressions.begin(), expressions.end(), uses_interface_distance))
      return parse<dim>(expressions);
    // (Refused off a dipping-interface mesh when the parameters were read; the
    // same check again for a SceneParameters made otherwise.)
    for (const std::string &e : expressions)
      prm.check_variables(e, parameter);
    return std::make_unique<WithInterfaceDistance<dim>>(expressions, dipping_interface);
  }



  template class SceneFunctions<2>;
} // namespace ContactStefan
