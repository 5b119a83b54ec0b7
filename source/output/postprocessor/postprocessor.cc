// Postprocessor: VTU/PVD fields, the per-step statistics table, and the errors
// against an exact solution that end a verification run as RESULT lines.
//
// This file holds the core: the output directory, the per-step bookkeeping, the
// VTU/PVD files, the statistics table and the RESULT lines' collection; the
// thermal results are in thermal_results.cc, the mechanical ones in
// mechanical_results.cc.
#include <deal.II/numerics/data_out.h>

#include <contact-stefan/output/postprocessor.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace ContactStefan
{
  template <int dim>
  Postprocessor<dim>::Postprocessor(const SceneParameters                           &prm,
                                    const Parameters::Output                        &output_prm,
                                    const bool                                       adaptive,
                                    const NeumannSolution                           *neumann,
                                    const Materials                                 &materials,
                                    SceneFunctions<dim>                             &functions,
                                    const parallel::distributed::Triangulation<dim> &triangulation,
                                    TimerOutput                                     &timer,
                                    const ConditionalOStream                        &pcout)
    : prm(prm)
    , output_prm(output_prm)
    , adaptive(adaptive)
    , neumann(neumann)
    , materials(materials)
    , functions(functions)
    , triangulation(triangulation)
    , mpi_communicator(triangulation.get_communicator())
    , timer(timer)
    , pcout(pcout)
  {
    // The output directory must be usable before any work is done. Rank 0 checks
    // and every rank learns the verdict, so that all of them stop together.
    std::string problem;
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        std::error_code error;
        std::filesystem::create_directories(output_prm.directory, error);
        const std::string probe = output_prm.directory + "/.contact-stefan-write-test";
        if (error || !std::filesystem::is_directory(output_prm.directory))
          problem = "cannot create the directory '" + output_prm.directory + "'";
        else if (!std::ofstream(probe))
          problem = "cannot write into '" + output_prm.directory + "'";
        std::filesystem::remove(probe, error);
        // One run at a time: a second run into the same directory would
        // interleave its statistics rows and VTU files with this one's.
        if (problem.empty())
          try
            {
              output_lock = std::make_unique<OutputDirectoryLock>(output_prm.directory);
            }
          catch (const std::exception &e)
            {
              problem = e.what();
            }
      }
    problem = Utilities::MPI::broadcast(mpi_communicator, problem, 0);
    if (!problem.empty())
      throw InputError("Output/Directory", problem);
  }



  template <int dim>
  void Postprocessor<dim>::remove_stale_output(const long last_kept_step) const
  {
    unsigned int removed = 0;
    std::string  problem;
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      try
        {
          removed = ContactStefan::remove_stale_output(output_prm.directory, last_kept_step);
          // A resumed run's index lists the steps up to the checkpoint (an
          // interrupted run's index may list later steps whose files are gone).
          if (last_kept_step >= 0 && !pvd_records.empty())
            {
              std::ostringstream pvd;
              DataOutBase::write_pvd_record(pvd, pvd_records);
              write_file_atomically(output_prm.directory + "/solution.pvd", pvd.str());
            }
        }
      catch (const std::exception &e)
        {
          problem = e.what();
        }
    problem = Utilities::MPI::broadcast(mpi_communicator, problem, 0);
    if (!problem.empty())
      throw std::runtime_error(problem);
    removed = Utilities::MPI::broadcast(mpi_communicator, removed, 0);
    pcout << "Output: '" << output_prm.directory << "'";
    if (removed > 0)
      pcout << " (removed " << removed << " VTU/PVD files of an earlier run"
            << (last_kept_step >= 0 ? " after the checkpoint's step" : "") << ")";
    pcout << std::endl;
  }



  template <int dim>
  void Postprocessor<dim>::attach(const ThermalField<dim>    *thermal_field,
                                  const MechanicalField<dim> *mechanical_field)
  {
    thermal    = thermal_field;
    mechanical = mechanical_field;
  }



  template <int dim>
  void Postprocessor<dim>::start(const double             time,
                                 const ContactStepReport &initial_contact,
                                 const double             wall_time)
  {
    start_time = time;
    if (thermal)
      {
        initial_total_enthalpy = thermal->total_enthalpy();
        accumulate_errors(time, 0);
      }
    if (mechanical)
      {
        accumulate_mechanical_results(time, initial_contact);
        elasticity_linear += initial_contact.linear;
        total_contact_work = 0; // work is counted from the initial equilibrium on
      }
    write_statistics_row(
      0, time, EnthalpyStepReport(), initial_contact, CouplingReport(), wall_time);
    if (output_prm.vtu_interval > 0)
      output_vtu(0, time);
  }



  template <int dim>
  void Postprocessor<dim>::end_step(const unsigned int        step,
                                    const double              time,
                                    const double              time_step,
                                    const bool                last_step,
                                    const EnthalpyStepReport &report,
                                    const ContactStepReport  &contact_report,
                                    const CouplingReport     &coupling_report,
                                    const double              wall_time)
  {
    total_coupling_iterations += coupling_report.iterations;
    max_coupling_iterations = std::max(max_coupling_iterations, coupling_report.iterations);
    reassembled_cells += coupling_report.reassembled_cells;
    if (mechanical)
      {
        contact_factorisations += contact_report.factorisations;
        elasticity_linear += contact_report.linear;
        max_active_nodes = std::max(max_active_nodes, contact_report.active_nodes);
        reused_contact_steps += contact_report.reused;
        accumulate_mechanical_results(time, contact_report);
        total_contact_iterations += contact_report.iterations;
        max_contact_iterations = std::max(max_contact_iterations, contact_report.iterations);
        if (step == 1)
          first_contact_iterations = contact_report.iterations;
        else
          max_contact_iterations_warm =
            std::max(max_contact_iterations_warm, contact_report.iterations);
        last_contact_report = contact_report;
      }
    if (thermal)
      {
        total_active_set_iterations += report.active_set_iterations;
        steps_with_fallback += (report.relaxation_iterations > 0);
        steps_with_truncated_newton += report.truncated_newton;
        max_energy_residual = max_with_nan(max_energy_residual, report.energy_residual);
        inconsistent_enthalpy_nodes += report.inconsistent_nodes;
        enthalpy_factorisations += report.factorisations;
        total_thermoelastic_heat += report.thermoelastic_heat;
        accumulate_errors(time, time_step);
      }
    dof_time_integral +=
      time_step * (thermal ? thermal->get_dof_handler() : mechanical->get_dof_handler()).n_dofs();
    write_statistics_row(step, time, report, contact_report, coupling_report, wall_time);
    pending_change = 0;
    if (output_prm.vtu_interval > 0 && (step % output_prm.vtu_interval == 0 || last_step))
      output_vtu(step, time);
  }



  template <int dim>
  void Postprocessor<dim>::record_adaptation(const double relative_enthalpy_change,
                                             const bool   coarsened)
  {
    if (!std::isfinite(relative_enthalpy_change))
      throw std::runtime_error("the total enthalpy is not finite after mesh adaptation " +
                               std::to_string(n_adaptations + 1));
    ++n_adaptations;
    pending_change  = relative_enthalpy_change;
    double &largest = coarsened ? max_coarsening_change : max_refinement_change;
    largest         = std::max(largest, std::abs(relative_enthalpy_change));
  }



  template <int dim>
  void Postprocessor<dim>::output_vtu(const unsigned int step, const double time)
  {
    TimerOutput::Scope t(timer, "output: vtu");
    DataOut<dim>       data_out;
    data_out.attach_triangulation(triangulation);
    // Each field adds its own fields and keeps the vectors alive.
    if (thermal)
      thermal->add_output(data_out);
    if (mechanical)
      mechanical->add_output(data_out);

    dealii::Vector<float> body(triangulation.n_active_cells());
    dealii::Vector<float> rank(triangulation.n_active_cells());
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          body(cell->active_cell_index()) = cell->material_id();
          rank(cell->active_cell_index()) = triangulation.locally_owned_subdomain();
        }
    data_out.add_data_vector(body, "body_id", DataOut<dim>::type_cell_data);
    data_out.add_data_vector(rank, "mpi_rank", DataOut<dim>::type_cell_data);
    data_out.build_patches();
    DataOutBase::VtkFlags flags;
    flags.compression_level = output_prm.vtu_compression;
    data_out.set_flags(flags);

    const std::string directory = output_prm.directory + "/";
    const std::string name =
      data_out.write_vtu_with_pvtu_record(directory, "solution", step, mpi_communicator, 5);
    pvd_records.emplace_back(time, name);
    // Every rank's piece is complete before the index names the step.
    Utilities::MPI::sum(0, mpi_communicator);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        // Through a rename: a run stopped while writing it (SIGKILL, a full
        // disk) leaves the previous, complete index, never an empty one.
        std::ostringstream pvd;
        DataOutBase::write_pvd_record(pvd, pvd_records);
        write_file_atomically(directory + "solution.pvd", pvd.str());
      }
  }



  // One row of the statistics table: the columns this scene has, each with
  // name, unit, meaning (the header's comment lines, at step 0) and this
  // step's value as written. A real value is checked before anything is
  // written: every number of the row is the same on every rank, and no row
  // with a NaN may reach the file.
  template <int dim>
  class Postprocessor<dim>::StatisticsRow
  {
  public:
    explicit StatisticsRow(const unsigned int step)
      : step(step)
    {}

    void count(const std::string &name, const std::string &meaning, const unsigned int value)
    {
      std::snprintf(field, sizeof(field), "%u", value);
      columns.push_back({name, "-", meaning, field});
    }

    void real(const std::string &name,
              const std::string &unit,
              const std::string &meaning,
              const char        *format,
              const double       value)
    {
      if (!std::isfinite(value))
        throw std::runtime_error("step " + std::to_string(step) + ": the statistics value '" +
                                 name + "' is not finite (" + std::to_string(value) + ")");
      std::snprintf(field, sizeof(field), format, value);
      columns.push_back({name, unit, meaning, field});
    }

    // Appends the row to the file at path, at step 0 after the header (a
    // fresh file).
    void append_to(const std::string &path) const
    {
      std::ofstream out(path, step == 0 ? std::ios::trunc : std::ios::app);
      if (step == 0)
        {
          // The header: one comment line per column (name, unit, meaning), then
          // the line of column names. gnuplot and pandas (comment='#') skip the
          // comments; the names line stays the first line that is not one.
          out << "# contact-stefan statistics, one row per time step. Units for a scene given in "
                 "SI units (m, kg, s, K or degC); a dimensionless scene's columns are "
                 "dimensionless.\n";
          std::size_t width = 0;
          for (const auto &c : columns)
            width = std::max(width, c.name.size() + c.unit.size() + 3);
          for (const auto &c : columns)
            {
              const std::string name_unit = c.name + " [" + c.unit + "]";
              out << "# " << name_unit << std::string(width - name_unit.size() + 1, ' ')
                  << c.meaning << '\n';
            }
          for (std::size_t i = 0; i < columns.size(); ++i)
            out << (i == 0 ? "" : " ") << columns[i].name;
          out << '\n';
        }
      for (std::size_t i = 0; i < columns.size(); ++i)
        out << (i == 0 ? "" : " ") << columns[i].value;
      out << std::endl;
      if (!out)
        throw std::runtime_error("cannot write '" + path + "'");
    }

  private:
    struct Column
    {
      std::string name, unit, meaning, value;
    };
    const unsigned int  step;
    std::vector<Column> columns;
    char                field[64];
  };



  // The enthalpy step's columns and, with both fields, the coupling's. area:
  // the melt area (collective, so computed before any column can throw).
  template <int dim>
  void Postprocessor<dim>::add_thermal_columns(StatisticsRow            &row,
                                               const double              area,
                                               const EnthalpyStepReport &report,
                                               const CouplingReport     &coupling_report) const
  {
    row.count("dofs",
              "temperature degrees of freedom",
              static_cast<unsigned int>(thermal->get_dof_handler().n_dofs()));
    row.count("pdas_iterations",
              "active-set iterations (linear solves) of the enthalpy step",
              report.active_set_iterations);
    row.count("state_changes",
              "nodal phase-state changes, summed over the iterations",
              report.state_changes);
    row.count("damped_steps",
              "enthalpy iterations whose Newton step was shortened",
              report.damped_steps);
    row.count("fallback_iterations",
              "iterations of the relaxation fallback (0: not needed)",
              report.relaxation_iterations);
    row.count("plateau_nodes",
              "nodes on a transition plateau (mushy) at the end of the step",
              report.plateau_nodes);
    row.real("liquid_area",
             "m^2",
             "melt area: lumped-mass weighted liquid fraction through the last transition, per "
             "unit thickness",
             "%.10e",
             area);
    row.real("energy_residual",
             "1",
             "enthalpy balance of the step relative to the size of its terms (doc/coupling.md 6)",
             "%.2e",
             report.energy_residual);
    if (mechanical)
      {
        row.count("coupling_iterations",
                  "passes of contact and enthalpy step (1: staggered)",
                  coupling_report.iterations);
        row.real("thermoelastic_heat",
                 "J/m",
                 "heat released by the step's strain increment, per unit thickness (> 0 under "
                 "compression)",
                 "%.10e",
                 report.thermoelastic_heat);
        row.count("restiffened_cells",
                  "cells whose stiffness was re-assembled for a phase change",
                  coupling_report.reassembled_cells);
      }
  }



  // The contact step's columns, the forces per contact group and the energy
  // terms.
  template <int dim>
  void Postprocessor<dim>::add_mechanical_columns(StatisticsRow           &row,
                                                  const ContactStepReport &contact_report) const
  {
    row.count("displacement_dofs",
              "displacement degrees of freedom",
              static_cast<unsigned int>(mechanical->get_dof_handler().n_dofs()));
    row.count("contact_iterations",
              "active-set iterations (linear solves) of the contact step",
              contact_report.iterations);
    row.count("active_nodes", "contact nodes in the active set", contact_report.active_nodes);
    for (const auto &group : mechanical->get_contact_groups())
      {
        std::string name = "force_" + group;
        std::replace(name.begin(), name.end(), ' ', '_');
        row.real(name,
                 "N/m",
                 "resultant normal contact force on '" + group +
                   "' per unit thickness (> 0 compressive)",
                 "%.10e",
                 contact_report.forces.count(group) ? contact_report.forces.at(group) : 0.);
      }
    row.real("max_pressure",
             "Pa",
             "largest nodal contact pressure (singular at corners)",
             "%.10e",
             contact_report.max_pressure);
    row.real("max_von_mises",
             "Pa",
             "largest von Mises stress at the cell centres (sigma_zz of plane strain included)",
             "%.10e",
             max_von_mises);
    row.real("elastic_energy",
             "J/m",
             "stored elastic energy, thermal part included, per unit thickness",
             "%.10e",
             elastic_energy);
    row.real("contact_work",
             "J/m",
             "work of the contact forces since t0, per unit thickness",
             "%.10e",
             total_contact_work);
  }



  // The statistics table: a header (comment lines, then the column names), then
  // one line per step, appended and
  // flushed as soon as the step is done, so that an interrupted run leaves every
  // finished step on disk and a long run costs O(1) per step. Only rank 0 writes.
  template <int dim>
  void Postprocessor<dim>::write_statistics_row(const unsigned int        step,
                                                const double              time,
                                                const EnthalpyStepReport &report,
                                                const ContactStepReport  &contact_report,
                                                const CouplingReport     &coupling_report,
                                                const double              wall_time) const
  {
    const double  area = thermal ? thermal->melt_area() : 0.;
    StatisticsRow row(step);
    row.count("step", "time step number (0: the initial state)", step);
    row.real("time", "s", "time at the end of the step", "%.10e", time);
    if (thermal)
      add_thermal_columns(row, area, report, coupling_report);
    if (mechanical)
      add_mechanical_columns(row, contact_report);
    if (adaptive)
      {
        row.count("cells",
                  "active cells",
                  static_cast<unsigned int>(triangulation.n_global_active_cells()));
        row.real("adapt_enthalpy_change",
                 "1",
                 "relative change of sum m_i h_i by the adaptation before the step",
                 "%.2e",
                 pending_change);
      }
    row.real("wall_time",
             "s",
             "wall-clock time since the run started (resumed: since the first)",
             "%.3f",
             wall_time);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;
    row.append_to(output_prm.directory + "/" + output_prm.statistics_file);
  }



  template <int dim>
  void Postprocessor<dim>::add_result(const std::string &name, const double value) const
  {
    results.emplace_back(name, value);
  }



  // The run's own checks that do not stop it (its output is complete and
  // finite) but that a researcher must know of before using its numbers.
  template <int dim>
  std::vector<std::string> Postprocessor<dim>::failed_diagnostics() const
  {
    std::vector<std::string> failed;
    if (thermal && inconsistent_enthalpy_nodes > 0)
      failed.push_back(std::to_string(inconsistent_enthalpy_nodes) +
                       " node-steps ended with an enthalpy outside H(Theta) (must be 0; see "
                       "doc/algorithms.md): the enthalpy step did not converge to a solution");
    if (mechanical && output_prm.small_strain_limit > 0 &&
        max_strain > output_prm.small_strain_limit)
      failed.push_back(
        "the largest strain " + number(max_strain) +
        " exceeds 'Output/Small-strain limit' = " + number(output_prm.small_strain_limit) +
        ": the linear small-strain model does not describe this deformation");
    return failed;
  }



  template <int dim>
  void Postprocessor<dim>::print_results(const unsigned int n_steps, const double time) const
  {
    results.clear();
    if (thermal)
      print_thermal_results(n_steps, time);
    if (mechanical)
      print_mechanical_results(n_steps);
    if (thermal && mechanical)
      print_coupling_results(n_steps);
    if (adaptive)
      {
        add_result("final cells", triangulation.n_global_active_cells());
        add_result("mesh adaptations", n_adaptations);
        if (time > start_time)
          add_result("time-averaged dofs", dof_time_integral / (time - start_time));
        add_result("max relative enthalpy change through refinement", max_refinement_change);
        add_result("max relative enthalpy change through coarsening", max_coarsening_change);
      }
    print_timer_calls();
    for (const auto &[name, value] : results)
      if (!std::isfinite(value))
        throw std::runtime_error("the result '" + name + "' is not finite (" +
                                 std::to_string(value) + "); no RESULT line is printed");
    for (const auto &[name, value] : results)
      pcout << "RESULT " << name << " = " << std::setprecision(10) << value << std::endl;
  }



  template <int dim>
  void Postprocessor<dim>::print_coupling_results(const unsigned int n_steps) const
  {
    add_result("max coupling iterations", max_coupling_iterations);
    add_result("mean coupling iterations",
               n_steps > 0 ? double(total_coupling_iterations) / n_steps : 0.);
    add_result("total thermoelastic heat", total_thermoelastic_heat);
    add_result("cells re-stiffened for a phase change", reassembled_cells);
  }



  // How often each solver section ran: a part that a scene does not need must
  // show zero calls (the tests check it).
  template <int dim>
  void Postprocessor<dim>::print_timer_calls() const
  {
    const auto                calls = timer.get_summary_data(TimerOutput::OutputData::n_calls);
    std::vector<const char *> sections;
    if (thermal)
      sections.insert(sections.end(), {"enthalpy step: factorise", "enthalpy step: linear solve"});
    if (mechanical)
      sections.insert(sections.end(),
                      {"contact step: assemble",
                       "contact step: factorise",
                       "contact step: linear solve"});
    if (thermal && mechanical)
      sections.insert(sections.end(),
                      {"coupling: thermal stress load",
                       "coupling: thermoelastic work",
                       "coupling: thermoelastic heating",
                       "coupling: phase-dependent stiffness"});
    for (const char *section : sections)
      {
        const auto it = calls.find(section);
        add_result(std::string("calls ") + section, it == calls.end() ? 0. : it->second);
      }
  }



  template class Postprocessor<2>;
} // namespace ContactStefan
