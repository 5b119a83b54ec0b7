// The entries of 'Time stepping' and the schedule of step sizes and step end
// times worked out from them before the run (core/parameters.h, TimeStepping).
#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/parameters.h>
#include <contact-stefan/core/time_round_off.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

namespace ContactStefan
{
  namespace Parameters
  {
    using namespace Input;

    void TimeStepping::declare(ParameterHandler &prm)
    {
      prm.enter_subsection("Time stepping");
      prm.declare_entry("Start time", "0", Patterns::Double(), "t0 (s).");
      prm.declare_entry("End time", "1", Patterns::Double(), "T (s), > t0.");
      prm.declare_entry("Time step",
                        "0.1",
                        Patterns::Double(),
                        "tau (s), > 0; the last step is shortened to end at T.");
      prm.declare_entry("Time step function",
                        "",
                        Patterns::Anything(),
                        "Empty: every step is 'Time step' long. Otherwise tau(t), a "
                        "function of the step's start time t (muparser), in which 'tau' "
                        "is the 'Time step' value: e.g. 'if(t < 10, tau, 4 * tau)' for two "
                        "phases, 'tau * min(1.2^(t / 5), 100)' for steps that grow with a "
                        "time scale of 5 s. A function of the form tau * g(t) halves every "
                        "step when 'Time step' is halved (benchmarks/ladder.py refines "
                        "time so). Each value must be finite and > 0; the whole schedule is "
                        "worked out and checked before the run.");
      prm.declare_entry("Step end times",
                        "",
                        Patterns::Anything(),
                        "Times, increasing, in (Start time, End time], at which a step must "
                        "end (e.g. logarithmic times for a diffusion problem, or the times "
                        "of a measurement): a step that would pass one is shortened to end "
                        "there; between them the steps are 'Time step' or 'Time step "
                        "function' long.");
      prm.declare_entry(
        "Step control",
        "schedule",
        Patterns::Selection("schedule|adaptive"),
        "schedule: the step sizes above (Time step, Time step function, Step end times), "
        "worked out before the run. adaptive: each step's size follows the change the "
        "step before made (doc/time_stepping.md): the first step is 'Time step' long; a "
        "step whose largest temperature change (free nodes) or phase change exceeds its "
        "target by more than 'Rejection factor' is redone shorter; tau is kept while the "
        "change stays between 1/'Minimum step growth' and 1 times its target, grows when "
        "below, shrinks when above. Steps still end exactly at the Step end times and at "
        "End time. Needs Physics/Thermal; not with a Time step function.");
      prm.declare_entry("Target temperature change",
                        "1",
                        Patterns::Double(),
                        "Step control = adaptive: the largest change of a node's temperature "
                        "in one step (K) that the steps aim at; > 0. Nodes with a prescribed "
                        "temperature do not count.");
      prm.declare_entry("Target phase change",
                        "0.5",
                        Patterns::Double(),
                        "Step control = adaptive, scenes with a phase change: the largest "
                        "change of a node's phase index in one step (0 solid ... number of "
                        "transitions liquid; 1 is a node that melts completely within the "
                        "step), > 0. 0.5 lets a front cross about half a cell per step.");
      prm.declare_entry("Rejection factor",
                        "2",
                        Patterns::Double(),
                        "Step control = adaptive: a step whose change exceeds its target by "
                        "more than this factor is redone with a shorter step; >= 1.");
      prm.declare_entry("Minimum time step",
                        "0",
                        Patterns::Double(),
                        "Step control = adaptive: the shortest step (s); a step of this size is "
                        "accepted whatever its change (the run's output counts them). 0: "
                        "'Time step' / 1000.");
      prm.declare_entry("Maximum time step",
                        "0",
                        Patterns::Double(),
                        "Step control = adaptive: the longest step (s). 0: End time - Start time.");
      prm.declare_entry("Minimum step growth",
                        "1.5",
                        Patterns::Double(),
                        "Step control = adaptive: tau grows only by at least this factor (> 1), "
                        "so that a factorisation, whose fingerprint holds tau, serves several "
                        "steps.");
      prm.declare_entry("Maximum step growth",
                        "2",
                        Patterns::Double(),
                        "Step control = adaptive: the largest factor by which tau grows from one "
                        "step to the next; >= Minimum step growth.");
      prm.declare_entry("Step reduction after a failure",
                        "0.25",
                        Patterns::Double(),
                        "Step control = adaptive: a step whose contact step, fixed-point "
                        "coupling or enthalpy relaxation did not converge within its limit is "
                        "redone this many times as long (in (0, 1)); at the Minimum time step "
                        "the failure ends the run.");
      prm.declare_entry("Max time steps",
                        "1000000",
                        Patterns::Integer(1),
                        "A run that would need more steps than this ((T - t0) / tau) is "
                        "refused before any work: a guard against a mistyped time step or "
                        "end time. Raise it for a long run on purpose.");
      prm.leave_subsection();
    }

    void TimeStepping::parse(ParameterHandler &prm)
    {
      prm.enter_subsection("Time stepping");
      start_time         = get_finite(prm, "Time stepping/", "Start time");
      end_time           = get_finite(prm, "Time stepping/", "End time");
      time_step          = get_finite(prm, "Time stepping/", "Time step");
      max_steps          = prm.get_integer("Max time steps");
      time_step_function = Utilities::trim(prm.get("Time step function"));
      step_end_times     = parse_doubles(prm.get("Step end times"), "Time stepping/Step end times");
      adaptive           = prm.get("Step control") == "adaptive";
      control.target_temperature_change =
        get_finite(prm, "Time stepping/", "Target temperature change");
      control.target_phase_change = get_finite(prm, "Time stepping/", "Target phase change");
      control.rejection_factor    = get_finite(prm, "Time stepping/", "Rejection factor");
      control.minimum_time_step   = get_finite(prm, "Time stepping/", "Minimum time step");
      control.maximum_time_step   = get_finite(prm, "Time stepping/", "Maximum time step");
      control.minimum_growth      = get_finite(prm, "Time stepping/", "Minimum step growth");
      control.maximum_growth      = get_finite(prm, "Time stepping/", "Maximum step growth");
      control.failure_reduction =
        get_finite(prm, "Time stepping/", "Step reduction after a failure");
      prm.leave_subsection();
      require(time_step > 0, "Time stepping/Time step", "must be > 0, got " + str(time_step));
      require(std::isnormal(time_step),
              "Time stepping/Time step",
              "must be a normal floating-point number, got " + str(time_step));
      require(end_time > start_time,
              "Time stepping/End time",
              "must be greater than Start time (" + str(start_time) + "), got " + str(end_time));
      // Time must advance in every step: t + tau > t in floating point at the
      // start and (the largest t) at the end.
      require(start_time + time_step > start_time && end_time - time_step < end_time,
              "Time stepping/Time step",
              str(time_step) + " is below the floating-point resolution of t near " +
                str(std::max(std::abs(start_time), std::abs(end_time))) +
                ": time would not advance");
      for (std::size_t k = 0; k < step_end_times.size(); ++k)
        require(step_end_times[k] > (k == 0 ? start_time : step_end_times[k - 1]) &&
                  step_end_times[k] <= end_time,
                "Time stepping/Step end times",
                "must increase and lie in (Start time, End time] = (" + str(start_time) + ", " +
                  str(end_time) + "], got " + str(step_end_times[k]) +
                  (k == 0 ? std::string() : " after " + str(step_end_times[k - 1])));
      if (adaptive)
        {
          check_step_control();
          return;
        }
      // A constant step that obviously needs too many steps is refused at once
      // (the schedule below counts exactly; this only spares working out 1e12
      // steps).
      if (time_step_function.empty())
        {
          const double steps = std::ceil((end_time - start_time) / time_step);
          require(steps <= max_steps + 1.,
                  "Time stepping/Time step",
                  "the run would take " + str(steps) + " steps, more than 'Time stepping/Max " +
                    "time steps' = " + std::to_string(max_steps));
        }
      make_schedule();
    }



    // The adaptive controller's entries, each against its range, with the
    // defaults of 0 replaced (the minimum 'Time step' / 1000, the maximum the
    // whole run).
    void TimeStepping::check_step_control()
    {
      const std::string p = "Time stepping/";
      require(time_step_function.empty(),
              p + "Step control",
              "adaptive steps do not take a 'Time step function' (it would fix the sizes "
              "the controller chooses): leave one of them empty");
      StepControlSettings &c = control;
      require(c.target_temperature_change > 0,
              p + "Target temperature change",
              "must be > 0, got " + str(c.target_temperature_change));
      require(c.target_phase_change > 0,
              p + "Target phase change",
              "must be > 0, got " + str(c.target_phase_change));
      require(c.rejection_factor >= 1,
              p + "Rejection factor",
              "must be >= 1, got " + str(c.rejection_factor));
      require(c.minimum_growth > 1,
              p + "Minimum step growth",
              "must be > 1, got " + str(c.minimum_growth));
      require(c.maximum_growth >= c.minimum_growth,
              p + "Maximum step growth",
              "must be >= Minimum step growth (" + str(c.minimum_growth) + "), got " +
                str(c.maximum_growth));
      require(c.failure_reduction > 0 && c.failure_reduction < 1,
              p + "Step reduction after a failure",
              "must lie in (0, 1), got " + str(c.failure_reduction));
      require(c.minimum_time_step >= 0,
              p + "Minimum time step",
              "must be >= 0 (0: Time step / 1000), got " + str(c.minimum_time_step));
      require(c.maximum_time_step >= 0,
              p + "Maximum time step",
              "must be >= 0 (0: End time - Start time), got " + str(c.maximum_time_step));
      if (c.minimum_time_step == 0)
        c.minimum_time_step = time_step / 1000;
      if (c.maximum_time_step == 0)
        c.maximum_time_step = end_time - start_time;
      require(c.minimum_time_step <= time_step,
              p + "Minimum time step",
              str(c.minimum_time_step) + " is longer than Time step (" + str(time_step) + ")");
      require(c.maximum_time_step >= time_step,
              p + "Maximum time step",
              str(c.maximum_time_step) + " is shorter than Time step (" + str(time_step) + ")");
      // Time must advance in the shortest step too.
      require(start_time + c.minimum_time_step > start_time &&
                end_time - c.minimum_time_step < end_time,
              p + "Minimum time step",
              str(c.minimum_time_step) + " is below the floating-point resolution of t near " +
                str(std::max(std::abs(start_time), std::abs(end_time))));
    }



    // The step sizes from t0 to T, added up exactly as the time loop adds
    // them. A step that would end within a 1e-9 fraction of itself of the end
    // time or of a step end time is stretched to end exactly there (round-off,
    // not a parameter); one that would pass such a time is shortened to it.
    void TimeStepping::make_schedule()
    {
      const std::string path =
        time_step_function.empty() ? "Time stepping/Time step" : "Time stepping/Time step function";
      std::unique_ptr<FunctionParser<1>> tau_of_t;
      if (!time_step_function.empty())
        {
          std::streambuf *const cerr_buffer = std::cerr.rdbuf(nullptr);
          try
            {
              tau_of_t = std::make_unique<FunctionParser<1>>(1);
              tau_of_t->initialize("t",
                                   time_step_function,
                                   {{"pi", numbers::PI}, {"tau", time_step}});
              // (muparser parses at the first evaluation.)
              (void)tau_of_t->value(Point<1>(start_time));
              std::cerr.rdbuf(cerr_buffer);
            }
          catch (...)
            {
              std::cerr.rdbuf(cerr_buffer);
              throw InputError(path, "cannot parse the function '" + time_step_function + "'");
            }
        }
      // The round-off of the sum t of the steps so far, and the allowance within
      // which a step is stretched to a stop (core/time_round_off.h).
      const auto round_off = [&](const double t) {
        return time_sum_round_off(step_sizes.size(), t, end_time);
      };
      const auto allowance = [&](const double tau, const double t) {
        return stop_allowance(tau, step_sizes.size(), t, end_time);
      };
      step_sizes.clear();
      step_times.clear();
      double      t    = start_time;
      std::size_t next = 0; // the next step end time not yet reached
      while (t < end_time - allowance(step_sizes.empty() ? time_step : step_sizes.back(), t))
        {
          double tau = time_step;
          if (tau_of_t)
            {
              tau = tau_of_t->value(Point<1>(t));
              require(std::isfinite(tau) && tau > 0,
                      path,
                      "must be finite and > 0 at every step's start time, is " + str(tau) +
                        " at t = " + str(t));
            }
          const double stop = next < step_end_times.size() ? step_end_times[next] : end_time;
          // Stretched (or shortened) to the stop, unless the difference is only
          // the round-off of the sum t: then the step keeps its size to the last
          // bit, so that nothing factorised for it is redone for the last step.
          const bool at_stop = t + tau > stop - allowance(tau, t);
          if (at_stop && std::abs((stop - t) - tau) > round_off(t))
            tau = stop - t;
          require(t + tau > t,
                  path,
                  str(tau) + " is below the floating-point resolution of t near " + str(t) +
                    ": time would not advance");
          t = at_stop ? stop : t + tau;
          step_times.push_back(t);
          step_sizes.push_back(tau);
          while (next < step_end_times.size() && t >= step_end_times[next] - allowance(tau, t))
            ++next;
          require(step_sizes.size() <= max_steps,
                  path,
                  "the run would take more than 'Time stepping/Max time steps' = " +
                    std::to_string(max_steps) + " steps (at t = " + str(t) + ")");
        }
    }
  } // namespace Parameters
} // namespace ContactStefan
