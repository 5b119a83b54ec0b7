// The adaptive time-step controller (Time stepping/Step control = adaptive;
// doc/time_stepping.md). A pure kernel: it sees a step's size and the change
// the step made, and decides whether the step stands and how long the next
// one is. CoupledProblem measures the change and redoes a rejected step.
//
// The change is measured against two targets: the largest change of a free
// node's temperature in the step (K; Dirichlet nodes are excluded, since their
// change is data that no step size can make smaller), and the largest change
// of a node's phase index (0 solid .. n_transitions liquid; 1 is a node that
// melted completely within the step, so 0.5 lets the front cross about half a
// cell per step). The ratio r = max(dTheta / target, dPhase / target) is what
// the controller sees; both changes shrink about linearly with tau, so tau / r
// is the step that would just meet the targets.
//
// Decisions:
//   r > rejection factor and tau above the minimum  -> reject; redo with
//       tau * s / r (s = 1 / sqrt(minimum growth), the geometric middle of the
//       band below), at least the minimum;
//   otherwise accept, and the next step is
//       tau * min(maximum growth, s / r)  if r < 1 / minimum growth (grow);
//       tau * s / r                       if r > 1 (shrink);
//       tau                               in between (keep).
// The band in which tau is kept is what lets a factorisation (its fingerprint
// holds tau) serve many steps: tau changes only by at least the minimum growth
// factor upwards, and downwards only once the target is exceeded. Every
// result is clamped to [minimum, maximum]. A step whose iteration did not
// converge (StepNotConverged) is redone 'failure reduction' times as long,
// unless it was at the minimum already (CoupledProblem::take_time_step).
#ifndef contact_stefan_step_control_h
#define contact_stefan_step_control_h

#include <string>

namespace ContactStefan
{
  struct StepControlSettings
  {
    double target_temperature_change = 1;   // K
    double target_phase_change       = 0.5; // phase index per step
    double rejection_factor          = 2;   // reject where r > this
    double minimum_time_step         = 0;   // s, > 0 when used
    double maximum_time_step         = 0;   // s, > 0 when used
    double minimum_growth            = 1.5; // tau grows by at least this, or stays
    double maximum_growth            = 2;   // and by at most this per step
    double failure_reduction         = 0.25; // a step that did not converge: redo this long
  };

  struct StepDecision
  {
    bool   accept     = true;
    double next       = 0;     // the size of the next attempt (the redo, if rejected)
    bool   at_minimum = false; // accepted over the rejection factor: tau was the minimum
  };

  /**
   * r = max(dTheta / target, dPhase / target) (with_phase = false: the
   * temperature alone). Throws std::runtime_error (one line, the values) if a
   * change is not finite: a step that produced one stops the run.
   */
  double step_change_ratio(const StepControlSettings &settings,
                           const double               temperature_change,
                           const double               phase_change,
                           const bool                 with_phase);

  /** The decision for a step of size tau whose change ratio is r (see above). */
  StepDecision decide_step(const StepControlSettings &settings, const double tau, const double r);
} // namespace ContactStefan

#endif
