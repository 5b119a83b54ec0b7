// The enthalpy step by a truncated nonsmooth Newton method in the temperature
// (Enthalpy solver = truncated-newton).
//
// The step's equations  m_i (h_i - h_i^old) + tau (A Theta)_i = tau F_i - G_i,
// h_i in H_i(Theta_i), at the free nodes are the optimality conditions of the
// strictly convex, piecewise quadratic functional
//
//     J(Theta) = 1/2 Theta^T tau A Theta + sum_i m_i Phi_i(Theta_i) - b^T Theta,
//     Phi_i' = H_i,   b_i = m_i h_i^old + tau F_i - G_i,
//
// whose kinks sit at the transition temperatures (Phi_i' jumps by the latent
// heat there). The active-set method of enthalpy_step.cc judges its steps in
// the enthalpy; where the front crosses many cells in one step (tau >> h^2/kappa)
// its first Newton step leaves no latent heat at the nodes the front is about to
// cross, overheats them, and the Armijo line search then lets the front advance
// about one column of nodes per linear solve (doc/performance.md).
//
// Here every iterate is a temperature field and every step is judged by J
// itself, as in the truncated nonsmooth Newton multigrid method (TNNMG, Graeser
// & Kornhuber 2009) with the multigrid correction replaced by our linear solver:
//   1. nonlinear Gauss-Seidel: each free node in turn moves to the exact
//      minimiser of J in its own value (EnthalpyLaw::solve_nodal); this is what
//      lets a node leave a plateau. Serially it never increases J; on several
//      ranks each rank sweeps its own nodes with the ghost values held, which
//      is Jacobi-like at the rank boundaries (the line search keeps the
//      iteration a descent method all the same);
//   2. truncated Newton: the nodes exactly at a transition temperature keep it,
//      the others are linearised on their branch; one linear solve (the same
//      solve_for_pieces() as the active-set method, so the same reuse of
//      factorisations and AMG hierarchies);
//   3. exact line search: J along theta + alpha v is convex and piecewise
//      quadratic in alpha, its derivative piecewise linear with an upward jump
//      m_i |v_i| L where node i crosses a transition. Walking the crossings in
//      order gives the exact minimiser; where it falls into a jump, the nodes of
//      that crossing stop exactly on their plateau. The Newton step overheats the
//      nodes ahead of the front; the line search stops the front where their
//      latent heat balances the heat the step brings, however many cells that is.
// The iteration ends when the solve's result lies on the pieces it was
// computed with, to round-off: then it solves the step. Should it reach the iteration
// limit, the step falls back to the relaxation iteration.

#include <contact-stefan/thermal/thermal_field.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Epetra_Import.h>
#include <Epetra_Vector.h>

namespace ContactStefan
{
  template <int dim>
  void ThermalField<dim>::gauss_seidel_sweep(Vector &theta)
  {
    TimerOutput::Scope      t(timer, "enthalpy step: Gauss-Seidel");
    const Epetra_CrsMatrix &A       = conductivity_matrix.trilinos_matrix();
    const Epetra_Map       &columns = A.ColMap();
    double                 *th      = entries(theta);
    {
      const Epetra_Vector owned_values(View, A.DomainMap(), th);
      to_columns(owned_values, column_values);
    }
    const double *m = entries(lumped_mass), *h_old = entries(old_enthalpy),
                 *load = entries(step_load);
    for (unsigned int r = 0; r < n_owned; ++r)
      if (owned_free[r])
        {
          const int diagonal_column = columns.LID(static_cast<int>(first_owned + r));
          int       n;
          double   *a;
          int      *index;
          A.ExtractMyRowView(r, n, a, index);
          double diagonal = 0, neighbours = 0;
          for (int k = 0; k < n; ++k)
            if (index[k] == diagonal_column)
              diagonal = a[k];
            else
              neighbours += a[k] * column_values[index[k]];
          const double rhs = m[r] * h_old[r] + load[r] - time_step * neighbours;
          th[r]            = owned_node_law(r).solve_nodal(time_step * diagonal, m[r], rhs);
          column_values[diagonal_column] = th[r];
        }
    hanging_node_constraints.distribute(theta);
  }



  template <int dim>
  double ThermalField<dim>::exact_line_search(Vector &theta, const Vector &v)
  {
    TimerOutput::Scope t(timer, "enthalpy step: line search");
    // dJ/dalpha = v^T (tau A (theta + alpha v) - b) + sum_i m_i v_i H_i(theta_i + alpha v_i)
    // over the free nodes (v vanishes on the Dirichlet ones; the hanging ones
    // are condensed out of A and carry no mass of their own).
    Vector A_theta(owned, mpi_communicator), A_v(owned, mpi_communicator);
    conductivity_matrix.vmult(A_theta, theta);
    conductivity_matrix.vmult(A_v, v);
    const double *th = entries(theta), *d = entries(v), *At = entries(A_theta), *Av = entries(A_v),
                 *m = entries(lumped_mass), *h_old = entries(old_enthalpy),
                 *load = entries(step_load);

    std::vector<LineCrossing> crossings;
    double                    local[2] = {0, 0}; // dJ/dalpha and d2J/dalpha2 at 0+
    for (unsigned int i = 0; i < n_owned; ++i)
      if (owned_free[i] && d[i] != 0)
        {
          local[0] += d[i] * (time_step * At[i] - m[i] * h_old[i] - load[i]);
          local[1] += d[i] * time_step * Av[i];
          owned_node_law(i).add_line_terms(th[i], d[i], m[i], local[0], local[1], crossings);
        }
    double global[2];
    Utilities::MPI::sum(ArrayView<const double>(local, 2),
                        mpi_communicator,
                        ArrayView<double>(global, 2));
    // Every rank walks the same crossings.
    {
      std::vector<double> flat;
      flat.reserve(3 * crossings.size());
      for (const LineCrossing &c : crossings)
        flat.insert(flat.end(), {c.alpha, c.jump, c.slope});
      const std::vector<std::vector<double>> all =
        Utilities::MPI::all_gather(mpi_communicator, flat);
      crossings.clear();
      for (const auto &part : all)
        for (std::size_t k = 0; k + 2 < part.size(); k += 3)
          crossings.push_back({part[k], part[k + 1], part[k + 2]});
    }
    std::sort(crossings.begin(), crossings.end(), [](const LineCrossing &a, const LineCrossing &b) {
      return a.alpha < b.alpha || (a.alpha == b.alpha && a.jump < b.jump);
    });

    // Crossings closer than the round-off of the linear solve are one
    // crossing: the nodes of a column of a straight front must stop together (a
    // node left 1e-12 off its plateau is put back on it by the next
    // Gauss-Seidel sweep anyway).
    const double tolerance   = 1e-10;
    const auto [alpha, snap] = minimise_on_segment(global[0], global[1], crossings, tolerance);

    double *th_out = entries(theta);
    for (unsigned int i = 0; i < n_owned; ++i)
      if (owned_free[i] && d[i] != 0)
        {
          const double       moved   = th_out[i] + alpha * d[i];
          const EnthalpyLaw &l       = owned_node_law(i);
          double             value_i = moved;
          if (snap)
            for (unsigned int j = 0; j < l.n_transitions(); ++j)
              {
                const double a_j = (l.transition_temperature(j) - th_out[i]) / d[i];
                if (a_j > 0 && std::abs(a_j - alpha) <= tolerance * alpha)
                  value_i = l.transition_temperature(j);
              }
          th_out[i] = value_i;
        }
    hanging_node_constraints.distribute(theta);
    return alpha;
  }



  template <int dim>
  bool ThermalField<dim>::truncated_newton_iteration(EnthalpyStepReport &report)
  {
    Vector theta(owned, mpi_communicator), v(owned, mpi_communicator);
    Vector h_new(owned, mpi_communicator);
    double enthalpy_scale = 0;
    for (const auto &l : laws)
      {
        enthalpy_scale = std::max(enthalpy_scale, l.max_heat_capacity());
        for (unsigned int j = 0; j < l.n_transitions(); ++j)
          enthalpy_scale = std::max(enthalpy_scale, l.latent_heat(j));
      }
    // The first iterate: the extrapolated temperature with this step's
    // Dirichlet values (v must vanish on the Dirichlet nodes).
    // (Later passes of a coupling loop within one step: the last pass's
    // temperature, the better guess.)
    theta = first_pass_of_step ? predicted_temperature : temperature;
    dirichlet_constraints.distribute(theta);

    double       *state = entries(phase_state), *th = entries(theta);
    const double *hn   = entries(h_new);
    const char   *free = owned_free.data();
    for (unsigned int it = 1; it <= step_prm.max_active_set_iterations; ++it)
      {
        if (it > 1)
          for (unsigned int s = 0; s < step_prm.gauss_seidel_sweeps; ++s)
            gauss_seidel_sweep(theta);
        // The truncation: a node exactly at a transition temperature stays there.
        unsigned int local_changes = 0;
        for (unsigned int i = 0; i < n_owned; ++i)
          {
            const unsigned int s = owned_node_law(i).state_of_temperature(th[i]);
            local_changes += free[i] && it > 1 && s != static_cast<unsigned int>(state[i]);
            state[i] = s;
          }
        to_ghosted(phase_state, phase_state_ghosted);
        report.state_changes += Utilities::MPI::sum(local_changes, mpi_communicator);

        temperature                  = theta; // the Krylov solvers' initial guess
        report.plateau_nodes         = solve_for_pieces(h_new);
        report.active_set_iterations = it;

        // The solve's result solves the step if every free node lies on the
        // piece it was computed with; up to round-off, because where the
        // solution sits exactly on a kink of H (an equilibrium at a transition
        // temperature) neighbouring pieces give the same (Theta, h).
        unsigned int local_inconsistent = 0;
        double       local_distance = 0, local_size = 0;
        for (unsigned int i = 0; i < n_owned; ++i)
          if (free[i])
            {
              const EnthalpyLaw &l = owned_node_law(i);
              const auto         s = static_cast<unsigned int>(state[i]);
              local_inconsistent += (l.state_of_enthalpy(hn[i]) != s);
              local_distance = std::max(local_distance, l.distance_to_piece(s, hn[i]));
              local_size     = std::max(local_size, std::abs(hn[i]));
            }
        const bool consistent = Utilities::MPI::sum(local_inconsistent, mpi_communicator) == 0;
        const bool consistent_to_round_off =
          Utilities::MPI::max(local_distance, mpi_communicator) <=
          step_prm.active_set_step_tolerance *
            (Utilities::MPI::max(local_size, mpi_communicator) + enthalpy_scale);
        if (consistent || consistent_to_round_off)
          {
            // The solve's (Theta, h) is the step's solution.
            enthalpy           = h_new;
            const double *t_in = entries(temperature), *h = entries(enthalpy);
            for (unsigned int i = 0; i < n_owned; ++i)
              state[i] = free[i] ? owned_node_law(i).state_of_enthalpy(h[i]) :
                                   owned_node_law(i).state_of_temperature(t_in[i]);
            to_ghosted(enthalpy, enthalpy_ghosted);
            to_ghosted(phase_state, phase_state_ghosted);
            if (verbosity >= 1)
              pcout << "      truncated Newton " << it << ": " << report.plateau_nodes
                    << " plateau nodes, converged" << std::endl;
            return true;
          }
        v = temperature;
        v -= theta;
        const double alpha = exact_line_search(theta, v);
        report.damped_steps += (alpha < 1);
        if (verbosity >= 1)
          pcout << "      truncated Newton " << it << ": " << report.plateau_nodes
                << " plateau nodes, step " << alpha << std::endl;
      }
    // Leave a consistent state for the relaxation fallback.
    temperature        = theta;
    const double *t_in = entries(temperature);
    double       *h    = entries(enthalpy);
    for (unsigned int i = 0; i < n_owned; ++i)
      h[i] = owned_node_law(i).enthalpy(t_in[i]);
    to_ghosted(enthalpy, enthalpy_ghosted);
    set_nodal_state_from_enthalpy();
    return false;
  }



  template void   ThermalField<2>::gauss_seidel_sweep(Vector &theta);
  template double ThermalField<2>::exact_line_search(Vector &theta, const Vector &v);
  template bool   ThermalField<2>::truncated_newton_iteration(EnthalpyStepReport &report);
} // namespace ContactStefan
