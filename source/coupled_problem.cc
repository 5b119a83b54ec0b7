// Construction and the time loop of CoupledProblem.
//
// One time step of the semi-implicit scheme (doc/model.md §2) is a contact step
// followed by an enthalpy step. A scene without mechanics has no mechanical
// field and skips the contact step entirely; a scene without phase change still
// runs the enthalpy step, which then is one linear solve (the active set is
// empty and never changes).
#include <deal.II/base/utilities.h>

#include <contact-stefan/coupled_problem.h>
#include <contact-stefan/mesh.h>

#include <cstdio>

namespace ContactStefan
{
  template <int dim>
  CoupledProblem<dim>::CoupledProblem(const AllParameters &parameters,
                                      const MPI_Comm       mpi_communicator)
    : prm(parameters)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
    , triangulation(mpi_communicator)
    , materials(parameters)
    , functions(parameters)
    , postprocessor(std::make_unique<Postprocessor<dim>>(prm,
                                                         materials,
                                                         functions,
                                                         triangulation,
                                                         timer,
                                                         pcout))
    , time(parameters.time.start_time)
  {
    assert_two_dimensional<dim>();
    if (prm.physics.thermal)
      thermal =
        std::make_unique<ThermalField<dim>>(prm, materials, functions, triangulation, timer, pcout);
    if (prm.physics.mechanics)
      mechanical = std::make_unique<MechanicalField<dim>>(
        prm, materials, functions, triangulation, timer, pcout);
    postprocessor->attach(thermal.get(), mechanical.get());
  }



  template <int dim>
  void CoupledProblem<dim>::run()
  {
    wall_clock.restart();
    {
      TimerOutput::Scope t(timer, "setup: mesh");
      make_mesh(prm, triangulation);
    }
    // Set-up and initial state; every input check that needs the mesh happens
    // here, before anything is printed or written.
    if (thermal)
      {
        thermal->setup_dofs();
        thermal->initialize(time);
      }
    if (mechanical)
      {
        mechanical->setup_dofs();
        mechanical->initialize(time);
      }
    postprocessor->start(time, wall_clock.wall_time());
    pcout << "Mesh: " << triangulation.n_global_active_cells() << " cells on "
          << Utilities::MPI::n_mpi_processes(triangulation.get_communicator()) << " MPI rank(s)\n"
          << (thermal ? thermal->describe() :
                        "Thermal: off (no enthalpy step, no temperature DoFs)")
          << '\n'
          << (mechanical ? mechanical->describe() :
                           "Mechanics: off (no contact step, no displacement DoFs)")
          << std::endl;

    const double end = prm.time.end_time;
    // A step that would end within this fraction of a step of the end time is
    // stretched to end exactly there (round-off, not a parameter).
    const double end_slack = 1e-9;
    while (time < end - end_slack * prm.time.time_step)
      {
        time_step = prm.time.time_step;
        if (time + time_step > end - end_slack * time_step)
          time_step = end - time;
        // Checked at parse time; guarded here so that no run can loop forever.
        if (!(time + time_step > time))
          throw std::runtime_error("time does not advance at t = " + std::to_string(time) +
                                   " with tau = " + std::to_string(time_step));
        time += time_step;
        ++step_number;

        if (thermal)
          thermal->begin_time_step(time, time_step);
        if (mechanical)
          mechanical->begin_time_step(time, time_step);
        // Contact step (doc/model.md §2, step 1), then the enthalpy step (step 2).
        const ContactStepReport contact_report =
          mechanical ? mechanical->solve() : ContactStepReport();
        const EnthalpyStepReport thermal_report = thermal ? thermal->solve() : EnthalpyStepReport();

        postprocessor->end_step(step_number,
                                time,
                                time_step,
                                time >= end,
                                thermal_report,
                                contact_report,
                                wall_clock.wall_time());
        print_step_line(thermal_report, contact_report);
      }

    postprocessor->print_results(step_number, time);
    pcout << "RESULT wall time = " << wall_clock.wall_time() << std::endl;
    timer.print_wall_time_statistics(triangulation.get_communicator());
  }



  // One line per step: step, t, tau, progress, the work of both steps, the wall
  // time so far and an estimate of the time left.
  template <int dim>
  void CoupledProblem<dim>::print_step_line(const EnthalpyStepReport &thermal_report,
                                            const ContactStepReport  &contact_report) const
  {
    const double done    = (time - prm.time.start_time) / (prm.time.end_time - prm.time.start_time);
    const double elapsed = wall_clock.wall_time();
    char         line[256];
    int          length = std::snprintf(line,
                               sizeof(line),
                               "Step %5u  t = %.5e  tau = %.3e  %5.1f%%",
                               step_number,
                               time,
                               time_step,
                               100 * done);
    if (mechanical)
      length += std::snprintf(line + length,
                              sizeof(line) - length,
                              "  contact %2u (%u active)",
                              contact_report.iterations,
                              contact_report.active_nodes);
    if (thermal)
      length += std::snprintf(line + length,
                              sizeof(line) - length,
                              "  active set %2u  plateau %6u",
                              thermal_report.active_set_iterations,
                              thermal_report.plateau_nodes);
    std::snprintf(line + length,
                  sizeof(line) - length,
                  "  wall %7.2f s  left ~%8.3g s",
                  elapsed,
                  elapsed * (1 - done) / done);
    pcout << line << std::endl;
  }



  template class CoupledProblem<2>;
} // namespace ContactStefan
