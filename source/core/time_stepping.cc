// The entries of 'Time stepping' and the schedule of step sizes and step end
// times worked out from them before the run (core/parameters.h, TimeStepping).
#include <deal.II/base/function_parser.h>
#include <deal.II/base/utilities.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/parameters.h>

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
      // which a step is stretched to a stop: 1e-9 of the step plus that
      // round-off (which after 1e5 steps of 1e-5 exceeds the first and would
      // leave a sliver of a last step).
      const auto round_off = [&](const double t) {
        return 4. * std::numeric_limits<double>::epsilon() * (step_sizes.size() + 1) *
               std::max(std::abs(t), std::abs(end_time));
      };
      const auto allowance = [&](const double tau, const double t) {
        return 1e-9 * tau + round_off(t);
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
