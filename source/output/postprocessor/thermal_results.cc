// Postprocessor (output/postprocessor.h): the thermal results. The errors
// against an exact temperature and liquid fraction accumulated after each step
// (with the geometry they need, cached per mesh), and the thermal RESULT lines:
// iteration counts, the energy balance, the equilibrium temperature and the
// Neumann fronts.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <contact-stefan/output/postprocessor.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace ContactStefan
{
  using ExactType = Parameters::ExactSolution::Type;

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
      print_equilibrium_results();
    if (neumann)
      print_front_results(time, h);
  }



  // The equilibrium scene (doc/benchmarks.md): the final temperature T_f and
  // the largest deviation from it, and the change of the total enthalpy.
  template <int dim>
  void Postprocessor<dim>::print_equilibrium_results() const
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



  // A Neumann scene: the computed and exact front of each transition, and the
  // front error in mesh widths (h: the mesh width).
  template <int dim>
  void Postprocessor<dim>::print_front_results(const double time, const double h) const
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



  template void   Postprocessor<2>::accumulate_errors(const double time, const double tau);
  template void   Postprocessor<2>::update_error_geometry();
  template double Postprocessor<2>::mesh_width() const;
  template void   Postprocessor<2>::print_equilibrium_results() const;
  template void   Postprocessor<2>::print_front_results(const double time, const double h) const;
  template void   Postprocessor<2>::print_thermal_results(const unsigned int n_steps,
                                                        const double       time) const;
} // namespace ContactStefan
