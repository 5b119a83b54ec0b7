// The adaptive time-step controller (core/step_control.h).
#include <contact-stefan/core/step_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace ContactStefan
{
  double step_change_ratio(const StepControlSettings &settings,
                           const double               temperature_change,
                           const double               phase_change,
                           const bool                 with_phase)
  {
    if (!std::isfinite(temperature_change) || !std::isfinite(phase_change))
      {
        std::ostringstream text;
        text << "the step's largest temperature change (" << temperature_change
             << " K) or phase change (" << phase_change << ") is not finite";
        throw std::runtime_error(text.str());
      }
    double r = temperature_change / settings.target_temperature_change;
    if (with_phase)
      r = std::max(r, phase_change / settings.target_phase_change);
    return r;
  }



  StepDecision decide_step(const StepControlSettings &settings, const double tau, const double r)
  {
    // The geometric middle of the band [1 / minimum growth, 1] in which tau is
    // kept: where a step sized by tau / r would land if the change were
    // exactly linear in tau.
    const double aim   = 1. / std::sqrt(settings.minimum_growth);
    const auto   clamp = [&](const double t) {
      return std::clamp(t, settings.minimum_time_step, settings.maximum_time_step);
    };
    // tau / r without overflow where r is 0 (nothing changed): the largest step.
    const auto scaled = [&](const double factor_limit) {
      return r > 0 ? tau * std::min(factor_limit, aim / r) : tau * factor_limit;
    };
    StepDecision decision;
    // (The minimum is compared with a little room: a tau clamped to it and
    // then shortened by the round-off of a stop is still "the minimum".)
    const bool at_minimum = tau <= settings.minimum_time_step * (1 + 1e-12);
    if (r > settings.rejection_factor && !at_minimum)
      {
        decision.accept = false;
        decision.next   = clamp(std::min(tau, scaled(1.)));
        return decision;
      }
    decision.at_minimum = r > settings.rejection_factor;
    if (r * settings.minimum_growth < 1)
      decision.next = clamp(scaled(settings.maximum_growth));
    else if (r > 1)
      decision.next = clamp(scaled(1.));
    else
      decision.next = clamp(tau);
    return decision;
  }
} // namespace ContactStefan
