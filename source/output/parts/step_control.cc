// Part 'step control' (Time stepping/Step control = adaptive): the adaptive
// step control's columns (attempts redone, the changes each step made) and
// its RESULT lines over the run (attempts redone, steps that stood only at the
// minimum step, the shortest and the longest step). doc/time_stepping.md.
#include <contact-stefan/output/part.h>

#include <algorithm>

namespace ContactStefan
{
  namespace
  {
    struct StepControlState
    {
      unsigned int rejected = 0, at_minimum = 0;
      // The shortest and longest step so far (0: no step yet).
      double shortest = 0, longest = 0;

      template <class Archive>
      void serialize(Archive &ar, const unsigned int)
      {
        ar &rejected &at_minimum &shortest &longest;
      }
    };

    template <int dim>
    class StepControl : public PartWithState<dim, StepControlState>
    {
    public:
      using PartWithState<dim, StepControlState>::PartWithState;
      using Slot = ResultLines::Slot;

      void update(const StepData &data) override
      {
        if (data.step == 0)
          return;
        StepControlState &s = this->state;
        s.rejected += data.step_control.rejected;
        s.at_minimum += data.step_control.at_minimum;
        s.shortest = s.shortest == 0 ? data.time_step : std::min(s.shortest, data.time_step);
        s.longest  = std::max(s.longest, data.time_step);
      }

      void add_columns(StatisticsRow &row, const StepData &data) const override
      {
        row.real("tau", "s", "the step's size", "%.10e", data.time_step);
        row.count("rejected_attempts",
                  "attempts of this step redone shorter (adaptive step control)",
                  data.step_control.rejected);
        row.real("temperature_change",
                 "K",
                 "the step's largest change of a free node's temperature",
                 "%.6e",
                 data.step_control.temperature_change);
        row.real("phase_change",
                 "1",
                 "the step's largest change of a node's phase index",
                 "%.6e",
                 data.step_control.phase_change);
      }

      void add_results(ResultLines &results, const unsigned int, const double) const override
      {
        const StepControlState &s = this->state;
        results.add(Slot::step_control, "rejected step attempts", s.rejected);
        results.add(Slot::step_control,
                    "steps over the rejection factor at the minimum time step",
                    s.at_minimum);
        results.add(Slot::step_control, "shortest time step", s.shortest);
        results.add(Slot::step_control, "longest time step", s.longest);
      }
    };
  } // namespace



  PartInfo step_control_part()
  {
    PartInfo info;
    info.name        = "step control";
    info.description = "The adaptive step control's columns and RESULT lines (Time "
                       "stepping/Step control = adaptive).";
    info.parse       = [](ParameterHandler &, const SceneParameters &scene, const bool) {
      return scene.time.adaptive ? std::make_shared<const PartParameters>() : nullptr;
    };
    info.create = part_factory<StepControl>();
    return info;
  }
} // namespace ContactStefan
