// Construction and the time loop of CoupledProblem.
//
// One time step of the semi-implicit scheme (DESIGN.md section 2) is a contact
// step followed by an enthalpy step. A scene without mechanics skips the contact
// step entirely; a scene without phase change still runs the enthalpy step, which
// then is one linear solve (the active set is empty and never changes).
#include <deal.II/base/utilities.h>

#include <contact-stefan/coupled_problem.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace ContactStefan
{
  template <int dim>
  CoupledProblem<dim>::CoupledProblem(const AllParameters &parameters,
                                      const MPI_Comm       mpi_communicator)
    : prm(parameters)
    , mpi_communicator(mpi_communicator)
    , pcout(std::cout, Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
    , timer(pcout, TimerOutput::never, TimerOutput::wall_times)
    , triangulation(mpi_communicator)
    , fe(1)
    , dof_handler(triangulation)
  {
    // The output directory must be usable before any work is done. Rank 0 checks
    // and every rank learns the verdict, so that all of them stop together.
    std::string problem;
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        std::error_code error;
        std::filesystem::create_directories(prm.output.directory, error);
        const std::string probe = prm.output.directory + "/.contact-stefan-write-test";
        if (error || !std::filesystem::is_directory(prm.output.directory))
          problem = "cannot create the directory '" + prm.output.directory + "'";
        else if (!std::ofstream(probe))
          problem = "cannot write into '" + prm.output.directory + "'";
        std::filesystem::remove(probe, error);
      }
    problem = Utilities::MPI::broadcast(mpi_communicator, problem, 0);
    if (!problem.empty())
      throw InputError("Output/Directory", problem);
  }



  template <int dim>
  void CoupledProblem<dim>::run()
  {
    wall_clock.restart();
    const bool thermal = prm.physics.thermal, mechanics = prm.physics.mechanics;
    time               = prm.time.start_time;
    make_mesh();
    if (thermal)
      {
        setup_thermal_system();
        setup_nodal_enthalpy_laws();
        setup_boundary_and_source_functions();
      }
    if (mechanics)
      setup_mechanical_system();

    double width = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        width = std::max(width, cell->extent_in_direction(0));
    mesh_width = Utilities::MPI::max(width, mpi_communicator);

    if (thermal)
      pcout << "Thermal: " << prm.body_ids.size() << " body(ies); "
            << (phase_change_present ?
                  "phase change on: primal-dual active set on the nodal phase states" :
                  "no phase change: the enthalpy step is one linear solve")
            << "; conductivity "
            << (conductivity_depends_on_phase ? "depends on the phase (re-assembled each step)" :
                                                "constant (assembled once)")
            << "; heat load " << (heat_load_present ? "on" : "off (skipped)") << std::endl;
    else
      pcout << "Thermal: off (no enthalpy step, no temperature DoFs)" << std::endl;
    if (!mechanics)
      pcout << "Mechanics: off (no contact step, no displacement DoFs)" << std::endl;

    if (thermal)
      {
        set_initial_condition();
        initial_total_enthalpy = total_enthalpy();
        assemble_cell_conductivities();
        accumulate_errors(0);
      }
    write_statistics_row(0, EnthalpyStepReport(), ContactStepReport());
    if (prm.output.vtu_interval > 0)
      output_vtu(0);

    const double end  = prm.time.end_time;
    const double span = end - prm.time.start_time;
    // A step that would end within this fraction of a step of the end time is
    // stretched to end exactly there (round-off, not a parameter).
    const double end_slack = 1e-9;
    while (time < end - end_slack * prm.time.time_step)
      {
        time_step = prm.time.time_step;
        if (time + time_step > end - end_slack * time_step)
          time_step = end - time;
        time += time_step;
        ++step_number;

        // Contact step (DESIGN.md section 2, step 1).
        ContactStepReport contact_report;
        if (mechanics)
          {
            contact_report = solve_contact_step();
            total_contact_iterations += contact_report.iterations;
            max_contact_iterations = std::max(max_contact_iterations, contact_report.iterations);
            if (step_number == 1)
              first_contact_iterations = contact_report.iterations;
            else
              max_contact_iterations_warm =
                std::max(max_contact_iterations_warm, contact_report.iterations);
            last_contact_report = contact_report;
          }

        // Enthalpy step (step 2).
        EnthalpyStepReport report;
        if (thermal)
          {
            // Warm start of the active set: the phase states of the enthalpy
            // extrapolated linearly from the last two steps (the previous step's
            // states on the first step). A front moving at a steady speed then
            // starts each step with the node it is about to reach already on its
            // plateau, and the active-set iteration usually needs one solve.
            if (step_number > 1 && prm.solver.extrapolate_active_set)
              {
                const double ratio = time_step / previous_time_step;
                for (const auto dof : locally_owned_dofs)
                  {
                    const double h_predicted =
                      enthalpy[dof] + ratio * (enthalpy[dof] - old_enthalpy[dof]);
                    phase_state[dof] = law(dof).state_of_enthalpy(h_predicted);
                  }
                phase_state.compress(VectorOperation::insert);
                phase_state_ghosted = phase_state;
              }
            old_enthalpy = enthalpy;
            if (conductivity_depends_on_phase)
              assemble_cell_conductivities();
            assemble_heat_load(time);
            make_dirichlet_constraints(time);
            report = solve_enthalpy_step();

            total_active_set_iterations += report.active_set_iterations;
            steps_with_fallback += (report.relaxation_iterations > 0);
            max_energy_residual = std::max(max_energy_residual, report.energy_residual);
            accumulate_errors(time_step);
          }
        previous_time_step = time_step;

        write_statistics_row(step_number, report, contact_report);
        if (prm.output.vtu_interval > 0 &&
            (step_number % prm.output.vtu_interval == 0 || time >= end))
          output_vtu(step_number);

        const double done    = (time - prm.time.start_time) / span;
        const double elapsed = wall_clock.wall_time();
        char         line[256];
        int          length = std::snprintf(line, sizeof(line), "Step %5u  t = %.5e  tau = %.3e  %5.1f%%",
                                   step_number, time, time_step, 100 * done);
        if (mechanics)
          length += std::snprintf(line + length, sizeof(line) - length, "  contact %2u (%u active)",
                                  contact_report.iterations, contact_report.active_nodes);
        if (thermal)
          length += std::snprintf(line + length, sizeof(line) - length, "  active set %2u  plateau %6u",
                                  report.active_set_iterations, report.plateau_nodes);
        std::snprintf(line + length, sizeof(line) - length, "  wall %7.2f s  left ~%7.2f s", elapsed,
                      elapsed * (1 - done) / done);
        pcout << line << std::endl;
      }

    if (thermal)
      print_results();
    if (mechanics)
      print_mechanical_results();
    pcout << "RESULT wall time = " << wall_clock.wall_time() << std::endl;
    timer.print_wall_time_statistics(mpi_communicator);
  }



  template class CoupledProblem<2>;
} // namespace ContactStefan
