// Postprocessor: VTU/PVD fields, the per-step statistics table, and the errors
// against an exact solution that end a verification run as RESULT lines.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/interfaces/contact.h>
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
  using ExactType = Parameters::ExactSolution::Type;

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
    const double area    = thermal ? thermal->melt_area() : 0.;
    const bool   coupled = thermal && mechanical;
    // One list of the columns this scene has: name, unit, meaning (the header's
    // comment lines, at step 0) and this step's value as written. A real value
    // is checked before anything is written: every number of the row is the
    // same on every rank, and no row with a NaN may reach the file.
    struct Column
    {
      std::string name, unit, meaning, value;
    };
    std::vector<Column> columns;
    char                field[64];
    const auto          count = [&](const std::string &name,
                           const std::string &meaning,
                           const unsigned int value) {
      std::snprintf(field, sizeof(field), "%u", value);
      columns.push_back({name, "-", meaning, field});
    };
    const auto real = [&](const std::string &name,
                          const std::string &unit,
                          const std::string &meaning,
                          const char        *format,
                          const double       value) {
      if (!std::isfinite(value))
        throw std::runtime_error("step " + std::to_string(step) + ": the statistics value '" +
                                 name + "' is not finite (" + std::to_string(value) + ")");
      std::snprintf(field, sizeof(field), format, value);
      columns.push_back({name, unit, meaning, field});
    };
    count("step", "time step number (0: the initial state)", step);
    real("time", "s", "time at the end of the step", "%.10e", time);
    if (thermal)
      {
        count("dofs",
              "temperature degrees of freedom",
              static_cast<unsigned int>(thermal->get_dof_handler().n_dofs()));
        count("pdas_iterations",
              "active-set iterations (linear solves) of the enthalpy step",
              report.active_set_iterations);
        count("state_changes",
              "nodal phase-state changes, summed over the iterations",
              report.state_changes);
        count("damped_steps",
              "enthalpy iterations whose Newton step was shortened",
              report.damped_steps);
        count("fallback_iterations",
              "iterations of the relaxation fallback (0: not needed)",
              report.relaxation_iterations);
        count("plateau_nodes",
              "nodes on a transition plateau (mushy) at the end of the step",
              report.plateau_nodes);
        real("liquid_area",
             "m^2",
             "melt area: lumped-mass weighted liquid fraction through the last transition, per "
             "unit thickness",
             "%.10e",
             area);
        real("energy_residual",
             "1",
             "enthalpy balance of the step relative to the size of its terms (doc/coupling.md 6)",
             "%.2e",
             report.energy_residual);
        if (coupled)
          {
            count("coupling_iterations",
                  "passes of contact and enthalpy step (1: staggered)",
                  coupling_report.iterations);
            real("thermoelastic_heat",
                 "J/m",
                 "heat released by the step's strain increment, per unit thickness (> 0 under "
                 "compression)",
                 "%.10e",
                 report.thermoelastic_heat);
            count("restiffened_cells",
                  "cells whose stiffness was re-assembled for a phase change",
                  coupling_report.reassembled_cells);
          }
      }
    if (mechanical)
      {
        count("displacement_dofs",
              "displacement degrees of freedom",
              static_cast<unsigned int>(mechanical->get_dof_handler().n_dofs()));
        count("contact_iterations",
              "active-set iterations (linear solves) of the contact step",
              contact_report.iterations);
        count("active_nodes", "contact nodes in the active set", contact_report.active_nodes);
        for (const auto &group : mechanical->get_contact_groups())
          {
            std::string name = "force_" + group;
            std::replace(name.begin(), name.end(), ' ', '_');
            real(name,
                 "N/m",
                 "resultant normal contact force on '" + group +
                   "' per unit thickness (> 0 compressive)",
                 "%.10e",
                 contact_report.forces.count(group) ? contact_report.forces.at(group) : 0.);
          }
        real("max_pressure",
             "Pa",
             "largest nodal contact pressure (singular at corners)",
             "%.10e",
             contact_report.max_pressure);
        real("max_von_mises",
             "Pa",
             "largest von Mises stress at the cell centres (sigma_zz of plane strain included)",
             "%.10e",
             max_von_mises);
        real("elastic_energy",
             "J/m",
             "stored elastic energy, thermal part included, per unit thickness",
             "%.10e",
             elastic_energy);
        real("contact_work",
             "J/m",
             "work of the contact forces since t0, per unit thickness",
             "%.10e",
             total_contact_work);
      }
    if (adaptive)
      {
        count("cells",
              "active cells",
              static_cast<unsigned int>(triangulation.n_global_active_cells()));
        real("adapt_enthalpy_change",
             "1",
             "relative change of sum m_i h_i by the adaptation before the step",
             "%.2e",
             pending_change);
      }
    real("wall_time",
         "s",
         "wall-clock time since the run started (resumed: since the first)",
         "%.3f",
         wall_time);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;

    const std::string path = output_prm.directory + "/" + output_prm.statistics_file;
    std::ofstream     out(path, step == 0 ? std::ios::trunc : std::ios::app);
    if (step == 0)
      {
        // The header: one comment line per column (name, unit, meaning), then
        // the line of column names. gnuplot and pandas (comment='#') skip the
        // comments; the names line stays the first line that is not one.
        out << "# contact-stefan statistics, one row per time step. Units for a scene given in SI "
               "units (m, kg, s, K or degC); a dimensionless scene's columns are dimensionless.\n";
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



  // Errors at the current time against the exact solution; the space-time error
  // sum_k tau_k ||e(t_k)||^2 is the right-endpoint rule that matches backward Euler.
  template <int dim>
  void Postprocessor<dim>::accumulate_errors(const double time, const double tau)
  {
    if (Function<dim> *fraction = functions.exact_liquid_fraction())
      {
        fraction->set_time(time);
        const auto &points = thermal->get_support_points();
        double      error  = 0;
        for (const auto dof : thermal->get_dof_handler().locally_owned_dofs())
          error =
            max_with_nan(error,
                         std::abs(thermal->law(dof).liquid_fraction(thermal->get_enthalpy()[dof]) -
                                  fraction->value(points.at(dof))));
        functions.check_finite_values(mpi_communicator);
        max_liquid_fraction_error =
          max_with_nan(max_liquid_fraction_error, global_max_with_nan(error, mpi_communicator));
      }
    Function<dim> *exact = functions.exact_temperature();
    if (!exact)
      return;
    TimerOutput::Scope t(timer, "errors");
    exact->set_time(time);
    const Vector &theta_h_all = thermal->get_temperature();
    // ||Theta_h - Theta|| and ||Theta|| in one pass over the cells (Gauss rule
    // two orders above the element's), with the cached geometry.
    update_error_geometry();
    const ErrorGeometry &g      = error_geometry;
    const double        *values = theta_h_all.trilinos_vector()[0];
    exact_values.resize(g.evaluation_points.size());
    for (unsigned int k = 0; k < g.evaluation_points.size(); ++k)
      exact_values[k] = exact->value(g.evaluation_points[k]);
    std::vector<double> theta(g.n_q_points);
    double              error_squared = 0, norm_squared = 0;
    for (unsigned int c = 0; c < g.n_cells; ++c)
      {
        for (unsigned int q = 0; q < g.n_q_points; ++q)
          theta[q] = exact_values[g.point_evaluation[c * g.n_q_points + q]];
        const int    *dofs = &g.local_dofs[c * g.dofs_per_cell];
        const double *JxW  = &g.JxW[c * g.n_q_points];
        for (unsigned int q = 0; q < g.n_q_points; ++q)
          {
            double theta_h = 0;
            for (unsigned int i = 0; i < g.dofs_per_cell; ++i)
              theta_h += values[dofs[i]] * g.shape[q * g.dofs_per_cell + i];
            error_squared += (theta_h - theta[q]) * (theta_h - theta[q]) * JxW[q];
            norm_squared += theta[q] * theta[q] * JxW[q];
          }
      }
    last_l2_error = std::sqrt(Utilities::MPI::sum(error_squared, mpi_communicator));
    last_l2_norm  = std::sqrt(Utilities::MPI::sum(norm_squared, mpi_communicator));

    // Max-norm error at the nodes, the largest exact nodal value, and the mean
    // signed error sum_i m_i (Theta_i - Theta(x_i)) / sum_i m_i.
    const double *mass      = thermal->get_lumped_mass().trilinos_vector()[0];
    double        max_error = 0, max_value = 0, signed_error = 0, total_mass = 0;
    for (unsigned int n = 0; n < g.nodes.size(); ++n)
      {
        const auto [ghosted, local] = g.nodes[n];
        const double value          = exact_values[g.node_evaluation[n]];
        max_error                   = max_with_nan(max_error, std::abs(values[ghosted] - value));
        max_value                   = std::max(max_value, std::abs(value));
        signed_error += mass[local] * (values[ghosted] - value);
        total_mass += mass[local];
      }
    functions.check_finite_values(mpi_communicator);
    last_max_error = global_max_with_nan(max_error, mpi_communicator);
    if (tau > 0) // the initial state is the user's data, not a result
      max_max_error = max_with_nan(max_max_error, last_max_error);
    max_exact_temperature =
      std::max(max_exact_temperature, Utilities::MPI::max(max_value, mpi_communicator));
    mean_errors.push_back(Utilities::MPI::sum(signed_error, mpi_communicator) /
                          Utilities::MPI::sum(total_mass, mpi_communicator));

    if (tau > 0)
      {
        space_time_error_squared += tau * last_l2_error * last_l2_error;
        space_time_norm_squared += tau * last_l2_norm * last_l2_norm;
      }
  }



  template <int dim>
  void Postprocessor<dim>::update_error_geometry()
  {
    const DoFHandler<dim> &dof_handler = thermal->get_dof_handler();
    ErrorGeometry         &g           = error_geometry;
    if (g.mesh_generation == thermal->mesh_generation())
      return;
    const auto       &fe = dof_handler.get_fe();
    const QGauss<dim> quadrature(fe.degree + 2);
    FEValues<dim>     fe_values(fe,
                            quadrature,
                            update_values | update_quadrature_points | update_JxW_values);
    g                                        = ErrorGeometry();
    g.mesh_generation                        = thermal->mesh_generation();
    g.n_q_points                             = quadrature.size();
    g.dofs_per_cell                          = fe.n_dofs_per_cell();
    const Epetra_BlockMap               &map = thermal->get_temperature().trilinos_vector().Map();
    std::vector<types::global_dof_index> dofs(g.dofs_per_cell);
    bool                                 first = true;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          cell->get_dof_indices(dofs);
          for (const auto dof : dofs)
            g.local_dofs.push_back(map.LID(static_cast<int>(dof)));
          for (unsigned int q = 0; q < g.n_q_points; ++q)
            {
              g.points.push_back(fe_values.quadrature_point(q));
              g.JxW.push_back(fe_values.JxW(q));
              if (first)
                for (unsigned int i = 0; i < g.dofs_per_cell; ++i)
                  g.shape.push_back(fe_values.shape_value(i, q));
            }
          first = false;
          ++g.n_cells;
        }
    const Epetra_BlockMap  &owned_map = thermal->get_lumped_mass().trilinos_vector().Map();
    std::vector<Point<dim>> node_points;
    for (const auto &[dof, point] : thermal->get_support_points())
      if (dof_handler.locally_owned_dofs().is_element(dof))
        {
          g.nodes.emplace_back(map.LID(static_cast<int>(dof)),
                               owned_map.LID(static_cast<int>(dof)));
          node_points.push_back(point);
        }
    // The distinct evaluation points (exact equality: the quadrature points of
    // cells in one column of a rectangle have bitwise equal abscissae).
    const bool                     x_only = neumann != nullptr;
    std::map<double, unsigned int> abscissa;
    const auto                     index_of = [&](const Point<dim> &p) {
      if (!x_only)
        {
          g.evaluation_points.push_back(p);
          return static_cast<unsigned int>(g.evaluation_points.size() - 1);
        }
      const auto [it, inserted] =
        abscissa.emplace(p[0], static_cast<unsigned int>(g.evaluation_points.size()));
      if (inserted)
        g.evaluation_points.push_back(p);
      return it->second;
    };
    for (const auto &p : g.points)
      g.point_evaluation.push_back(index_of(p));
    for (const auto &p : node_points)
      g.node_evaluation.push_back(index_of(p));
  }



  template <int dim>
  double Postprocessor<dim>::mesh_width() const
  {
    double width = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        width = std::max(width, cell->extent_in_direction(0));
    return Utilities::MPI::max(width, mpi_communicator);
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
  void Postprocessor<dim>::print_thermal_results(const unsigned int n_steps,
                                                 const double       time) const
  {
    add_result("time steps", n_steps);
    add_result("temperature dofs", thermal->get_dof_handler().n_dofs());
    add_result("mean active-set iterations",
               n_steps > 0 ? double(total_active_set_iterations) / n_steps : 0.);
    add_result("steps with relaxation fallback", steps_with_fallback);
    // Only where it ran: the active-set method's large-step mode or its
    // hand-over at its iteration limit, or 'Enthalpy solver = truncated-newton'.
    if (steps_with_truncated_newton > 0)
      add_result("steps solved by the truncated Newton method", steps_with_truncated_newton);
    add_result("max energy-balance residual", max_energy_residual);
    add_result("enthalpy matrix factorisations", enthalpy_factorisations);
    add_result("melt area", thermal->melt_area());
    if (functions.exact_liquid_fraction())
      add_result("max liquid fraction error", max_liquid_fraction_error);
    add_result("nodes with h outside H(Theta)", inconsistent_enthalpy_nodes);
    const double h = mesh_width();
    if (functions.exact_temperature())
      {
        add_result("mesh width", h);
        add_result("L2 error temperature", last_l2_error);
        // A relative error needs an exact solution that is not zero (Function
        // = 0, or min(t, 100 - t) at t = 100): there the absolute error, which
        // the line above and the space-time line below report, is the measure.
        if (last_l2_norm > 0)
          add_result("relative L2 error temperature", last_l2_error / last_l2_norm);
        if (space_time_norm_squared > 0)
          add_result("relative space-time L2 error temperature",
                     std::sqrt(space_time_error_squared / space_time_norm_squared));
        else
          add_result("space-time L2 error temperature", std::sqrt(space_time_error_squared));
        add_result("max-norm error temperature", last_max_error);
        add_result("max over the steps of the relative max-norm error temperature",
                   max_exact_temperature > 0 ? max_max_error / max_exact_temperature : 0.);
        add_result("mean signed error temperature", mean_errors.back());
        // Successive changes of the mean error: how a lag between the fields
        // decays (doc/benchmarks.md T3: by -gamma/rho c per step when staggered).
        const std::size_t k = mean_errors.size();
        // (Only where both increments are well above round-off: a scheme exact
        // to round-off has no lag to show, and a converged one only noise.)
        const double noise = 1e-10 * max_exact_temperature;
        if (k >= 4 && std::abs(mean_errors[k - 1] - mean_errors[k - 2]) > noise &&
            std::abs(mean_errors[k - 2] - mean_errors[k - 3]) > noise)
          add_result("ratio of the last two increments of the mean error",
                     (mean_errors[k - 1] - mean_errors[k - 2]) /
                       (mean_errors[k - 2] - mean_errors[k - 3]));
      }
    if (prm.exact_solution.type == ExactType::equilibrium)
      {
        // T_f from the body laws and the body areas alone (no nodal mixtures):
        // sum_b |body b| H_b(T_f) = E(0), by bisection on the monotone left side.
        std::map<unsigned int, double> area;
        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            area[cell->material_id()] += cell->measure();
        std::vector<std::pair<double, const EnthalpyLaw *>> bodies;
        for (const unsigned int id : prm.body_ids)
          bodies.emplace_back(Utilities::MPI::sum(area[id], mpi_communicator),
                              &materials[id].enthalpy_law);
        const auto total = [&](const double T) {
          double E = 0;
          for (const auto &[A, l] : bodies)
            E += A * l->enthalpy(T);
          return E;
        };
        double lo = -1, hi = 1;
        while (total(lo) > initial_total_enthalpy)
          lo *= 2;
        while (total(hi) < initial_total_enthalpy)
          hi *= 2;
        for (unsigned int i = 0; i < 200 && hi - lo > 0; ++i)
          {
            const double mid                                = 0.5 * (lo + hi);
            (total(mid) < initial_total_enthalpy ? lo : hi) = mid;
          }
        const double  T_f         = 0.5 * (lo + hi);
        const Vector &temperature = thermal->get_temperature();
        double        deviation   = 0;
        for (const auto dof : thermal->get_dof_handler().locally_owned_dofs())
          deviation = max_with_nan(deviation, std::abs(temperature[dof] - T_f));
        const double E_end = thermal->total_enthalpy();
        add_result("equilibrium temperature", T_f);
        add_result("max deviation from equilibrium temperature",
                   global_max_with_nan(deviation, mpi_communicator));
        if (initial_total_enthalpy != 0)
          add_result("relative change of total enthalpy",
                     std::abs(E_end - initial_total_enthalpy) / std::abs(initial_total_enthalpy));
        else
          add_result("change of total enthalpy", std::abs(E_end - initial_total_enthalpy));
      }
    if (neumann)
      {
        // Fronts: from the melt area of each transition (strip of height Y).
        const auto  &g      = prm.geometry;
        const double height = g.upper_right[1] - g.lower_left[1];
        const auto  &law    = materials[prm.exact_solution.body].enthalpy_law;
        for (unsigned int j = 0; j < law.n_transitions(); ++j)
          {
            const std::string suffix = law.n_transitions() == 1 ? "" : " " + std::to_string(j);
            const double      s_h =
              g.lower_left[0] + thermal->liquid_area(law.transition_temperature(j)) / height;
            const double s = prm.exact_solution.origin + neumann->front_position(j, time);
            add_result("front position" + suffix, s_h);
            add_result("exact front position" + suffix, s);
            add_result("front position error" + suffix, std::abs(s_h - s));
            add_result("front position error in mesh widths" + suffix, std::abs(s_h - s) / h);
            if (adaptive)
              {
                // The widest cell the exact front crosses.
                double local = 0;
                for (const auto &cell : triangulation.active_cell_iterators())
                  if (cell->is_locally_owned())
                    {
                      const auto box = cell->bounding_box();
                      if (box.lower_bound(0) <= s && s <= box.upper_bound(0))
                        local = std::max(local, cell->extent_in_direction(0));
                    }
                local = Utilities::MPI::max(local, mpi_communicator);
                add_result("front position error in local mesh widths" + suffix,
                           local > 0 ? std::abs(s_h - s) / local : 0.);
              }
          }
      }
  }



  // After each step (and at the start) with mechanics: the energy terms, the
  // errors against an exact stress and contact pressure, and the opening of each
  // contact group (the time its force reaches zero, from the last two loaded
  // steps: exact while the force falls linearly, as in doc/benchmarks.md T4).
  template <int dim>
  void Postprocessor<dim>::accumulate_mechanical_results(const double             time,
                                                         const ContactStepReport &contact_report)
  {
    TimerOutput::Scope t(timer, "statistics: mechanical");
    const auto         elastic = mechanical->elastic_statistics();
    elastic_energy             = elastic.energy;
    max_strain                 = std::max(max_strain, elastic.max_strain);
    const auto [von_mises, where] = mechanical->max_cell_von_mises();
    max_von_mises                 = von_mises;
    // (A later step counts only if it is larger beyond round-off: the time and
    // place must not depend on the partition.)
    if (von_mises > max_von_mises_over_steps * (1 + 1e-10))
      {
        max_von_mises_over_steps = von_mises;
        max_von_mises_time       = time;
        max_von_mises_point      = where;
      }
    total_contact_work += mechanical->contact_work();
    for (const auto &[group, force] : contact_report.forces)
      {
        // Zero up to round-off of the largest force the group carried: the
        // force is a sum over the contact nodes, each with a round-off of the
        // order of that force, so the allowance grows with the number of nodes
        // that carried it (T4 on 64 x 64 cells: 4e-17 after the opening, 129
        // nodes, a largest force of 6.5e-4).
        auto &history        = loaded_force_history[group];
        largest_force[group] = std::max(largest_force[group], std::abs(force));
        if (force > round_off_factor * std::numeric_limits<double>::epsilon() *
                      largest_force[group] * std::max(1u, max_active_nodes))
          {
            history.emplace_back(time, force);
            if (history.size() > 2)
              history.erase(history.begin());
            opening_time.erase(group);
          }
        else if (history.size() == 2 && opening_time.count(group) == 0)
          {
            const auto [t0, f0] = history[0];
            const auto [t1, f1] = history[1];
            opening_time[group] = f0 > f1 ? t1 + f1 * (t1 - t0) / (f0 - f1) : t1;
          }
      }

    // The exact stress and pressure are compared after each step, not at t0
    // (a scene may start before its loading does, as T4 with its first step).
    if (Function<dim> *exact = functions.exact_stress(); exact && time > prm.time.start_time)
      {
        exact->set_time(time);
        double error2 = 0, norm2 = 0, thermal2 = 0;
        mechanical->for_each_vertex_stress([&](const Point<dim>              &x,
                                               const double                   w,
                                               const SymmetricTensor<2, dim> &sigma,
                                               const double                   szz,
                                               const SymmetricTensor<2, dim> &thermal_part,
                                               const ElasticModuli &) {
          const double e[4] = {sigma[0][0] - exact->value(x, 0),
                               sigma[1][1] - exact->value(x, 1),
                               sigma[0][1] - exact->value(x, 2),
                               szz - exact->value(x, 3)};
          error2 += w * (e[0] * e[0] + e[1] * e[1] + 2 * e[2] * e[2] + e[3] * e[3]);
          norm2 += w * (std::pow(exact->value(x, 0), 2) + std::pow(exact->value(x, 1), 2) +
                        2 * std::pow(exact->value(x, 2), 2) + std::pow(exact->value(x, 3), 2));
          thermal2 += w * (thermal_part * thermal_part);
        });
        // The same error of the two stress outputs (doc/output.md): the
        // cell-centre values by the midpoint rule, the recovered nodal field by
        // the vertex rule.
        const auto squared_error =
          [&](const Point<dim> &x, const SymmetricTensor<2, dim> &sigma, const double szz) {
            const double e[4] = {sigma[0][0] - exact->value(x, 0),
                                 sigma[1][1] - exact->value(x, 1),
                                 sigma[0][1] - exact->value(x, 2),
                                 szz - exact->value(x, 3)};
            return e[0] * e[0] + e[1] * e[1] + 2 * e[2] * e[2] + e[3] * e[3];
          };
        double     cell_error2 = 0, recovered_error2 = 0;
        const auto stresses = mechanical->cell_centre_stresses();
        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const auto &s = stresses[cell->active_cell_index()];
              cell_error2 += cell->measure() * squared_error(cell->center(), s.sigma, s.sigma_zz);
            }
        mechanical->for_each_recovered_vertex_stress(
          [&](const Point<dim>              &x,
              const double                   w,
              const SymmetricTensor<2, dim> &sigma,
              const double szz) { recovered_error2 += w * squared_error(x, sigma, szz); });
        functions.check_finite_values(mpi_communicator);
        error2             = Utilities::MPI::sum(error2, mpi_communicator);
        cell_error2        = Utilities::MPI::sum(cell_error2, mpi_communicator);
        recovered_error2   = Utilities::MPI::sum(recovered_error2, mpi_communicator);
        norm2              = Utilities::MPI::sum(norm2, mpi_communicator);
        thermal2           = Utilities::MPI::sum(thermal2, mpi_communicator);
        const double scale = std::sqrt(norm2) + std::sqrt(thermal2);
        if (scale > 0)
          {
            max_relative_stress_error =
              max_with_nan(max_relative_stress_error, std::sqrt(error2) / scale);
            max_relative_stress_error_cell =
              max_with_nan(max_relative_stress_error_cell, std::sqrt(cell_error2) / scale);
            max_relative_stress_error_recovered = max_with_nan(max_relative_stress_error_recovered,
                                                               std::sqrt(recovered_error2) / scale);
          }
      }
    if (Function<dim> *exact = functions.exact_section_normal_force();
        exact && time > prm.time.start_time)
      {
        exact->set_time(time);
        const auto &lines  = output_prm.section_lines;
        const auto  forces = mechanical->section_forces(lines);
        for (unsigned int l = 0; l < lines.size(); ++l)
          for (unsigned int side = 0; side < 2; ++side)
            if (forces[l].length[side] > 0)
              {
                const unsigned int axis = lines[l].axis;
                // The exact force at the line's point on the axis: (c, 0) for
                // x = c, (0, c) for y = c.
                Point<dim> on_line;
                on_line[axis]           = lines[l].value;
                const double force      = exact->value(on_line);
                max_exact_section_force = std::max(max_exact_section_force, std::abs(force));
                max_section_error_cell =
                  max_with_nan(max_section_error_cell,
                               std::abs(forces[l].cell_centre[side][axis] - force));
                max_section_error_recovered =
                  max_with_nan(max_section_error_recovered,
                               std::abs(forces[l].recovered[side][axis] - force));
                ++section_sides_checked;
                if (forces[l].uniform_row(side))
                  {
                    ++section_sides_uniform;
                    max_section_error_cell_uniform =
                      max_with_nan(max_section_error_cell_uniform,
                                   std::abs(forces[l].cell_centre[side][axis] - force));
                  }
              }
        functions.check_finite_values(mpi_communicator);
      }
    if (Function<dim> *exact = functions.exact_contact_pressure();
        exact && time > prm.time.start_time)
      {
        exact->set_time(time);
        double error = 0, size = 0;
        for (const auto &c : mechanical->get_normal_conditions())
          if (c.kind != NormalCondition::Kind::roller &&
              mechanical->get_dof_handler().locally_owned_dofs().is_element(c.dofs_k[0]))
            {
              const double p = exact->value(c.position);
              error          = max_with_nan(error, std::abs(mechanical->contact_pressure(c) - p));
              size           = std::max(size, std::abs(p));
            }
        functions.check_finite_values(mpi_communicator);
        max_pressure_error =
          max_with_nan(max_pressure_error, global_max_with_nan(error, mpi_communicator));
        max_exact_pressure =
          std::max(max_exact_pressure, Utilities::MPI::max(size, mpi_communicator));
      }
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



  // Contact results; with an exact solution (Hertz, patch test) its errors.
  template <int dim>
  void Postprocessor<dim>::print_mechanical_results(const unsigned int n_steps) const
  {
    add_result("displacement dofs", mechanical->get_dof_handler().n_dofs());
    add_result("contact iterations first step", first_contact_iterations);
    add_result("max contact iterations", max_contact_iterations);
    add_result("max contact iterations after the first step", max_contact_iterations_warm);
    add_result("mean contact iterations",
               n_steps > 0 ? double(total_contact_iterations) / n_steps : 0.);
    add_result("active contact nodes", last_contact_report.active_nodes);
    add_result("max active contact nodes over the steps", max_active_nodes);
    for (const auto &[group, force] : last_contact_report.forces)
      add_result("contact force " + group, force);
    add_result("max contact pressure", last_contact_report.max_pressure);
    add_result("min contact pressure at active nodes", last_contact_report.min_active_pressure);
    add_result("contact matrix factorisations", contact_factorisations);
    add_result("contact solves skipped (unchanged data)", reused_contact_steps);
    // From the cell-centre stresses, where Q1 is accurate (doc/output.md).
    add_result("max von Mises stress (cell centres)", max_von_mises_over_steps);
    add_result("max von Mises stress time", max_von_mises_time);
    add_result("max von Mises stress x", max_von_mises_point[0]);
    add_result("max von Mises stress y", max_von_mises_point[1]);
    // The iterative path's work. It depends on the preconditioner's settings
    // and on the partition (ML aggregates per rank), not only on the problem:
    // the regression tests bound these lines ('... solver: ') instead of
    // comparing them with a reference.
    if (elasticity_linear.cg_solves > 0)
      {
        add_result("elasticity solver: CG solves", elasticity_linear.cg_solves);
        add_result("elasticity solver: max CG iterations per solve",
                   elasticity_linear.max_cg_iterations);
        add_result("elasticity solver: mean CG iterations per solve",
                   double(elasticity_linear.cg_iterations) / elasticity_linear.cg_solves);
        add_result("elasticity solver: AMG builds", elasticity_linear.amg_builds);
        add_result("elasticity solver: AMG recomputations", elasticity_linear.amg_recomputations);
      }
    add_result("elastic energy", elastic_energy);
    add_result("total contact work", total_contact_work);
    for (const auto &[group, t] : opening_time)
      add_result("opening time " + group, t);
    if (functions.exact_stress())
      {
        add_result("max relative stress L2 error", max_relative_stress_error);
        add_result("max relative stress L2 error (cell centres)", max_relative_stress_error_cell);
        add_result("max relative stress L2 error (recovered)", max_relative_stress_error_recovered);
      }
    // The section forces at the end (both sides of each line, both stress
    // outputs), and their errors over the steps.
    const auto &lines = output_prm.section_lines;
    if (!lines.empty())
      {
        const auto forces = mechanical->section_forces(lines);
        for (unsigned int l = 0; l < lines.size(); ++l)
          for (unsigned int side = 0; side < 2; ++side)
            if (forces[l].length[side] > 0)
              {
                const std::string where = "section force " + lines[l].name + " " +
                                          (side == 0 ? (lines[l].axis == 0 ? "left" : "below") :
                                                       (lines[l].axis == 0 ? "right" : "above"));
                const unsigned int axis = lines[l].axis, other = 1 - axis;
                add_result(where + ": normal (cell centres)", forces[l].cell_centre[side][axis]);
                add_result(where + ": tangential (cell centres)",
                           forces[l].cell_centre[side][other]);
                add_result(where + ": normal (recovered)", forces[l].recovered[side][axis]);
                add_result(where + ": tangential (recovered)", forces[l].recovered[side][other]);
              }
      }
    if (functions.exact_section_normal_force())
      {
        add_result("section sides compared", section_sides_checked);
        add_result("section sides on rows of equal cells", section_sides_uniform);
        // Relative to the largest exact force over the steps; the absolute
        // errors (N/m) where that is zero.
        if (max_exact_section_force == 0)
          {
            add_result("max section normal force error (cell centres)", max_section_error_cell);
            add_result("max section normal force error (recovered)", max_section_error_recovered);
            // (Nothing about the rows of equal cells when there was none: a
            // bound on it must not pass on an empty set.)
            if (section_sides_uniform > 0)
              add_result("max section normal force error (cell centres, rows of equal cells)",
                         max_section_error_cell_uniform);
          }
        else
          {
            add_result("max relative section normal force error (cell centres)",
                       max_section_error_cell / max_exact_section_force);
            add_result("max relative section normal force error (recovered)",
                       max_section_error_recovered / max_exact_section_force);
            if (section_sides_uniform > 0)
              add_result(
                "max relative section normal force error (cell centres, rows of equal cells)",
                max_section_error_cell_uniform / max_exact_section_force);
          }
      }
    if (functions.exact_contact_pressure())
      {
        add_result("max contact pressure error", max_pressure_error);
        add_result("max relative contact pressure error",
                   max_exact_pressure > 0 ? max_pressure_error / max_exact_pressure : 0.);
      }
    if (!prm.exact_solution.contact_pressure.empty() || !opening_time.empty())
      for (const auto &group : mechanical->get_contact_groups())
        {
          // Mean gap over the group's nodes at the end (0 where closed).
          double       sum = 0;
          unsigned int n   = 0;
          for (const auto &c : mechanical->get_normal_conditions())
            if (c.group == group &&
                mechanical->get_dof_handler().locally_owned_dofs().is_element(c.dofs_k[0]))
              {
                sum += mechanical->contact_gap(c);
                ++n;
              }
          sum = Utilities::MPI::sum(sum, mpi_communicator);
          n   = Utilities::MPI::sum(n, mpi_communicator);
          add_result("mean gap " + group, n > 0 ? sum / n : 0.);
        }

    if (prm.exact_solution.type == ExactType::hertz)
      print_hertz_results();
    if (prm.exact_solution.type == ExactType::patch)
      print_patch_results();
  }



  // C1 (doc/benchmarks.md): the Hertz solution for the computed force, against
  // the pressure at the obstacle's nodes.
  template <int dim>
  void Postprocessor<dim>::print_hertz_results() const
  {
    using Kind             = NormalCondition::Kind;
    const auto &exact      = prm.exact_solution;
    const auto &owned      = mechanical->get_dof_handler().locally_owned_dofs();
    const auto &conditions = mechanical->get_normal_conditions();
    {
      // The contact nodes of the obstacle: position, pressure and weight.
      std::vector<std::array<double, 3>> local;
      double                             local_force = 0;
      for (const auto &c : conditions)
        if (c.kind == Kind::obstacle && owned.is_element(c.dofs_k[0]))
          {
            const double p = mechanical->is_active(c) ? mechanical->contact_pressure(c) : 0.;
            local.push_back({{c.position[0], p, c.weight}});
            local_force += p * c.weight;
          }
      const double         P      = Utilities::MPI::sum(local_force, mpi_communicator);
      const double         E_star = materials[exact.body].plane_strain_modulus;
      const Contact::Hertz hertz(P, exact.cylinder_radius, E_star);
      double               contact_length = 0, p0 = 0, error2 = 0, norm2 = 0;
      for (const auto &[x, p, w] : local)
        {
          contact_length += (p > 0 ? w : 0.);
          p0 = max_with_nan(p0, p);
          error2 += w * (p - hertz.pressure(x)) * (p - hertz.pressure(x));
          norm2 += w * hertz.pressure(x) * hertz.pressure(x);
        }
      contact_length = Utilities::MPI::sum(contact_length, mpi_communicator);
      p0             = global_max_with_nan(p0, mpi_communicator);
      error2         = Utilities::MPI::sum(error2, mpi_communicator);
      norm2          = Utilities::MPI::sum(norm2, mpi_communicator);
      // The computed half-width is half the lumped length of the active nodes.
      const double a = 0.5 * contact_length;
      add_result("Hertz force P", P);
      add_result("Hertz half-width", a);
      add_result("Hertz exact half-width", hertz.half_width);
      add_result("Hertz half-width relative error",
                 std::abs(a - hertz.half_width) / hertz.half_width);
      add_result("Hertz peak pressure", p0);
      add_result("Hertz exact peak pressure", hertz.peak_pressure);
      add_result("Hertz peak pressure relative error",
                 std::abs(p0 - hertz.peak_pressure) / hertz.peak_pressure);
      add_result("Hertz pressure profile relative L2 error", std::sqrt(error2 / norm2));
      double spacing = HUGE_VAL;
      for (const auto &c : conditions)
        if (c.kind == Kind::obstacle)
          spacing = std::min(spacing, c.weight);
      add_result("contact mesh width", Utilities::MPI::min(spacing, mpi_communicator));
    }
  }



  // C2 (doc/benchmarks.md): the patch test's uniform stress and pressure.
  template <int dim>
  void Postprocessor<dim>::print_patch_results() const
  {
    using Kind             = NormalCondition::Kind;
    const auto &exact      = prm.exact_solution;
    const auto &owned      = mechanical->get_dof_handler().locally_owned_dofs();
    const auto &conditions = mechanical->get_normal_conditions();
    {
      // Uniform stress sigma_yy = -(delta - g) / sum_b (H_b / E*_b) (the blocks
      // act as springs in series; H_b from the mesh) when the interface closes
      // (delta >= gap), zero otherwise; every interface node in contact.
      double gap = -HUGE_VAL; // the (constant) interface gap
      for (const auto &c : conditions)
        if (c.kind == Kind::interface)
          gap = std::max(gap, c.gap);
      gap               = Utilities::MPI::max(gap, mpi_communicator);
      double compliance = 0;
      for (const unsigned int id : prm.body_ids)
        compliance += mechanical->body_height(id) / materials[id].plane_strain_modulus;
      const bool   closed  = exact.patch_displacement >= gap;
      const double sigma_y = closed ? -(exact.patch_displacement - gap) / compliance : 0.;
      const double scale   = closed ? std::abs(sigma_y) : exact.patch_displacement / compliance;
      double       stress_error = 0, pressure_error = 0, min_gap = HUGE_VAL;
      unsigned int interface_nodes = 0, active = 0;
      const auto  &dof_handler = mechanical->get_dof_handler();
      const hp::QCollection<dim> q{QMidpoint<dim>()};
      hp::FEValues<dim>          hp_fe_values(dof_handler.get_fe_collection(), q, update_gradients);
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            hp_fe_values.reinit(cell);
            const auto                              &fv = hp_fe_values.get_present_fe_values();
            std::vector<std::vector<Tensor<1, dim>>> grads(
              1, std::vector<Tensor<1, dim>>(fv.get_fe().n_components()));
            fv.get_function_gradients(mechanical->get_displacement(), grads);
            const unsigned int      slot = mechanical->body_slot(cell->material_id());
            SymmetricTensor<2, dim> strain;
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = i; j < dim; ++j)
                strain[i][j] = 0.5 * (grads[0][slot * dim + i][j] + grads[0][slot * dim + j][i]);
            const SymmetricTensor<2, dim> sigma =
              materials[cell->material_id()].elasticity * strain;
            stress_error =
              max_with_nan(max_with_nan(stress_error, std::abs(sigma[0][0])),
                           max_with_nan(std::abs(sigma[0][1]), std::abs(sigma[1][1] - sigma_y)));
          }
      for (const auto &c : conditions)
        if (c.kind == Kind::interface && owned.is_element(c.dofs_k[0]))
          {
            ++interface_nodes;
            active += mechanical->is_active(c);
            pressure_error =
              max_with_nan(pressure_error,
                           std::abs(mechanical->contact_pressure(c) - std::abs(sigma_y)));
            min_gap = std::min(min_gap, mechanical->contact_gap(c));
          }
      add_result("patch exact sigma_yy", sigma_y);
      add_result("patch stress relative error",
                 global_max_with_nan(stress_error, mpi_communicator) / scale);
      add_result("patch pressure relative error",
                 global_max_with_nan(pressure_error, mpi_communicator) / scale);
      add_result("patch interface nodes", Utilities::MPI::sum(interface_nodes, mpi_communicator));
      add_result("patch interface nodes active", Utilities::MPI::sum(active, mpi_communicator));
      add_result("patch min interface gap", Utilities::MPI::min(min_gap, mpi_communicator));
    }
  }



  template class Postprocessor<2>;
} // namespace ContactStefan
