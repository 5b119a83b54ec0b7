// Check 'contact pressure' ('Exact solution/Contact pressure' given, any
// Type): the nodal contact pressure on every obstacle and interface node
// against an exact one (0 where open) after every step: the largest error and
// the largest exact pressure. A scene with it also reports the mean gap of
// each contact group (part 'mechanical statistics').
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/output/part.h>

#include <cmath>

namespace ContactStefan
{
  using namespace Input;

  namespace
  {
    struct PressureParameters : PartParameters
    {
      std::string pressure;
    };

    struct PressureState
    {
      double max_error = 0, max_exact = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &max_error &max_exact;
      }
    };

    template <int dim>
    class PressureCheck : public PartWithState<dim, PressureState>
    {
    public:
      PressureCheck(const RunContext<dim> &run, const PressureParameters &parameters)
        : PartWithState<dim, PressureState>(run)
        , exact(run.functions.checked_expression({parameters.pressure},
                                                 "Exact solution/Contact pressure"))
      {}

      // After each step, not at t0 (a scene may start before its loading does).
      void update(const StepData &data) override
      {
        const RunContext<dim> &run = this->run;
        if (data.time <= run.scene.time.start_time)
          return;
        TimerOutput::Scope t(run.timer, "errors");
        exact->set_time(data.time);
        const MechanicalField<dim> &mechanical = *run.mechanical;
        double                      error = 0, size = 0;
        for (const auto &c : mechanical.get_normal_conditions())
          if (c.kind != NormalCondition::Kind::roller &&
              mechanical.get_dof_handler().locally_owned_dofs().is_element(c.dofs_k[0]))
            {
              const double p = exact->value(c.position);
              error          = max_with_nan(error, std::abs(mechanical.contact_pressure(c) - p));
              size           = std::max(size, std::abs(p));
            }
        run.functions.check_finite_values(run.mpi_communicator);
        PressureState &s = this->state;
        s.max_error = max_with_nan(s.max_error, global_max_with_nan(error, run.mpi_communicator));
        s.max_exact = std::max(s.max_exact, Utilities::MPI::max(size, run.mpi_communicator));
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const PressureState &s = this->state;
        results.add(ResultLines::Slot::contact_pressure, "max contact pressure error", s.max_error);
        results.add(ResultLines::Slot::contact_pressure,
                    "max relative contact pressure error",
                    s.max_exact > 0 ? s.max_error / s.max_exact : 0.);
      }

    private:
      const std::unique_ptr<Function<dim>> exact;
    };
  } // namespace



  PartInfo contact_pressure_part()
  {
    PartInfo info;
    info.name        = "contact pressure";
    info.description = "The contact pressure error against 'Exact solution/Contact pressure' "
                       "after every step.";
    info.declare     = [](ParameterHandler &prm) {
      prm.enter_subsection("Exact solution");
      prm.declare_entry("Contact pressure",
                        "",
                        Patterns::Anything(),
                        "Empty, or the exact contact pressure on every obstacle and "
                            "interface node (Pa, function of x, y, t; 0 where open): the run "
                            "reports the pressure error at every step (any Type).");
      prm.leave_subsection();
    };
    info.parse = [](ParameterHandler &prm, const SceneParameters &scene, const bool) {
      auto p = std::make_shared<PressureParameters>();
      prm.enter_subsection("Exact solution");
      p->pressure = prm.get("Contact pressure");
      prm.leave_subsection();
      if (p->pressure.empty())
        return std::shared_ptr<const PartParameters>();
      check_function(p->pressure, "Exact solution/Contact pressure", false);
      scene.check_variables(p->pressure, "Exact solution/Contact pressure");
      require(scene.physics.mechanics,
              "Exact solution/Contact pressure",
              "an exact contact pressure needs Physics/Mechanics = true");
      return std::shared_ptr<const PartParameters>(p);
    };
    info.create = part_factory<PressureCheck, PressureParameters>();
    return info;
  }
} // namespace ContactStefan
