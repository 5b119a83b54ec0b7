// The errors against an exact temperature (verification/temperature_errors.h).
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>

#include <contact-stefan/verification/temperature_errors.h>

#include <cmath>
#include <map>

namespace ContactStefan
{
  template <int dim>
  TemperatureErrors<dim>::TemperatureErrors(const RunContext<dim> &run, const bool x_only)
    : PartWithState<dim, TemperatureErrorState>(run)
    , x_only(x_only)
  {}



  // Errors at the current time against the exact solution; the space-time error
  // sum_k tau_k ||e(t_k)||^2 is the right-endpoint rule that matches backward Euler.
  template <int dim>
  void TemperatureErrors<dim>::update(const StepData &data)
  {
    const RunContext<dim>   &run     = this->run;
    TemperatureErrorState   &s       = this->state;
    const ThermalField<dim> &thermal = *run.thermal;
    const double             tau     = data.time_step;
    Function<dim>           &exact   = *run.functions.exact_temperature();
    TimerOutput::Scope       t(run.timer, "errors");
    exact.set_time(data.time);
    // ||Theta_h - Theta|| and ||Theta|| in one pass over the cells (Gauss rule
    // two orders above the element's), with the cached geometry.
    update_geometry();
    const Geometry &g      = geometry;
    const double   *values = thermal.get_temperature().trilinos_vector()[0];
    exact_values.resize(g.evaluation_points.size());
    for (unsigned int k = 0; k < g.evaluation_points.size(); ++k)
      exact_values[k] = exact.value(g.evaluation_points[k]);
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
    const MPI_Comm comm = run.mpi_communicator;
    s.last_l2_error     = std::sqrt(Utilities::MPI::sum(error_squared, comm));
    s.last_l2_norm      = std::sqrt(Utilities::MPI::sum(norm_squared, comm));

    // Max-norm error at the nodes, the largest exact nodal value, and the mean
    // signed error sum_i m_i (Theta_i - Theta(x_i)) / sum_i m_i.
    const double *mass      = thermal.get_lumped_mass().trilinos_vector()[0];
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
    run.functions.check_finite_values(comm);
    s.last_max_error = global_max_with_nan(max_error, comm);
    if (tau > 0) // the initial state is the user's data, not a result
      s.max_max_error = max_with_nan(s.max_max_error, s.last_max_error);
    s.max_exact_temperature =
      std::max(s.max_exact_temperature, Utilities::MPI::max(max_value, comm));
    s.mean_errors.push_back(Utilities::MPI::sum(signed_error, comm) /
                            Utilities::MPI::sum(total_mass, comm));

    if (tau > 0)
      {
        s.space_time_error_squared += tau * s.last_l2_error * s.last_l2_error;
        s.space_time_norm_squared += tau * s.last_l2_norm * s.last_l2_norm;
      }
  }



  template <int dim>
  void TemperatureErrors<dim>::update_geometry()
  {
    const ThermalField<dim> &thermal     = *this->run.thermal;
    const DoFHandler<dim>   &dof_handler = thermal.get_dof_handler();
    Geometry                &g           = geometry;
    if (g.mesh_generation == thermal.mesh_generation())
      return;
    // (Q1 in every slot: DoF v of a cell is the shape function of vertex v.)
    const FE_Q<dim>   fe(1);
    const QGauss<dim> quadrature(fe.degree + 2);
    FEValues<dim>     fe_values(fe,
                            quadrature,
                            update_values | update_quadrature_points | update_JxW_values);
    g                                        = Geometry();
    g.mesh_generation                        = thermal.mesh_generation();
    g.n_q_points                             = quadrature.size();
    g.dofs_per_cell                          = fe.n_dofs_per_cell();
    const Epetra_BlockMap               &map = thermal.get_temperature().trilinos_vector().Map();
    std::vector<types::global_dof_index> dofs(g.dofs_per_cell);
    bool                                 first = true;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fe_values.reinit(typename Triangulation<dim>::cell_iterator(cell));
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
    const Epetra_BlockMap  &owned_map = thermal.get_lumped_mass().trilinos_vector().Map();
    std::vector<Point<dim>> node_points;
    for (const auto &[dof, point] : thermal.get_support_points())
      if (dof_handler.locally_owned_dofs().is_element(dof))
        {
          g.nodes.emplace_back(map.LID(static_cast<int>(dof)),
                               owned_map.LID(static_cast<int>(dof)));
          node_points.push_back(point);
        }
    // The distinct evaluation points (exact equality: the quadrature points of
    // cells in one column of a rectangle have bitwise equal abscissae).
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
  void
  TemperatureErrors<dim>::add_results(ResultLines &results, const unsigned int, const double) const
  {
    const TemperatureErrorState &s   = this->state;
    const auto                   add = [&](const std::string &name, const double value) {
      results.add(ResultLines::Slot::temperature, name, value);
    };
    add("mesh width", mesh_width(this->run.triangulation));
    add("L2 error temperature", s.last_l2_error);
    // A relative error needs an exact solution that is not zero (Function
    // = 0, or min(t, 100 - t) at t = 100): there the absolute error, which
    // the line above and the space-time line below report, is the measure.
    if (s.last_l2_norm > 0)
      add("relative L2 error temperature", s.last_l2_error / s.last_l2_norm);
    if (s.space_time_norm_squared > 0)
      add("relative space-time L2 error temperature",
          std::sqrt(s.space_time_error_squared / s.space_time_norm_squared));
    else
      add("space-time L2 error temperature", std::sqrt(s.space_time_error_squared));
    add("max-norm error temperature", s.last_max_error);
    add("max over the steps of the relative max-norm error temperature",
        s.max_exact_temperature > 0 ? s.max_max_error / s.max_exact_temperature : 0.);
    add("mean signed error temperature", s.mean_errors.back());
    // Successive changes of the mean error: how a lag between the fields
    // decays (doc/benchmarks.md T3: by -gamma/rho c per step when staggered).
    const std::vector<double> &m = s.mean_errors;
    const std::size_t          k = m.size();
    // (Only where both increments are well above round-off: a scheme exact
    // to round-off has no lag to show, and a converged one only noise.)
    const double noise = 1e-10 * s.max_exact_temperature;
    if (k >= 4 && std::abs(m[k - 1] - m[k - 2]) > noise && std::abs(m[k - 2] - m[k - 3]) > noise)
      add("ratio of the last two increments of the mean error",
          (m[k - 1] - m[k - 2]) / (m[k - 2] - m[k - 3]));
  }



  template class TemperatureErrors<2>;
} // namespace ContactStefan
