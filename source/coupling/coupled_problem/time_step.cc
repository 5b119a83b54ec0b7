// One time step of CoupledProblem with its size: the schedule's (worked out
// before the run), or the adaptive step control's (doc/time_stepping.md).
//
// With adaptive steps, a step is an attempt that may be redone. Before the
// first attempt the state at the step's start is kept in memory: the primary
// state of both fields (both time levels) and their restart values, the time
// and the step number -- exactly what a checkpoint holds of the fields. An
// attempt whose change exceeds the controller's bound is undone the way a
// resumed run starts from a checkpoint: the fields take the kept state with
// the data of the step's start time, re-derive everything else from it and
// start their solvers afresh; then the step is tried again, shorter. Nothing
// of a rejected attempt reaches the output: the report is made only for the
// attempt that stands.
#include <contact-stefan/core/time_round_off.h>
#include <contact-stefan/coupling/coupled_problem.h>
#include <contact-stefan/output/run_guard.h>

#include <cmath>
#include <cstdlib>
#include <limits>

namespace ContactStefan
{
  template <int dim>
  bool CoupledProblem<dim>::run_finished() const
  {
    return prm.time.adaptive ? !(time < prm.time.end_time) :
                               step_number >= prm.time.step_sizes.size();
  }



  // The next attempt from the proposed size: not past the next stop (a Step
  // end time or End time), which it ends at exactly where it would pass it or
  // end within the round-off allowance of the schedule before it; a step that
  // would leave less than half of itself before the stop is split into two
  // equal ones instead of leaving a sliver. Sets time_step; returns the end
  // time and whether the step was shortened for the stop.
  template <int dim>
  double CoupledProblem<dim>::adaptive_step_end(bool &shortened)
  {
    const auto  &times     = prm.time.step_end_times;
    const auto   next      = std::upper_bound(times.begin(), times.end(), time);
    const double stop      = next != times.end() ? *next : prm.time.end_time;
    const double tau       = std::min(proposed_time_step, prm.time.control.maximum_time_step);
    // (As the schedule stretches a step to a stop: core/time_round_off.h.)
    const double allowance = stop_allowance(tau, step_number, time, prm.time.end_time);
    shortened = false;
    if (time + tau > stop - allowance)
      {
        time_step = stop - time;
        shortened = time_step < tau;
        return stop;
      }
    if (time + 1.5 * tau > stop)
      {
        time_step = (stop - time) / 2;
        shortened = true;
        return time + time_step;
      }
    time_step = tau;
    return time + tau;
  }



  // A resumed run with adaptive steps: no schedule to compare the time state
  // with; the sizes must be ones the controller can choose. Empty: valid.
  template <int dim>
  std::string CoupledProblem<dim>::adaptive_state_problem() const
  {
    const auto &control = prm.time.control;
    if (time > prm.time.start_time && time_step > 0 && std::isfinite(time_step) &&
        proposed_time_step >= control.minimum_time_step &&
        proposed_time_step <= control.maximum_time_step)
      return "";
    return "the time " + number(time) + ", the step size " + number(time_step) +
           " or the proposed step " + number(proposed_time_step) +
           " is not one the adaptive step control can reach (Minimum and Maximum time step)";
  }



  template <int dim>
  void CoupledProblem<dim>::save_step_start(StepStart &start)
  {
    const auto keep = [](const std::vector<Vector *> &state, std::vector<Vector> &copy) {
      copy.clear();
      for (const Vector *v : state)
        copy.push_back(*v);
    };
    if (thermal)
      {
        keep(thermal->primary_state(), start.thermal_state);
        start.thermal_scalars = thermal->restart_state();
      }
    if (mechanical)
      {
        keep(mechanical->primary_state(), start.mechanical_state);
        start.mechanical_scalars = mechanical->restart_state();
      }
    start.time        = time;
    start.time_step   = time_step;
    start.step_number = step_number;
  }



  // As load_mesh_and_primary_state() after a resume, without a new mesh: each
  // field set to the start time (its data: loads, Dirichlet values, gaps),
  // the kept state copied in, everything else re-derived, solvers afresh.
  template <int dim>
  void CoupledProblem<dim>::restore_step_start(const StepStart &start)
  {
    TimerOutput::Scope t(timer, "step control: undo");
    time                = start.time;
    time_step           = start.time_step;
    step_number         = start.step_number;
    const auto put_back = [](const std::vector<Vector> &copy, const std::vector<Vector *> &state) {
      for (unsigned int i = 0; i < state.size(); ++i)
        *state[i] = copy[i];
    };
    if (thermal)
      {
        thermal->initialize(time);
        put_back(start.thermal_state, thermal->primary_state());
        thermal->set_restart_state(start.thermal_scalars);
      }
    if (mechanical)
      {
        mechanical->initialize(time);
        put_back(start.mechanical_state, mechanical->primary_state());
        mechanical->set_restart_state(start.mechanical_scalars);
      }
    after_mesh_change();
    if (thermal)
      thermal->restart_solvers();
    if (mechanical)
      mechanical->restart_solvers();
  }



  // One step: its size, both fields' step, and with adaptive steps the
  // controller's decision (attempts redone until one stands). Returns whether
  // the step ends the run.
  template <int dim>
  bool CoupledProblem<dim>::take_time_step(EnthalpyStepReport &thermal_report,
                                           ContactStepReport  &contact_report,
                                           CouplingReport     &coupling_report,
                                           StepControlReport  &control_report)
  {
    const bool adaptive = prm.time.adaptive;
    StepStart  start;
    if (adaptive)
      save_step_start(start);
    const unsigned int births         = coupling_report.births;
    const unsigned int corrections    = block ? block->n_corrections() : 0;
    const unsigned int factorisations = block ? block->n_factorisations() : 0;
    const unsigned int ldlt           = block ? block->n_symmetric_factorisations() : 0;
    const unsigned int guesses        = block ? mechanical->n_guesses_accepted() : 0;
    const unsigned int heat_guesses   = block ? thermal->n_guesses_accepted() : 0;
    // Test hook (tests/compare_undo.py): CONTACT_STEFAN_REJECT_STEP=K[:F] undoes
    // the first attempt of step K and redoes it F times as long (default 1);
    // the result must be the run whose step K was that long from the start.
    const char        *forced = std::getenv("CONTACT_STEFAN_REJECT_STEP");
    char              *rest   = nullptr;
    const unsigned int forced_step =
      adaptive && forced ? static_cast<unsigned int>(std::strtoul(forced, &rest, 10)) : 0;
    const double forced_factor = rest && *rest == ':' ? std::strtod(rest + 1, nullptr) : 1.;
    for (unsigned int attempt = 0;; ++attempt)
      {
        bool   shortened = false;
        double end;
        if (adaptive)
          end = adaptive_step_end(shortened);
        else
          {
            time_step = prm.time.step_sizes[step_number];
            end       = prm.time.step_times[step_number];
          }
        // Checked at parse time; guarded here so that no run can loop forever.
        if (!(end > time))
          throw std::runtime_error("time does not advance at t = " + number(time) +
                                   " with tau = " + number(time_step));
        if (adaptive && step_number >= prm.time.max_steps)
          throw InputError("Time stepping/Max time steps",
                           "the adaptive steps reached " + std::to_string(prm.time.max_steps) +
                             " at t = " + number(time) + ", before End time = " +
                             number(prm.time.end_time) + " (raise it, or the targets)");
        time = end;
        ++step_number;
        if (thermal)
          thermal->begin_time_step(time, time_step);
        if (mechanical)
          mechanical->begin_time_step(time, time_step);
        thermal_report         = EnthalpyStepReport();
        contact_report         = ContactStepReport();
        coupling_report        = CouplingReport();
        coupling_report.births = births;
        // A step whose iteration did not converge (every rank throws alike):
        // with adaptive steps, redone shorter unless it is at the minimum.
        const auto &control    = prm.time.control;
        // (The controller's own test of the minimum: a step it would not
        // shorten whatever its change.)
        const bool at_minimum =
          decide_step(control, time_step, std::numeric_limits<double>::infinity()).accept;
        std::string failure;
        try
          {
            coupled_step(thermal_report, contact_report, coupling_report);
          }
        catch (const StepNotConverged &e)
          {
            if (!adaptive)
              throw;
            if (at_minimum)
              throw StepNotConverged(std::string(e.what()) +
                                     ", with the step already at 'Time stepping/Minimum "
                                     "time step' = " +
                                     number(control.minimum_time_step));
            failure = e.what();
          }
        if (!adaptive)
          break;
        if (!failure.empty())
          {
            ++control_report.rejected;
            proposed_time_step =
              std::max(control.minimum_time_step, control.failure_reduction * time_step);
            pcout << "    step " << step_number << " (tau = " << number(time_step)
                  << ") redone with tau = " << number(proposed_time_step) << ": " << failure
                  << std::endl;
            restore_step_start(start);
            continue;
          }

        const auto [temperature_change, phase_change] = thermal->step_change();
        const double r                                = step_change_ratio(prm.time.control,
                                           temperature_change,
                                           phase_change,
                                           thermal->phase_change_present());
        StepDecision decision                         = decide_step(prm.time.control, time_step, r);
        if (attempt == 0 && forced_step == step_number)
          decision = {false, forced_factor * proposed_time_step, false};
        if (decision.accept)
          {
            control_report.temperature_change = temperature_change;
            control_report.phase_change       = phase_change;
            control_report.at_minimum         = decision.at_minimum;
            // A step shortened for a stop does not shorten the next one.
            proposed_time_step =
              shortened && r <= 1 ? std::max(decision.next, proposed_time_step) : decision.next;
            if (decision.at_minimum)
              pcout << "    step " << step_number << " stood at the minimum time step "
                    << number(time_step) << " with a change of " << number(r)
                    << " times its target (over the rejection factor)" << std::endl;
            break;
          }
        ++control_report.rejected;
        if (prm.output.verbosity >= 1)
          pcout << "    step " << step_number << " (tau = " << number(time_step)
                << ") redone with tau = " << number(std::min(decision.next, time_step))
                << ": its change was " << number(r) << " times its target" << std::endl;
        proposed_time_step = decision.next;
        restore_step_start(start);
      }
    if (block)
      {
        // This step's counts (all attempts): the report carries them over a restart.
        coupling_report.block_correction     = true;
        coupling_report.block_corrections    = block->n_corrections() - corrections;
        coupling_report.block_factorisations = block->n_factorisations() - factorisations;
        coupling_report.block_ldlt            = block->n_symmetric_factorisations() - ldlt;
        coupling_report.guesses_accepted     = mechanical->n_guesses_accepted() - guesses;
        coupling_report.heat_guesses_accepted = thermal->n_guesses_accepted() - heat_guesses;
      }
    return adaptive ? !(time < prm.time.end_time) : step_number == prm.time.step_sizes.size();
  }



  template bool   CoupledProblem<2>::run_finished() const;
  template double CoupledProblem<2>::adaptive_step_end(bool &);
  template std::string CoupledProblem<2>::adaptive_state_problem() const;
  template void   CoupledProblem<2>::save_step_start(StepStart &);
  template void   CoupledProblem<2>::restore_step_start(const StepStart &);
  template bool   CoupledProblem<2>::take_time_step(EnthalpyStepReport &,
                                                  ContactStepReport &,
                                                  CouplingReport &,
                                                  StepControlReport &);
} // namespace ContactStefan
