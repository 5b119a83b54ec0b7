// Unit test of the adaptive time-step controller (core/step_control.h): the
// change ratio, rejection, the band in which tau is kept, growth and shrinking
// with their limits, the minimum and maximum step, and a non-finite change.
// Prints deterministic lines; returns 1 if any check fails.
#include <contact-stefan/core/step_control.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;
using UnitTest::close;

int main()
{
  StepControlSettings s;
  s.target_temperature_change = 2;
  s.target_phase_change       = 0.5;
  s.rejection_factor          = 2;
  s.minimum_time_step         = 1e-3;
  s.maximum_time_step         = 10;
  s.minimum_growth            = 1.5;
  s.maximum_growth            = 2;
  const double aim            = 1 / std::sqrt(1.5);

  // The ratio: the larger of the two, the phase only where asked.
  check(close(step_change_ratio(s, 1, 0.1, true), 0.5), "ratio: temperature decides");
  check(close(step_change_ratio(s, 1, 0.4, true), 0.8), "ratio: phase decides");
  check(close(step_change_ratio(s, 1, 0.4, false), 0.5), "ratio: phase ignored without phases");
  bool thrown = false;
  try
    {
      step_change_ratio(s, std::numeric_limits<double>::quiet_NaN(), 0, true);
    }
  catch (const std::runtime_error &e)
    {
      thrown = std::string(e.what()).find("not finite") != std::string::npos;
    }
  check(thrown, "ratio: a NaN change stops the run with a message");

  // Within the band [1 / 1.5, 1]: tau kept to the last bit.
  for (const double r : {1 / 1.5, 0.8, 1.})
    {
      const StepDecision d = decide_step(s, 0.1, r);
      check(d.accept && d.next == 0.1 && !d.at_minimum, "keep tau at r = " + std::to_string(r));
    }
  // Below the band: grow to the middle of the band, at most by 2.
  {
    const StepDecision d = decide_step(s, 0.1, 0.5);
    check(d.accept && close(d.next, 0.1 * aim / 0.5), "grow at r = 0.5 to tau aim / r");
    check(decide_step(s, 0.1, 0.1).next == 0.2, "grow at most by the maximum growth");
    check(decide_step(s, 0.1, 0.).next == 0.2, "nothing changed: the maximum growth");
    check(decide_step(s, 8, 0.1).next == 10, "growth clamped to the maximum time step");
  }
  // Above the band but below the rejection factor: accepted, next shorter.
  {
    const StepDecision d = decide_step(s, 0.1, 1.6);
    check(d.accept && close(d.next, 0.1 * aim / 1.6), "r = 1.6: accepted, next tau aim / r");
    check(decide_step(s, 0.1, 2.).accept, "r = rejection factor: accepted");
  }
  // Over the rejection factor: redone shorter, not below the minimum.
  {
    const StepDecision d = decide_step(s, 0.1, 4);
    check(!d.accept && close(d.next, 0.1 * aim / 4), "r = 4: rejected, redo with tau aim / r");
    const StepDecision e = decide_step(s, 0.002, 1e6);
    check(!e.accept && e.next == 1e-3, "a redo is not shorter than the minimum");
    const StepDecision f = decide_step(s, 1e-3, 1e6);
    check(f.accept && f.at_minimum && f.next == 1e-3,
          "at the minimum: accepted over the rejection factor, and flagged");
  }
  // A step ends at a stop shorter than tau: its decision scales from its own size.
  check(close(decide_step(s, 0.05, 1.2).next, 0.05 * aim / 1.2), "shrink from the taken size");
  return UnitTest::finish();
}
