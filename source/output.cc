// Output: VTU/PVD fields, the per-step statistics table, and the errors against an
// exact solution that end a verification run as RESULT lines.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/mapping_q1.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <contact-stefan/contact.h>

#include <contact-stefan/coupled_problem.h>

#include <algorithm>
#include <cstdio>
#include <stdexcept>
#include <fstream>
#include <iomanip>

namespace ContactStefan
{
  namespace
  {
    // Displacement, stresses and von Mises stress from the hp displacement field:
    // each cell reads its own body's slot of components (the other slots are
    // FE_Nothing and vanish).
    template <int dim>
    class MechanicalPostprocessor : public DataPostprocessor<dim>
    {
    public:
      MechanicalPostprocessor(const AllParameters &prm, const std::map<unsigned int, unsigned int> &slots)
        : body_slot(slots)
      {
        for (const auto &[id, m] : prm.materials)
          {
            C[id] = m.elasticity_tensor();
            // Plane strain: sigma_zz = C_zzkl e_kl; for isotropic data lambda tr(e).
            // (Not available for a 2D anisotropic tensor: taken as 0.)
            lambda[id] = m.elasticity == "anisotropic" ? 0. : C[id][0][0][1][1];
          }
      }

      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                                 std::vector<dealii::Vector<double>>        &computed) const override
      {
        const auto         cell = inputs.template get_cell<dim>();
        const unsigned int id   = cell->material_id();
        const unsigned int c0   = body_slot.at(id) * dim;
        for (unsigned int q = 0; q < computed.size(); ++q)
          {
            SymmetricTensor<2, dim> strain;
            for (unsigned int i = 0; i < dim; ++i)
              for (unsigned int j = i; j < dim; ++j)
                strain[i][j] = 0.5 * (inputs.solution_gradients[q][c0 + i][j] +
                                      inputs.solution_gradients[q][c0 + j][i]);
            const SymmetricTensor<2, dim> sigma = C.at(id) * strain;
            const double                  szz   = lambda.at(id) * trace(strain);
            computed[q](0) = inputs.solution_values[q][c0];
            computed[q](1) = inputs.solution_values[q][c0 + 1];
            computed[q](2) = sigma[0][0];
            computed[q](3) = sigma[1][1];
            computed[q](4) = sigma[0][1];
            computed[q](5) = std::sqrt(0.5 * ((sigma[0][0] - sigma[1][1]) * (sigma[0][0] - sigma[1][1]) +
                                              (sigma[1][1] - szz) * (sigma[1][1] - szz) +
                                              (szz - sigma[0][0]) * (szz - sigma[0][0])) +
                                       3 * sigma[0][1] * sigma[0][1]);
          }
      }
      std::vector<std::string> get_names() const override
      {
        return {"displacement", "displacement", "stress_xx", "stress_yy", "stress_xy", "von_mises"};
      }
      std::vector<DataComponentInterpretation::DataComponentInterpretation>
      get_data_component_interpretation() const override
      {
        std::vector<DataComponentInterpretation::DataComponentInterpretation> i(
          6, DataComponentInterpretation::component_is_scalar);
        i[0] = i[1] = DataComponentInterpretation::component_is_part_of_vector;
        return i;
      }
      UpdateFlags get_needed_update_flags() const override
      {
        return update_values | update_gradients;
      }

    private:
      const std::map<unsigned int, unsigned int>        &body_slot;
      std::map<unsigned int, SymmetricTensor<4, dim>>    C;
      std::map<unsigned int, double>                     lambda;
    };

    // A nodal quantity stored at the x DoF of each body's slot (contact pressure,
    // gap), summed over the slots into one scalar field.
    template <int dim>
    class SlotSum : public DataPostprocessorScalar<dim>
    {
    public:
      SlotSum(const std::string &name, const unsigned int n_slots)
        : DataPostprocessorScalar<dim>(name, update_values)
        , n_slots(n_slots)
      {}
      void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                                 std::vector<dealii::Vector<double>>        &computed) const override
      {
        for (unsigned int q = 0; q < computed.size(); ++q)
          {
            computed[q](0) = 0;
            for (unsigned int s = 0; s < n_slots; ++s)
              computed[q](0) += inputs.solution_values[q][s * dim];
          }
      }

    private:
      const unsigned int n_slots;
    };
  } // namespace



  template <int dim>
  void CoupledProblem<dim>::output_vtu(const unsigned int step)
  {
    TimerOutput::Scope t(timer, "output: vtu");
    DataOut<dim>       data_out;
    data_out.attach_triangulation(triangulation);

    Vector phase_index_ghosted, liquid_ghosted;
    if (prm.physics.thermal)
      {
        Vector phase_index(locally_owned_dofs, mpi_communicator);
        Vector liquid(locally_owned_dofs, mpi_communicator);
        for (const auto dof : locally_owned_dofs)
          {
            phase_index[dof] = law(dof).phase_index(enthalpy[dof]);
            liquid[dof]      = law(dof).liquid_fraction(enthalpy[dof]);
          }
        phase_index.compress(VectorOperation::insert);
        liquid.compress(VectorOperation::insert);
        phase_index_ghosted.reinit(locally_owned_dofs, locally_relevant_dofs, mpi_communicator);
        liquid_ghosted.reinit(locally_owned_dofs, locally_relevant_dofs, mpi_communicator);
        phase_index_ghosted = phase_index;
        liquid_ghosted      = liquid;
        data_out.add_data_vector(dof_handler, temperature_ghosted, "temperature");
        data_out.add_data_vector(dof_handler, enthalpy_ghosted, "enthalpy");
        data_out.add_data_vector(dof_handler, phase_index_ghosted, "phase_index");
        data_out.add_data_vector(dof_handler, liquid_ghosted, "liquid_fraction");
      }

    std::unique_ptr<MechanicalPostprocessor<dim>> mechanical;
    std::unique_ptr<SlotSum<dim>>                 pressure_field, gap_field;
    Vector                                        pressure_ghosted, gap_ghosted;
    if (prm.physics.mechanics)
      {
        mechanical = std::make_unique<MechanicalPostprocessor<dim>>(prm, body_slot);
        pressure_field = std::make_unique<SlotSum<dim>>("contact_pressure", prm.body_ids.size());
        gap_field      = std::make_unique<SlotSum<dim>>("contact_gap", prm.body_ids.size());
        pressure_ghosted.reinit(mechanical_owned, mechanical_relevant, mpi_communicator);
        gap_ghosted.reinit(mechanical_owned, mechanical_relevant, mpi_communicator);
        pressure_ghosted = contact_pressure;
        gap_ghosted      = contact_gap;
        data_out.add_data_vector(mechanical_dof_handler, displacement_ghosted, *mechanical);
        data_out.add_data_vector(mechanical_dof_handler, pressure_ghosted, *pressure_field);
        data_out.add_data_vector(mechanical_dof_handler, gap_ghosted, *gap_field);
      }

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



  // sum_i m_i h_i: the heat content (J per unit thickness) of the whole mesh.
  template <int dim>
  double CoupledProblem<dim>::total_enthalpy() const
  {
    double E = 0;
    for (const auto dof : locally_owned_dofs)
      if (!hanging_node_constraints.is_constrained(dof))
        E += lumped_mass[dof] * enthalpy[dof];
    return Utilities::MPI::sum(E, mpi_communicator);
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
                                                 const EnthalpyStepReport &report,
                                                 const ContactStepReport  &contact_report)
  {
    // Melt area: lumped-mass weighted liquid fraction, i.e. the fraction through
    // the last transition of each node's own law.
    double area = 0;
    if (prm.physics.thermal)
      {
        for (const auto dof : locally_owned_dofs)
          if (!hanging_node_constraints.is_constrained(dof))
            area += lumped_mass[dof] * law(dof).liquid_fraction(enthalpy[dof]);
        area = Utilities::MPI::sum(area, mpi_communicator);
      }
    if (Utilities::MPI::this_mpi_process(mpi_communicator) != 0)
      return;

    const std::string path = prm.output.directory + "/" + prm.output.statistics_file;
    std::ofstream     out(path, step == 0 ? std::ios::trunc : std::ios::app);
    char              field[64];
    const auto        add = [&](const char *format, const auto value) {
      std::snprintf(field, sizeof(field), format, value);
      out << ' ' << field;
    };
    if (step == 0)
      {
        out << "step time";
        if (prm.physics.thermal)
          out << " dofs pdas_iterations state_changes damped_steps fallback_iterations "
                 "plateau_nodes liquid_area energy_residual";
        if (prm.physics.mechanics)
          {
            out << " displacement_dofs contact_iterations active_nodes";
            for (std::string group : contact_groups)
              {
                std::replace(group.begin(), group.end(), ' ', '_');
                out << " force_" << group;
              }
            out << " max_pressure";
          }
        out << " wall_time\n";
      }
    out << step;
    add("%.10e", time);
    if (prm.physics.thermal)
      {
        add("%u", static_cast<unsigned int>(dof_handler.n_dofs()));
        add("%u", report.active_set_iterations);
        add("%u", report.state_changes);
        add("%u", report.damped_steps);
        add("%u", report.relaxation_iterations);
        add("%u", report.plateau_nodes);
        add("%.10e", area);
        add("%.2e", report.energy_residual);
      }
    if (prm.physics.mechanics)
      {
        add("%u", static_cast<unsigned int>(mechanical_dof_handler.n_dofs()));
        add("%u", contact_report.iterations);
        add("%u", contact_report.active_nodes);
        for (const auto &group : contact_groups)
          add("%.10e", contact_report.forces.count(group) ? contact_report.forces.at(group) : 0.);
        add("%.10e", contact_report.max_pressure);
      }
    add("%.3f", wall_clock.wall_time());
    out << std::endl;
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
    result("nodes with h outside H(Theta)", inconsistent_enthalpy_nodes);
    if (exact_temperature)
      {
        result("mesh width", mesh_width);
        result("L2 error temperature", last_l2_error);
        result("relative L2 error temperature", last_l2_error / last_l2_norm);
        result("relative space-time L2 error temperature",
               std::sqrt(space_time_error_squared / space_time_norm_squared));
        result("max-norm error temperature", last_max_error);
      }
    if (prm.exact_solution.type == "equilibrium")
      {
        // T_f from the body laws and the body areas alone (no nodal mixtures):
        // sum_b |body b| H_b(T_f) = E(0), by bisection on the monotone left side.
        std::map<unsigned int, double> area;
        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            area[cell->material_id()] += cell->measure();
        std::vector<std::pair<double, EnthalpyLaw>> bodies;
        for (const unsigned int id : prm.body_ids)
          bodies.emplace_back(Utilities::MPI::sum(area[id], mpi_communicator),
                              prm.materials.at(id).enthalpy_law());
        const auto total = [&](const double T) {
          double E = 0;
          for (const auto &[A, l] : bodies)
            E += A * l.enthalpy(T);
          return E;
        };
        double lo = -1, hi = 1;
        while (total(lo) > initial_total_enthalpy)
          lo *= 2;
        while (total(hi) < initial_total_enthalpy)
          hi *= 2;
        for (unsigned int i = 0; i < 200 && hi - lo > 0; ++i)
          {
            const double mid = 0.5 * (lo + hi);
            (total(mid) < initial_total_enthalpy ? lo : hi) = mid;
          }
        const double T_f       = 0.5 * (lo + hi);
        double       deviation = 0;
        for (const auto dof : locally_owned_dofs)
          deviation = std::max(deviation, std::abs(temperature[dof] - T_f));
        const double E_end = total_enthalpy();
        result("equilibrium temperature", T_f);
        result("max deviation from equilibrium temperature",
               Utilities::MPI::max(deviation, mpi_communicator));
        result("relative change of total enthalpy",
               std::abs(E_end - initial_total_enthalpy) / std::abs(initial_total_enthalpy));
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
  }



  // Contact results; with an exact solution (Hertz, patch test) its errors.
  template <int dim>
  void CoupledProblem<dim>::print_mechanical_results()
  {
    using Kind        = NormalCondition::Kind;
    const auto result = [&](const std::string &name, const double value) {
      pcout << "RESULT " << name << " = " << std::setprecision(10) << value << std::endl;
    };
    result("displacement dofs", mechanical_dof_handler.n_dofs());
    result("contact iterations first step", first_contact_iterations);
    result("max contact iterations", max_contact_iterations);
    result("max contact iterations after the first step", max_contact_iterations_warm);
    result("mean contact iterations",
           step_number > 0 ? double(total_contact_iterations) / step_number : 0.);
    result("active contact nodes", last_contact_report.active_nodes);
    for (const auto &[group, force] : last_contact_report.forces)
      result("contact force " + group, force);
    result("max contact pressure", last_contact_report.max_pressure);

    const auto &exact = prm.exact_solution;
    if (exact.type == "hertz")
      {
        // The contact nodes of the obstacle: position, pressure and weight.
        std::vector<std::array<double, 3>> local;
        double                             local_force = 0;
        for (const auto &c : normal_conditions)
          if (c.kind == Kind::obstacle && mechanical_owned.is_element(c.dofs_k[0]))
            {
              const bool active = obstacle_active[c.dofs_k[0]] > 0.5;
              local.push_back({{c.position[0], active ? static_cast<double>(contact_pressure[c.dofs_k[0]]) : 0., c.weight}});
              local_force += active ? contact_pressure[c.dofs_k[0]] * c.weight : 0.;
            }
        const double P      = Utilities::MPI::sum(local_force, mpi_communicator);
        const double E_star = prm.materials.at(exact.body).plane_strain_modulus();
        const Contact::Hertz hertz(P, exact.cylinder_radius, E_star);
        double contact_length = 0, p0 = 0, error2 = 0, norm2 = 0;
        for (const auto &[x, p, w] : local)
          {
            contact_length += (p > 0 ? w : 0.);
            p0 = std::max(p0, p);
            error2 += w * (p - hertz.pressure(x)) * (p - hertz.pressure(x));
            norm2 += w * hertz.pressure(x) * hertz.pressure(x);
          }
        contact_length = Utilities::MPI::sum(contact_length, mpi_communicator);
        p0             = Utilities::MPI::max(p0, mpi_communicator);
        error2         = Utilities::MPI::sum(error2, mpi_communicator);
        norm2          = Utilities::MPI::sum(norm2, mpi_communicator);
        // The computed half-width is half the lumped length of the active nodes.
        const double a = 0.5 * contact_length;
        result("Hertz force P", P);
        result("Hertz half-width", a);
        result("Hertz exact half-width", hertz.half_width);
        result("Hertz half-width relative error", std::abs(a - hertz.half_width) / hertz.half_width);
        result("Hertz peak pressure", p0);
        result("Hertz exact peak pressure", hertz.peak_pressure);
        result("Hertz peak pressure relative error",
               std::abs(p0 - hertz.peak_pressure) / hertz.peak_pressure);
        result("Hertz pressure profile relative L2 error", std::sqrt(error2 / norm2));
        double spacing = HUGE_VAL;
        for (const auto &c : normal_conditions)
          if (c.kind == Kind::obstacle)
            spacing = std::min(spacing, c.weight);
        result("contact mesh width", Utilities::MPI::min(spacing, mpi_communicator));
      }
    if (exact.type == "patch")
      {
        // Uniform stress sigma_yy = -(delta - g) / sum_b (H_b / E*_b) (the blocks
        // act as springs in series; H_b from the mesh) when the interface closes
        // (delta >= gap), zero otherwise; every interface node in contact.
        double gap = -HUGE_VAL; // the (constant) interface gap
        for (const auto &c : normal_conditions)
          if (c.kind == Kind::interface)
            gap = std::max(gap, c.gap);
        gap = Utilities::MPI::max(gap, mpi_communicator);
        double compliance = 0;
        for (const unsigned int id : prm.body_ids)
          compliance += body_height(body_slot.at(id)) / prm.materials.at(id).plane_strain_modulus();
        const bool   closed  = exact.patch_displacement >= gap;
        const double sigma_y = closed ? -(exact.patch_displacement - gap) / compliance : 0.;
        const double scale   = closed ? std::abs(sigma_y) : exact.patch_displacement / compliance;
        double       stress_error = 0, pressure_error = 0, min_gap = HUGE_VAL;
        unsigned int interface_nodes = 0, active = 0;
        const QMidpoint<dim>       midpoint;
        hp::QCollection<dim>       q(midpoint);
        hp::FEValues<dim>          hp_fe_values(mechanical_fe, q, update_gradients);
        for (const auto &cell : mechanical_dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              hp_fe_values.reinit(cell);
              const auto &fv = hp_fe_values.get_present_fe_values();
              std::vector<std::vector<Tensor<1, dim>>> grads(1, std::vector<Tensor<1, dim>>(fv.get_fe().n_components()));
              fv.get_function_gradients(displacement_ghosted, grads);
              const unsigned int      slot = body_slot.at(cell->material_id());
              SymmetricTensor<2, dim> strain;
              for (unsigned int i = 0; i < dim; ++i)
                for (unsigned int j = i; j < dim; ++j)
                  strain[i][j] = 0.5 * (grads[0][slot * dim + i][j] + grads[0][slot * dim + j][i]);
              const SymmetricTensor<2, dim> sigma =
                prm.materials.at(cell->material_id()).elasticity_tensor() * strain;
              stress_error = std::max({stress_error, std::abs(sigma[0][0]), std::abs(sigma[0][1]),
                                       std::abs(sigma[1][1] - sigma_y)});
            }
        for (const auto &c : normal_conditions)
          if (c.kind == Kind::interface && mechanical_owned.is_element(c.dofs_k[0]))
            {
              ++interface_nodes;
              active += interface_active[c.dofs_k[0]] > 0.5;
              pressure_error = std::max(pressure_error, std::abs(static_cast<double>(contact_pressure[c.dofs_k[0]]) - std::abs(sigma_y)));
              min_gap        = std::min(min_gap, static_cast<double>(contact_gap[c.dofs_k[0]]));
            }
        result("patch exact sigma_yy", sigma_y);
        result("patch stress relative error",
               Utilities::MPI::max(stress_error, mpi_communicator) / scale);
        result("patch pressure relative error",
               Utilities::MPI::max(pressure_error, mpi_communicator) / scale);
        result("patch interface nodes", Utilities::MPI::sum(interface_nodes, mpi_communicator));
        result("patch interface nodes active", Utilities::MPI::sum(active, mpi_communicator));
        result("patch min interface gap", Utilities::MPI::min(min_gap, mpi_communicator));
      }
  }



  template class CoupledProblem<2>;
} // namespace ContactStefan
