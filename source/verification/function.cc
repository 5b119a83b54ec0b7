// Part 'function' (Exact solution/Type = function): the temperature given by
// 'Exact solution/Function', a function of x, y, t (a manufactured or steady
// solution). It gives the scene its exact temperature (the keyword 'exact' in
// boundary values and the initial condition) and reports the temperature
// errors.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/verification/temperature_errors.h>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct FunctionParameters : PartParameters
    {
      std::string function;

      std::function<std::unique_ptr<Function<2>>()> exact_temperature() const override
      {
        const std::string f = function;
        return [f]() { return SceneFunctions<2>::expression({f}); };
      }
    };
  } // namespace



  PartInfo function_part()
  {
    PartInfo info;
    info.name           = "function";
    info.exact_solution    = true;
    info.gives_temperature = true;
    info.description       = "the temperature given by Function.";
    info.declare        = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Function",
                        "0",
                        Patterns::Anything(),
                        "Type = function: the exact temperature, a function of x, y, t.");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool chosen) {
      auto p = std::make_shared<FunctionParameters>();
      prm.enter_subsection("Exact solution");
      p->function = prm.get("Function");
      prm.leave_subsection();
      if (!chosen)
        return std::shared_ptr<const PartParameters>();
      require(scene.physics.thermal,
              "Exact solution/Type",
              "'function' needs Physics/Thermal = true");
      check_function(p->function, "Exact solution/Function", false);
      require(!uses_interface_distance(p->function),
              "Exact solution/Function",
              "an exact temperature is a function of x, y, t only (not interface_distance)");
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = [](const RunContext<2> &run, const PartParameters &) {
      return std::unique_ptr<Part<2>>(std::make_unique<TemperatureErrors<2>>(run, false));
    };
    return info;
  }
} // namespace ContactStefan
