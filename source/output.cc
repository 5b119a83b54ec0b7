// Output: VTU/PVD fields, the per-step statistics table, and the errors against an
// exact solution that end a verification run as RESULT lines.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/fe/fe_values.h>

#include <contact-stefan/coupled_problem.h>

#include <cstdio>
#include <stdexcept>
#include <fstream>
#include <iomanip>

namespace ContactStefan
{
  template <int dim>
  void CoupledProblem<dim>::output_vtu(const unsigned int step)
  {
    TimerOutput::Scope t(timer, "output: vtu");
    Vector phase_index(locally_owned_dofs, mpi_communicator);
    Vector liquid(locally_owned_dofs, mpi_communicator);
    for (const auto dof : locally_owned_dofs)
      {
        phase_index[dof] = law(dof).phase_index(enthalpy[dof]);
        liquid[dof]      = law(dof).liquid_fraction(enthalpy[dof]);
      }
    phase_index.compress(VectorOperation::insert);
    liquid.compress(VectorOperation::insert);
    Vector phase_index_ghosted(locally_owned_dofs, locally_relevant_dofs, mpi_communicator);
    Vector liquid_ghosted(locally_owned_dofs, locally_relevant_dofs, mpi_communicator);
    phase_index_ghosted = phase_index;
    liquid_ghosted      = liquid;

    dealii::Vector<float> body(triangulation.n_active_cells());
    dealii::Vector<float> rank(triangulation.n_active_cells());
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          body(cell->active_cell_index()) = cell->material_id();
          rank(cell->active_cell_index()) = triangulation.locally_owned_subdomain();
        }

    DataOut<dim> data_out;
    data_out.attach_dof_handler(dof_handler);
    data_out.add_data_vector(temperature_ghosted, "temperature");
    data_out.add_data_vector(enthalpy_ghosted, "enthalpy");
    data_out.add_data_vector(phase_index_ghosted, "phase_index");
    data_out.add_data_vector(liquid_ghosted, "liquid_fraction");
    data_out.add_data_vector(body, "body_id");
    data_out.add_data_vector(rank, "mpi_rank");
    data_out.build_patches();

    const std::string directory = prm.output.directory + "/";
    const std::string name =
      data_out.write_vtu_with_pvtu_record(directory, "solution", step, mpi_communicator, 5);
    pvd_records.emplace_back(time, name);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      {
        std::ofstream pvd(directory + "solution.pvd");
        DataOutBase::write_pvd_record(pvd, pvd_records);
        if (!pvd)
          throw std::runtime_error("cannot write '" + directory + "solution.pvd'");
      }
  }



  template <int dim>
  double CoupledProblem<dim>::liquid_area(const double transition_temperature) const
  {
    double area = 0;
    for (const auto dof : locally_owned_dofs)
      if (!hanging_node_constraints.is_constrained(dof))
        area += lumped_mass[dof] *
                law(dof).fraction_through_temperature(transition_temperature, enthalpy[dof]);
    return Utilities::MPI::sum(area, mpi_communicator);
  }



  // The statistics table: a header line, then one line per step, appended and
  // flushed as soon as the step is done, so that an interrupted run leaves every
  // finished step on disk and a long run costs O(1) per step. Only rank 0 writes.
  template <int dim>
  void CoupledProblem<dim>::write_statistics_row(const unsigned int        step,
                                                 const EnthalpyStepReport &report)
  {
    // Melt area: lumped-mass weighted liquid fraction, i.e. the fraction through
    // the last transition of each node's own law.
    double area = 0;
    for (const auto dof : locally_owned_dofs)
      if (!hanging_node_constraints.is_constrained(dof))
        area += lumped_mass[dof] * law(dof).liquid_fraction(enthalpy[dof]);
    area = Utilities::MPI::sum(area, mpi_communicator);
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;

    const std::string path = prm.output.directory + "/" + prm.output.statistics_file;
    std::ofstream     out(path, step == 0 ? std::ios::trunc : std::ios::app);
    char              line[512];
    if (step == 0)
      out << "step time dofs pdas_iterations state_changes damped_steps fallback_iterations "
             "plateau_nodes liquid_area energy_residual wall_time\n";
    std::snprintf(line, sizeof(line), "%u %.10e %u %u %u %u %u %u %.10e %.2e %.3f\n", step,
                  time, static_cast<unsigned int>(dof_handler.n_dofs()),
                  report.active_set_iterations, report.state_changes, report.damped_steps,
                  report.relaxation_iterations, report.plateau_nodes, area,
                  report.energy_residual, wall_clock.wall_time());
    out << line << std::flush;
    if (!out)
      throw std::runtime_error("cannot write '" + path + "'");
  }



  // Errors at the current time against the exact solution; the space-time error
  // sum_k tau_k ||e(t_k)||^2 is the right-endpoint rule that matches backward Euler.
  template <int dim>
  void CoupledProblem<dim>::accumulate_errors(const double tau)
  {
    if (!exact_temperature)
      return;
    TimerOutput::Scope t(timer, "errors");
    exact_temperature->set_time(time);
    // ||Theta_h - Theta|| and ||Theta|| in one pass over the cells (Gauss rule
    // two orders above the element's).
    const QGauss<dim>   quadrature(fe.degree + 2);
    FEValues<dim>       fe_values(fe, quadrature,
                            update_values | update_quadrature_points | update_JxW_values);
    std::vector<double> theta_h(quadrature.size()), theta(quadrature.size());
    double              error_squared = 0, norm_squared = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(cell);
          fe_values.get_function_values(temperature_ghosted, theta_h);
          exact_temperature->value_list(fe_values.get_quadrature_points(), theta);
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              error_squared += (theta_h[q] - theta[q]) * (theta_h[q] - theta[q]) * fe_values.JxW(q);
              norm_squared += theta[q] * theta[q] * fe_values.JxW(q);
            }
        }
    last_l2_error = std::sqrt(Utilities::MPI::sum(error_squared, mpi_communicator));
    last_l2_norm  = std::sqrt(Utilities::MPI::sum(norm_squared, mpi_communicator));

    // Max-norm error at the nodes.
    if (support_points.empty())
      DoFTools::map_dofs_to_support_points(MappingQ1<dim>(), dof_handler, support_points);
    double max_error = 0;
    for (const auto dof : locally_owned_dofs)
      max_error = std::max(max_error, std::abs(temperature[dof] -
                                               exact_temperature->value(support_points.at(dof))));
    last_max_error = Utilities::MPI::max(max_error, mpi_communicator);

    if (tau > 0)
      {
        space_time_error_squared += tau * last_l2_error * last_l2_error;
        space_time_norm_squared += tau * last_l2_norm * last_l2_norm;
      }
  }



  template <int dim>
  void CoupledProblem<dim>::print_results()
  {
    const auto result = [&](const std::string &name, const double value) {
      pcout << "RESULT " << name << " = " << std::setprecision(10) << value << std::endl;
    };
    result("time steps", step_number);
    result("temperature dofs", dof_handler.n_dofs());
    result("mean active-set iterations",
           step_number > 0 ? double(total_active_set_iterations) / step_number : 0.);
    result("steps with relaxation fallback", steps_with_fallback);
    result("max energy-balance residual", max_energy_residual);
    if (exact_temperature)
      {
        result("mesh width", mesh_width);
        result("L2 error temperature", last_l2_error);
        result("relative L2 error temperature", last_l2_error / last_l2_norm);
        result("relative space-time L2 error temperature",
               std::sqrt(space_time_error_squared / space_time_norm_squared));
        result("max-norm error temperature", last_max_error);
      }
    if (neumann)
      {
        // Fronts: from the melt area of each transition (strip of height Y).
        const auto  &g      = prm.geometry;
        const double height = g.upper_right[1] - g.lower_left[1];
        const auto  &m      = prm.materials.at(prm.exact_solution.body);
        for (unsigned int j = 0; j < m.transition_temperatures.size(); ++j)
          {
            const std::string suffix =
              m.transition_temperatures.size() == 1 ? "" : " " + std::to_string(j);
            const double s_h = g.lower_left[0] + liquid_area(m.transition_temperatures[j]) / height;
            const double s   = prm.exact_solution.origin + neumann->front_position(j, time);
            result("front position" + suffix, s_h);
            result("exact front position" + suffix, s);
            result("front position error" + suffix, std::abs(s_h - s));
            result("front position error in mesh widths" + suffix, std::abs(s_h - s) / mesh_width);
          }
      }
    result("wall time", wall_clock.wall_time());
  }



  template class CoupledProblem<2>;
} // namespace ContactStefan
