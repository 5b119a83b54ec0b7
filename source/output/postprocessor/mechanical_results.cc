// Postprocessor (output/postprocessor.h): the mechanical results. After each
// step the energy terms, the opening of each contact group and the errors
// against an exact stress, section force and contact pressure; at the end the
// contact RESULT lines, with the Hertz (C1) and patch (C2) checks.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <contact-stefan/interfaces/contact.h>
#include <contact-stefan/output/postprocessor.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ContactStefan
{
  using ExactType = Parameters::ExactSolution::Type;

  // The opening of each contact group: the time its force reaches zero,
  // extrapolated from the last two loaded steps (exact while the force falls
  // linearly, as in doc/benchmarks.md T4).
  template <int dim>
  void Postprocessor<dim>::track_contact_opening(const double             time,
                                                 const ContactStepReport &contact_report)
  {
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
  }



  // The stress error against the exact stress at the current time: by the
  // vertex rule at the vertices (the historical measure), and of the two stress
  // outputs (doc/output.md), each relative to the exact stress plus the thermal
  // stress. Collective.
  template <int dim>
  void Postprocessor<dim>::accumulate_stress_errors(Function<dim> &exact, const double time)
  {
    exact.set_time(time);
    double error2 = 0, norm2 = 0, thermal2 = 0;
    mechanical->for_each_vertex_stress([&](const Point<dim>              &x,
                                           const double                   w,
                                           const SymmetricTensor<2, dim> &sigma,
                                           const double                   szz,
                                           const SymmetricTensor<2, dim> &thermal_part,
                                           const ElasticModuli &) {
      const double e[4] = {sigma[0][0] - exact.value(x, 0),
                           sigma[1][1] - exact.value(x, 1),
                           sigma[0][1] - exact.value(x, 2),
                           szz - exact.value(x, 3)};
      error2 += w * (e[0] * e[0] + e[1] * e[1] + 2 * e[2] * e[2] + e[3] * e[3]);
      norm2 += w * (std::pow(exact.value(x, 0), 2) + std::pow(exact.value(x, 1), 2) +
                    2 * std::pow(exact.value(x, 2), 2) + std::pow(exact.value(x, 3), 2));
      thermal2 += w * (thermal_part * thermal_part);
    });
    // The same error of the two stress outputs (doc/output.md): the
    // cell-centre values by the midpoint rule, the recovered nodal field by
    // the vertex rule.
    const auto squared_error =
      [&](const Point<dim> &x, const SymmetricTensor<2, dim> &sigma, const double szz) {
        const double e[4] = {sigma[0][0] - exact.value(x, 0),
                             sigma[1][1] - exact.value(x, 1),
                             sigma[0][1] - exact.value(x, 2),
                             szz - exact.value(x, 3)};
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
        max_relative_stress_error_recovered =
          max_with_nan(max_relative_stress_error_recovered, std::sqrt(recovered_error2) / scale);
      }
  }



  // The section forces of both stress outputs against 'Exact solution/Section
  // normal force' at the current time, over the lines and their sides.
  // Collective.
  template <int dim>
  void Postprocessor<dim>::accumulate_section_force_errors(Function<dim> &exact, const double time)
  {
    exact.set_time(time);
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
            const double force      = exact.value(on_line);
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



  // The nodal contact pressure against the exact one at the current time: the
  // largest error and the largest exact pressure. Collective.
  template <int dim>
  void Postprocessor<dim>::accumulate_pressure_errors(Function<dim> &exact, const double time)
  {
    exact.set_time(time);
    double error = 0, size = 0;
    for (const auto &c : mechanical->get_normal_conditions())
      if (c.kind != NormalCondition::Kind::roller &&
          mechanical->get_dof_handler().locally_owned_dofs().is_element(c.dofs_k[0]))
        {
          const double p = exact.value(c.position);
          error          = max_with_nan(error, std::abs(mechanical->contact_pressure(c) - p));
          size           = std::max(size, std::abs(p));
        }
    functions.check_finite_values(mpi_communicator);
    max_pressure_error =
      max_with_nan(max_pressure_error, global_max_with_nan(error, mpi_communicator));
    max_exact_pressure = std::max(max_exact_pressure, Utilities::MPI::max(size, mpi_communicator));
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
    const auto         elastic    = mechanical->elastic_statistics();
    elastic_energy                = elastic.energy;
    max_strain                    = std::max(max_strain, elastic.max_strain);
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
    track_contact_opening(time, contact_report);

    // The exact stress and pressure are compared after each step, not at t0
    // (a scene may start before its loading does, as T4 with its first step).
    if (Function<dim> *exact = functions.exact_stress(); exact && time > prm.time.start_time)
      accumulate_stress_errors(*exact, time);
    if (Function<dim> *exact = functions.exact_section_normal_force();
        exact && time > prm.time.start_time)
      accumulate_section_force_errors(*exact, time);
    if (Function<dim> *exact = functions.exact_contact_pressure();
        exact && time > prm.time.start_time)
      accumulate_pressure_errors(*exact, time);
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
    print_section_force_results();
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



  // The section forces at the end and, with an exact section force, their
  // errors over the steps.
  template <int dim>
  void Postprocessor<dim>::print_section_force_results() const
  {
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



  template void Postprocessor<2>::track_contact_opening(const double             time,
                                                        const ContactStepReport &contact_report);
  template void Postprocessor<2>::accumulate_stress_errors(Function<2> &exact, const double time);
  template void Postprocessor<2>::accumulate_section_force_errors(Function<2> &exact,
                                                                  const double time);
  template void Postprocessor<2>::accumulate_pressure_errors(Function<2> &exact, const double time);
  template void
                Postprocessor<2>::accumulate_mechanical_results(const double             time,
                                                  const ContactStepReport &contact_report);
  template void Postprocessor<2>::print_section_force_results() const;
  template void Postprocessor<2>::print_mechanical_results(const unsigned int n_steps) const;
  template void Postprocessor<2>::print_hertz_results() const;
  template void Postprocessor<2>::print_patch_results() const;
} // namespace ContactStefan
