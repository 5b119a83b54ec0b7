// Check 'liquid fraction' ('Exact solution/Liquid fraction' given, any Type):
// the liquid fraction (through the last transition) at every node against an
// exact one, at the start and after every step; the largest nodal error.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/part.h>

#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct FractionParameters : PartParameters
    {
      std::string fraction;
    };

    struct FractionState
    {
      double max_error = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &max_error;
      }
    };

    template <int dim>
    class FractionCheck : public PartWithState<dim, FractionState>
    {
    public:
      FractionCheck(const RunContext<dim> &run, const FractionParameters &parameters)
        : PartWithState<dim, FractionState>(run)
        , exact(run.functions.checked_expression({parameters.fraction},
                                                 "Exact solution/Liquid fraction"))
      {}

      void update(const StepData &data) override
      {
        const RunContext<dim>   &run     = this->run;
        const ThermalField<dim> &thermal = *run.thermal;
        exact->set_time(data.time);
        const auto &points = thermal.get_support_points();
        double      error  = 0;
        for (const auto dof : thermal.get_dof_handler().locally_owned_dofs())
          error =
            max_with_nan(error,
                         std::abs(thermal.law(dof).liquid_fraction(thermal.get_enthalpy()[dof]) -
                                  exact->value(points.at(dof))));
        run.functions.check_finite_values(run.mpi_communicator);
        this->state.max_error =
          max_with_nan(this->state.max_error, global_max_with_nan(error, run.mpi_communicator));
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        results.add(ResultLines::Slot::liquid_fraction,
                    "max liquid fraction error",
                    this->state.max_error);
      }

    private:
      const std::unique_ptr<Function<dim>> exact;
    };
  } // namespace



  PartInfo liquid_fraction_part()
  {
    PartInfo info;
    info.name        = "liquid fraction";
    info.description = "The nodal liquid fraction error against 'Exact solution/Liquid "
                       "fraction' at the start and after every step.";
    info.declare     = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Liquid fraction",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact liquid fraction (fraction through the last "
                            "transition) at every node, a function of x, y, t: the run reports "
                            "its largest nodal error over the steps (any Type).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool) {
      auto p = std::make_shared<FractionParameters>();
      prm.enter_subsection("Exact solution");
      p->fraction = prm.get("Liquid fraction");
      prm.leave_subsection();
      if (p->fraction.empty())
        return std::shared_ptr<const PartParameters>();
      check_function(p->fraction, "Exact solution/Liquid fraction", false);
      scene.check_variables(p->fraction, "Exact solution/Liquid fraction");
      require(scene.physics.thermal,
              "Exact solution/Liquid fraction",
              "an exact liquid fraction needs Physics/Thermal = true");
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<FractionCheck, FractionParameters>();
    return info;
  }
} // namespace ContactStefan
