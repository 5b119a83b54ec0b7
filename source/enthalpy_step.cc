// The enthalpy (Stefan) step: find nodal Theta and h with h_i in H_i(Theta_i) and
//
//     m_i (h_i - h_i^old) + tau (A Theta)_i = tau F_i         at every free node i.
//
// H_i is a maximal monotone graph, so this is a variational inequality. We solve it
// by a primal-dual active-set (semismooth Newton) method on the phase states: for
// a guess of which piece of its graph each node sits on, the system is linear,
//   - a node on the branch of phase p has h_i = offset_p + c_p Theta_i, so its row
//     gets m_i c_p on the diagonal and m_i (h_i^old - offset_p) on the right;
//   - a node on a plateau has Theta_i = T_j: an inhomogeneous constraint, held in
//     the same AffineConstraints object as the Dirichlet and hanging-node ones.
// After the solve every node's enthalpy is known (branch nodes from the law,
// plateau nodes from the residual of their row), and each node moves to the piece
// of its graph that contains that enthalpy. When no node moves, the discrete
// problem is solved exactly (up to the linear solver). Because Theta = beta(h) is
// piecewise linear this is Newton's method on Theta_i = beta(h_i); with an
// M-matrix it converges monotonically in finitely many steps. Outside that setting
// it can cycle, which a per-node count of state changes detects; the step then
// falls back to the nonlinear relaxation iteration, slower but always convergent.
#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>

#include <contact-stefan/coupled_problem.h>

#include <algorithm>
#include <cmath>
#include <functional>

namespace ContactStefan
{
  // Assemble  (tau A + diag(m d)) Theta = m g + tau F  from the per-cell operators,
  // with the current constraints eliminated. d and g are nodal (ghosted vectors).
  template <int dim>
  void CoupledProblem<dim>::assemble_enthalpy_system(const bool assemble_matrix)
  {
    TimerOutput::Scope t(timer, "enthalpy step: assemble");
    const unsigned int n = fe.n_dofs_per_cell();
    LocalMatrix        local_matrix(n, n);
    dealii::Vector<double> local_rhs(n);
    std::vector<types::global_dof_index> dofs(n);
    if (assemble_matrix)
      system_matrix = 0;
    system_rhs = 0;

    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int c = cell->active_cell_index();
          cell->get_dof_indices(dofs);
          local_matrix = cell_conductivity[c];
          local_matrix *= time_step;
          for (unsigned int i = 0; i < n; ++i)
            {
              local_matrix(i, i) += cell_mass[c](i) * nodal_diagonal_ghosted[dofs[i]];
              local_rhs(i) = cell_mass[c](i) * nodal_rhs_ghosted[dofs[i]] +
                             (heat_load_present ? time_step * cell_load[c](i) : 0.);
            }
          if (assemble_matrix)
            constraints.distribute_local_to_global(local_matrix, local_rhs, dofs,
                                                   system_matrix, system_rhs);
          else
            constraints.distribute_local_to_global(local_rhs, dofs, system_rhs, local_matrix);
        }
    if (assemble_matrix)
      system_matrix.compress(VectorOperation::add);
    system_rhs.compress(VectorOperation::add);
  }



  // Solve system_matrix x = system_rhs with the selected solver; x holds the
  // constrained values afterwards.
  template <int dim>
  void CoupledProblem<dim>::solve_linear_system(Vector &solution)
  {
    TimerOutput::Scope t(timer, "enthalpy step: linear solve");
    if (prm.solver.linear_solver == "direct")
      {
        SolverControl                                  control(1, 0);
        TrilinosWrappers::SolverDirect::AdditionalData data(prm.output.verbosity >= 2,
                                                            prm.solver.direct_solver_type);
        TrilinosWrappers::SolverDirect                 solver(control, data);
        solver.solve(system_matrix, solution, system_rhs);
      }
    else
      {
        SolverControl control(prm.solver.cg_max_iterations,
                              prm.solver.cg_tolerance * system_rhs.l2_norm());
        TrilinosWrappers::PreconditionAMG                 amg;
        TrilinosWrappers::PreconditionAMG::AdditionalData data;
        data.elliptic = true;
        amg.initialize(system_matrix, data);
        SolverCG<Vector> cg(control);
        cg.solve(system_matrix, solution, system_rhs, amg);
        if (prm.output.verbosity >= 2)
          pcout << "      CG: " << control.last_step() << " iterations" << std::endl;
      }
    constraints.distribute(solution);
  }



  // result = A theta, hanging-node condensed (unconstrained otherwise).
  template <int dim>
  void CoupledProblem<dim>::compute_conductivity_residual(const Vector &theta,
                                                          Vector       &result) const
  {
    const unsigned int                   n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index> dofs(n);
    dealii::Vector<double>               local_theta(n), local_result(n);
    result = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int i = 0; i < n; ++i)
            local_theta(i) = theta[dofs[i]];
          cell_conductivity[cell->active_cell_index()].vmult(local_result, local_theta);
          hanging_node_constraints.distribute_local_to_global(local_result, dofs, result);
        }
    result.compress(VectorOperation::add);
  }



  // One linear solve of the step for a given choice of linear piece at every
  // node: pieces with a fixed temperature become constraints (on top of the
  // hanging-node and Dirichlet ones, which win), the others put m_i c on the
  // diagonal and m_i (h_i^old - offset) on the right. Afterwards every owned
  // node has its enthalpy: from its piece where it is free, from the residual of
  // its row where its temperature was fixed, from the temperature on Dirichlet nodes.
  template <int dim>
  unsigned int CoupledProblem<dim>::solve_for_pieces(
    const std::function<LinearPiece(const types::global_dof_index)> &piece_of)
  {
    constraints.clear();
    constraints.reinit(locally_relevant_dofs);
    constraints.merge(dirichlet_constraints);
    unsigned int local_fixed = 0;
    for (const auto dof : locally_relevant_dofs)
      if (!constraints.is_constrained(dof))
        {
          const LinearPiece p = piece_of(dof);
          if (p.fixed)
            {
              constraints.add_line(dof);
              constraints.set_inhomogeneity(dof, p.temperature);
              local_fixed += locally_owned_dofs.is_element(dof);
            }
        }
    constraints.close();

    for (const auto dof : locally_owned_dofs)
      {
        const LinearPiece p = piece_of(dof);
        nodal_diagonal[dof] = p.fixed ? 0. : p.capacity;
        nodal_rhs[dof]      = p.fixed ? 0. : old_enthalpy[dof] - p.offset;
      }
    nodal_diagonal.compress(VectorOperation::insert);
    nodal_rhs.compress(VectorOperation::insert);
    nodal_diagonal_ghosted = nodal_diagonal;
    nodal_rhs_ghosted      = nodal_rhs;

    assemble_enthalpy_system(true);
    solve_linear_system(temperature);
    temperature_ghosted = temperature;

    Vector A_theta(locally_owned_dofs, mpi_communicator);
    compute_conductivity_residual(temperature_ghosted, A_theta);
    for (const auto dof : locally_owned_dofs)
      {
        const double theta = temperature[dof];
        if (dirichlet_constraints.is_constrained(dof))
          enthalpy[dof] = law(dof).enthalpy(theta);
        else if (const LinearPiece p = piece_of(dof); p.fixed)
          enthalpy[dof] = old_enthalpy[dof] +
                          time_step * (heat_load[dof] - A_theta[dof]) / lumped_mass[dof];
        else
          enthalpy[dof] = p.offset + p.capacity * theta;
      }
    enthalpy.compress(VectorOperation::insert);
    enthalpy_ghosted = enthalpy;
    return Utilities::MPI::sum(local_fixed, mpi_communicator);
  }



  // Move every owned node to the state new_state(dof, h) and count the moves; the
  // state vector travels to the ghosts. Returns the number of moves everywhere.
  // With a tracker, a move against the direction of the node's previous move
  // (back down the phase sequence after moving up, or vice versa) is counted as
  // a reversal: the signature of the overshoot that makes plain Newton cycle.
  template <int dim>
  unsigned int CoupledProblem<dim>::update_states(
    Vector                                                                  &state,
    Vector                                                                  &state_ghosted,
    const std::function<unsigned int(const types::global_dof_index, double)> &new_state,
    ReversalTracker                                                         *tracker)
  {
    unsigned int local_changes = 0, k = 0;
    for (const auto dof : locally_owned_dofs)
      {
        const unsigned int s   = new_state(dof, enthalpy[dof]);
        const unsigned int old = static_cast<unsigned int>(state[dof]);
        if (s != old)
          {
            state[dof] = s;
            ++local_changes;
            if (tracker)
              {
                const int direction = (s > old ? 1 : -1);
                if (tracker->last_direction[k] == -direction)
                  ++tracker->reversals[k];
                tracker->last_direction[k] = direction;
              }
          }
        ++k;
      }
    state.compress(VectorOperation::insert);
    state_ghosted = state;
    return Utilities::MPI::sum(local_changes, mpi_communicator);
  }



  // The fallback: nonlinear relaxation (Berger, Brezis & Rogers 1979; the form the
  // Nedoma-Dvorak paper writes the step in). With alpha <= min c and
  // Theta^m = beta(h^m), solve
  //     (alpha M + tau A) w = M (h^old - h^m + alpha Theta^m) + tau F
  // and set h^{m+1} = h^m + alpha (w - Theta^m). The fixed point is the solution of
  // the step; the iteration contracts because beta is Lipschitz with constant
  // 1/min c. The matrix is the same in every iteration.
  template <int dim>
  unsigned int CoupledProblem<dim>::relaxation_fallback()
  {
    TimerOutput::Scope t(timer, "enthalpy step: relaxation fallback");
    double min_capacity = HUGE_VAL, h_scale = 0;
    for (const auto &l : laws)
      {
        min_capacity = std::min(min_capacity, l.min_heat_capacity());
        for (unsigned int j = 0; j < l.n_transitions(); ++j)
          h_scale = std::max(h_scale, l.latent_heat(j));
      }
    min_capacity = Utilities::MPI::min(min_capacity, mpi_communicator);
    h_scale      = std::max(Utilities::MPI::max(h_scale, mpi_communicator),
                       Utilities::MPI::max(old_enthalpy.linfty_norm(), mpi_communicator));
    const double alpha = prm.solver.relaxation_parameter_fraction * min_capacity;

    constraints.clear();
    constraints.reinit(locally_relevant_dofs);
    constraints.merge(dirichlet_constraints);
    constraints.close();
    nodal_diagonal = alpha;
    nodal_diagonal_ghosted = nodal_diagonal;

    TrilinosWrappers::SolverDirect::AdditionalData data(false, prm.solver.direct_solver_type);
    SolverControl                                  control(1, 0);
    TrilinosWrappers::SolverDirect                 direct(control, data);

    for (unsigned int m = 1; m <= prm.solver.relaxation_max_iterations; ++m)
      {
        for (const auto dof : locally_owned_dofs)
          nodal_rhs[dof] = old_enthalpy[dof] - enthalpy[dof] + alpha * law(dof).temperature(enthalpy[dof]);
        nodal_rhs.compress(VectorOperation::insert);
        nodal_rhs_ghosted = nodal_rhs;
        assemble_enthalpy_system(m == 1);
        if (prm.solver.linear_solver == "direct")
          {
            if (m == 1)
              direct.initialize(system_matrix);
            direct.solve(temperature, system_rhs);
            constraints.distribute(temperature);
          }
        else
          solve_linear_system(temperature);

        double local_change = 0;
        for (const auto dof : locally_owned_dofs)
          {
            const EnthalpyLaw &l = law(dof);
            double             h;
            if (dirichlet_constraints.is_constrained(dof))
              h = l.enthalpy(temperature[dof]);
            else
              h = enthalpy[dof] + alpha * (temperature[dof] - l.temperature(enthalpy[dof]));
            local_change  = std::max(local_change, std::abs(h - enthalpy[dof]));
            enthalpy[dof] = h;
          }
        enthalpy.compress(VectorOperation::insert);
        const double change = Utilities::MPI::max(local_change, mpi_communicator);
        if (prm.output.verbosity >= 1)
          pcout << "      relaxation " << m << ": max enthalpy change " << change << std::endl;
        if (change <= prm.solver.relaxation_tolerance * h_scale)
          {
            for (const auto dof : locally_owned_dofs)
              {
                temperature[dof] = law(dof).temperature(enthalpy[dof]);
                phase_state[dof] = law(dof).state_of_enthalpy(enthalpy[dof]);
              }
            temperature.compress(VectorOperation::insert);
            phase_state.compress(VectorOperation::insert);
            hanging_node_constraints.distribute(temperature);
            temperature_ghosted = temperature;
            enthalpy_ghosted    = enthalpy;
            phase_state_ghosted = phase_state;
            return m;
          }
      }
    throw std::runtime_error("the relaxation fallback of the enthalpy step did not converge in "
                             "'Solver/Relaxation max iterations' = " +
                             std::to_string(prm.solver.relaxation_max_iterations) +
                             " iterations at t = " + std::to_string(time));
  }



  // Energy balance of the step. With r = M (h - h^old) + tau A Theta - tau F, the
  // rows of free nodes must vanish; the rows of Dirichlet nodes are the heat that
  // entered through them (the reaction). So
  //     (stored heat) - (sources and fluxes) - (Dirichlet heat) = sum over free r_i,
  // which we report relative to the heat moved in the step. It measures how well
  // the discrete equations, including the enthalpy bookkeeping on the plateaus,
  // are satisfied.
  template <int dim>
  double CoupledProblem<dim>::compute_energy_balance()
  {
    Vector A_theta(locally_owned_dofs, mpi_communicator);
    compute_conductivity_residual(temperature_ghosted, A_theta);
    double free_sum = 0, scale = 0;
    for (const auto dof : locally_owned_dofs)
      {
        if (hanging_node_constraints.is_constrained(dof))
          continue;
        const double stored = lumped_mass[dof] * (enthalpy[dof] - old_enthalpy[dof]);
        const double r      = stored + time_step * (A_theta[dof] - heat_load[dof]);
        if (!dirichlet_constraints.is_constrained(dof))
          free_sum += r;
        else
          scale += std::abs(r);
        scale += std::abs(stored) + time_step * std::abs(heat_load[dof]);
      }
    free_sum = Utilities::MPI::sum(free_sum, mpi_communicator);
    scale    = Utilities::MPI::sum(scale, mpi_communicator);
    return scale > 0 ? std::abs(free_sum) / scale : 0.;
  }



  // The plain primal-dual active-set iteration on the phase states, warm-started
  // from the previous step. Returns true when the states are consistent.
  template <int dim>
  bool CoupledProblem<dim>::plain_active_set_iteration(EnthalpyStepReport &report)
  {
    ReversalTracker tracker(locally_owned_dofs.n_elements());
    const auto      piece_of = [&](const types::global_dof_index dof) {
      return law(dof).piece(static_cast<unsigned int>(phase_state_ghosted[dof]));
    };
    const auto new_state = [&](const types::global_dof_index dof, const double h) {
      return dirichlet_constraints.is_constrained(dof) ?
               law(dof).state_of_temperature(temperature[dof]) :
               law(dof).state_of_enthalpy(h);
    };
    while (report.active_set_iterations < prm.solver.max_active_set_iterations)
      {
        report.plateau_nodes = solve_for_pieces(piece_of);
        ++report.active_set_iterations;
        const unsigned int n_changes =
          update_states(phase_state, phase_state_ghosted, new_state, &tracker);
        report.state_changes += n_changes;
        if (prm.output.verbosity >= 1)
          pcout << "      active set " << report.active_set_iterations << ": "
                << report.plateau_nodes << " plateau nodes, " << n_changes << " state changes"
                << std::endl;
        if (n_changes == 0)
          return true;
        if (Utilities::MPI::max(tracker.max_reversals(), mpi_communicator) >=
            prm.solver.max_state_reversals_per_node)
          return false;
      }
    return false;
  }



  // The nested Newton iteration (Brugnano & Casulli 2008; Casulli & Zanolli
  // 2012): the outer level J of each node (which concave kinks it has passed) is
  // frozen while an inner active-set iteration solves the convexified problem;
  // the inner iteration then moves monotonically and cannot cycle, and the outer
  // levels settle after finitely many rounds. Starts from the current enthalpy.
  template <int dim>
  bool CoupledProblem<dim>::nested_active_set_iteration(EnthalpyStepReport &report)
  {
    for (const auto dof : locally_owned_dofs)
      {
        const unsigned int J = law(dof).outer_level(enthalpy[dof]);
        outer_level[dof]     = J;
        phase_state[dof]     = law(dof).nested_piece_of_enthalpy(J, enthalpy[dof]);
      }
    outer_level.compress(VectorOperation::insert);
    phase_state.compress(VectorOperation::insert);
    outer_level_ghosted = outer_level;
    phase_state_ghosted = phase_state;

    const auto piece_of = [&](const types::global_dof_index dof) {
      return law(dof).nested_piece(static_cast<unsigned int>(outer_level_ghosted[dof]),
                                   static_cast<unsigned int>(phase_state_ghosted[dof]));
    };
    const auto inner_state = [&](const types::global_dof_index dof, const double h) {
      return law(dof).nested_piece_of_enthalpy(static_cast<unsigned int>(outer_level[dof]), h);
    };
    const auto outer_state = [&](const types::global_dof_index dof, const double h) {
      return law(dof).outer_level(h);
    };

    while (report.active_set_iterations < prm.solver.max_active_set_iterations)
      {
        report.plateau_nodes = solve_for_pieces(piece_of);
        ++report.active_set_iterations;
        const unsigned int n_inner =
          update_states(phase_state, phase_state_ghosted, inner_state, nullptr);
        report.state_changes += n_inner;
        unsigned int n_outer = 0;
        if (n_inner == 0)
          {
            // Inner iteration converged: update the outer levels and restart the
            // inner states from the new levels.
            n_outer = update_states(outer_level, outer_level_ghosted, outer_state, nullptr);
            report.state_changes += n_outer;
            if (n_outer > 0)
              update_states(phase_state, phase_state_ghosted, inner_state, nullptr);
          }
        if (prm.output.verbosity >= 1)
          pcout << "      nested " << report.active_set_iterations << ": "
                << report.plateau_nodes << " obstacle/plateau nodes, " << n_inner
                << " inner and " << n_outer << " outer changes" << std::endl;
        if (n_inner == 0 && n_outer == 0)
          {
            // Consistent: record the true phase states for output and warm start.
            for (const auto dof : locally_owned_dofs)
              phase_state[dof] = law(dof).state_of_enthalpy(enthalpy[dof]);
            phase_state.compress(VectorOperation::insert);
            phase_state_ghosted = phase_state;
            return true;
          }
      }
    return false;
  }



  template <int dim>
  EnthalpyStepReport CoupledProblem<dim>::solve_enthalpy_step()
  {
    EnthalpyStepReport report;
    bool               converged = plain_active_set_iteration(report);
    if (!converged && report.active_set_iterations < prm.solver.max_active_set_iterations)
      {
        if (prm.output.verbosity >= 1)
          pcout << "      cycling: switching to the nested Newton iteration" << std::endl;
        report.nested = true;
        converged     = nested_active_set_iteration(report);
      }
    if (!converged)
      {
        pcout << "   Enthalpy step: no convergence in 'Solver/Max active-set iterations' = "
              << prm.solver.max_active_set_iterations << " at t = " << time
              << "; switching to the relaxation fallback" << std::endl;
        report.relaxation_iterations = relaxation_fallback();
        unsigned int local_plateau   = 0;
        for (const auto dof : locally_owned_dofs)
          local_plateau += EnthalpyLaw::is_plateau(static_cast<unsigned int>(phase_state[dof]));
        report.plateau_nodes = Utilities::MPI::sum(local_plateau, mpi_communicator);
      }
    report.energy_residual = compute_energy_balance();
    return report;
  }



  template class CoupledProblem<2>;
} // namespace ContactStefan
