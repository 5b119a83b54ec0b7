// The round-off bounds of a running sum of step sizes, shared by the schedule
// (Parameters::TimeStepping::make_schedule()) and the adaptive steps
// (CoupledProblem::adaptive_step_end()), so that both stretch a step to a stop
// alike (doc/time_stepping.md).
#ifndef contact_stefan_time_round_off_h
#define contact_stefan_time_round_off_h

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

namespace ContactStefan
{
  /**
   * The round-off of t, the sum of the first n_steps step sizes from the
   * start time, in a run that ends at end_time.
   */
  inline double time_sum_round_off(const std::size_t n_steps, const double t, const double end_time)
  {
    return 4. * std::numeric_limits<double>::epsilon() * (n_steps + 1) *
           std::max(std::abs(t), std::abs(end_time));
  }

  /**
   * The allowance within which a step of size tau that starts at t is
   * stretched to end exactly at a stop: 1e-9 of the step plus the round-off of
   * t (which after 1e5 steps of 1e-5 exceeds the first and would leave a
   * sliver of a last step).
   */
  inline double
  stop_allowance(const double tau, const std::size_t n_steps, const double t, const double end_time)
  {
    return 1e-9 * tau + time_sum_round_off(n_steps, t, end_time);
  }
} // namespace ContactStefan

#endif
