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
// piecewise linear this is Newton's method on Theta_i = beta(h_i). Full Newton
// steps can cycle; an Armijo line search on the step's convex functional makes
// the iteration globally convergent (see active_set_iteration and
// doc/algorithms.md). Should it still hit its iteration limit, the step falls
// back to the nonlinear relaxation iteration, slower but always convergent.

#include <contact-stefan/linear_algebra/crs_rows.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include <Epetra_Import.h>
#include <Epetra_Vector.h>

namespace ContactStefan
{
  // The system  (tau A + diag(m d)) Theta = m g + tau F - G  of one active-set
  // iteration, with the Dirichlet and plateau values eliminated.
  //
  // Only a few rows change from one iteration (or step) to the next, so nothing
  // is integrated here: the conductivity matrix A (hanging nodes condensed) is
  // assembled once per mesh and conductivity (assemble_conductivity_matrix), and
  // the step's load tau F - G once per solve() (assemble_step_load). This
  // function copies tau A into the system matrix row by row, adds the lumped
  // mass terms m_i d_i on the free rows, and eliminates the nodes with a
  // prescribed value (Dirichlet or plateau): their row becomes the diagonal
  // entry alone, their column moves to the right-hand side. That is what
  // AffineConstraints::distribute_local_to_global would produce, at the cost
  // of one pass over the matrix entries instead of an integration over all
  // cells. The lumped mass stays the condensed diagonal m_i on hanging meshes
  // (distributing a cell's diagonal mass through hanging-node constraints would
  // couple the parents). d and g are nodal vectors.
  template <int dim>
  void ThermalField<dim>::assemble_system(const bool assemble_matrix)
  {
    TimerOutput::Scope      t(timer, "enthalpy step: assemble");
    const Epetra_CrsMatrix &A = conductivity_matrix.trilinos_matrix();
    // Edited in place: the matrix keeps its layout (and the AMG hierarchy
    // built on it stays attached to it).
    Epetra_CrsMatrix &S = const_cast<Epetra_CrsMatrix &>(system_matrix.trilinos_matrix());

    // The prescribed value of every column (NaN: free or hanging), decided by
    // the column's owner and imported: a column of a condensed hanging-node
    // row may lie outside this process's relevant set.
    // (From the list of constraint lines, not a lookup per row: the lines are
    // the prescribed and plateau nodes, a fraction of the rows.)
    std::vector<char> fixed_row(n_owned, 0);
    {
      Epetra_Vector owned_values(A.DomainMap());
      for (int r = 0; r < static_cast<int>(n_owned); ++r)
        owned_values[r] = std::numeric_limits<double>::quiet_NaN();
      for (const auto &line : constraints.get_lines())
        if (line.index >= first_owned && line.index < first_owned + n_owned &&
            !owned_hanging[line.index - first_owned])
          {
            const auto r    = line.index - first_owned;
            fixed_row[r]    = 1;
            owned_values[r] = line.inhomogeneity;
          }
      to_columns(owned_values, fixed_column_value);
    }
    // Row r is owned node r (index_local_entries() checks it), and so is its
    // diagonal column (owned_diagonal_column).
    const CrsRows row_of_A(A), row_of_S(S);
    const double *load = entries(step_load), *m = entries(lumped_mass);
    const double *capacity = entries(nodal_diagonal), *nodal = entries(nodal_rhs);
    double       *rhs_entries = entries(system_rhs);
    for (int r = 0; r < static_cast<int>(n_owned); ++r)
      {
        const int diagonal_column = owned_diagonal_column[r];
        int       n_a, n_s;
        double   *a, *s;
        int      *index_a, *index_s;
        row_of_A(r, n_a, a, index_a);
        row_of_S(r, n_s, s, index_s);
        Assert(n_a == n_s, ExcInternalError());
        const bool hanging  = owned_hanging[r];
        const bool fixed    = fixed_row[r];
        double     diagonal = 0, rhs = hanging ? 0. : load[r];
        for (int k = 0; k < n_a; ++k)
          {
            Assert(index_a[k] == index_s[k], ExcInternalError());
            const double value = time_step * a[k];
            if (index_a[k] == diagonal_column)
              diagonal = value;
            else if (!std::isnan(fixed_column_value[index_a[k]]))
              {
                rhs -= value * fixed_column_value[index_a[k]];
                if (assemble_matrix)
                  s[k] = 0;
              }
            else if (assemble_matrix)
              s[k] = fixed ? 0. : value;
          }
        if (fixed)
          {
            // The row of a prescribed node: its diagonal entry alone, scaled
            // like its neighbours' so that neither the direct solver's pivoting
            // nor the AMG hierarchy sees an outlier.
            const double scale =
              diagonal > 0 ? diagonal : m[r] * owned_node_law(r).max_heat_capacity();
            diagonal = scale > 0 ? scale : 1.;
            rhs      = diagonal * constraints.get_inhomogeneity(first_owned + r);
          }
        else if (!hanging)
          {
            diagonal += m[r] * capacity[r];
            rhs += m[r] * nodal[r];
          }
        if (assemble_matrix)
          for (int k = 0; k < n_a; ++k)
            if (index_a[k] == diagonal_column)
              s[k] = diagonal;
        rhs_entries[r] = rhs;
      }
  }



  // A (the conductivity matrix of the mesh, hanging nodes condensed), assembled
  // from the cell matrices A_K whenever they changed.
  template <int dim>
  void ThermalField<dim>::assemble_conductivity_matrix()
  {
    if (conductivity_matrix_version == conductivity_version)
      return;
    TimerOutput::Scope                   t(timer, "assemble conductivity");
    const unsigned int                   n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index> dofs(n);
    conductivity_matrix = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(
            cell_conductivity[cell->active_cell_index()], dofs, conductivity_matrix);
        }
    add_conductance_matrix(conductivity_matrix);
    conductivity_matrix.compress(VectorOperation::add);
    conductivity_matrix_version = conductivity_version;
  }



  // tau F - G of the step, hanging nodes condensed: the load every iteration of
  // solve() shares.
  template <int dim>
  void ThermalField<dim>::assemble_step_load()
  {
    TimerOutput::Scope                   t(timer, "enthalpy step: assemble");
    const unsigned int                   n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index> dofs(n);
    dealii::Vector<double>               local(n);
    step_load = 0;
    if (functions.heat_load_present() || heating)
      {
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const unsigned int c = cell->active_cell_index();
              cell->get_dof_indices(dofs);
              for (unsigned int i = 0; i < n; ++i)
                local(i) = (functions.heat_load_present() ? time_step * cell_load[c](i) : 0.) -
                           (heating ? cell_heating[c](i) : 0.);
              hanging_node_constraints.distribute_local_to_global(local, dofs, step_load);
            }
        step_load.compress(VectorOperation::add);
      }
  }



  // result = A theta, hanging-node condensed (unconstrained otherwise), cell
  // by cell from the A_K.
  template <int dim>
  void ThermalField<dim>::apply_conductivity(const Vector &theta, Vector &result) const
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
    add_conductance_product(theta, result);
    result.compress(VectorOperation::add);
  }



  template <int dim>
  void ThermalField<dim>::to_ghosted(const Vector &values, Vector &ghosted) const
  {
    AssertThrow(ghosted.trilinos_vector().Import(values.trilinos_vector(), *ghost_import, Insert) ==
                  0,
                ExcInternalError());
  }



  // values (over the conductivity matrix's domain map, i.e. the owned rows)
  // onto its column map, in column order.
  template <int dim>
  void ThermalField<dim>::to_columns(const Epetra_Vector &values, std::vector<double> &result) const
  {
    const Epetra_CrsMatrix &A = conductivity_matrix.trilinos_matrix();
    result.resize(A.ColMap().NumMyElements());
    if (A.Importer() == nullptr) // the columns are the owned rows
      {
        for (int c = 0; c < A.ColMap().NumMyElements(); ++c)
          result[c] = values[c];
        return;
      }
    Epetra_Vector columns(A.ColMap());
    AssertThrow(columns.Import(values, *A.Importer(), Insert) == 0, ExcInternalError());
    for (int c = 0; c < A.ColMap().NumMyElements(); ++c)
      result[c] = columns[c];
  }



  // Both products of conductivity_times() in one pass over the rows (the
  // energy balance needs both after every step).
  template <int dim>
  void ThermalField<dim>::conductivity_times(Vector &product, Vector &absolute_product) const
  {
    const Epetra_CrsMatrix &A = conductivity_matrix.trilinos_matrix();
    Epetra_Vector           owned_values(A.DomainMap());
    const double           *theta = entries(temperature);
    to_columns(*temperature.trilinos_vector()(0), signed_column_values);
    for (int r = 0; r < A.DomainMap().NumMyElements(); ++r)
      owned_values[r] = std::abs(theta[r]);
    to_columns(owned_values, column_values);
    double       *Ax = entries(product), *Ax_abs = entries(absolute_product);
    const CrsRows row_of(A);
    for (int r = 0; r < A.RowMap().NumMyElements(); ++r)
      {
        int     n;
        double *a;
        int    *index;
        row_of(r, n, a, index);
        double sum = 0, sum_abs = 0;
        for (int k = 0; k < n; ++k)
          {
            sum += a[k] * signed_column_values[index[k]];
            sum_abs += std::abs(a[k]) * column_values[index[k]];
          }
        Ax[r]     = sum;
        Ax_abs[r] = sum_abs;
      }
  }



  template <int dim>
  void ThermalField<dim>::conductivity_times(Vector &result) const
  {
    conductivity_matrix.vmult(result, temperature);
  }



  // One linear solve of the step for a given choice of linear piece at every
  // node: pieces with a fixed temperature become constraints (on top of the
  // hanging-node and Dirichlet ones, which win), the others put m_i c on the
  // diagonal and m_i (h_i^old - offset) on the right. Afterwards every owned
  // node has its enthalpy: from its piece where it is free, from the residual of
  // its row where its temperature was fixed, from the temperature on Dirichlet nodes.
  template <int dim>
  unsigned int ThermalField<dim>::solve_for_pieces(Vector &h_new, const double tolerance)
  {
    constraints.clear();
    constraints.reinit(relevant);
    constraints.merge(dirichlet_constraints);
    unsigned int  local_fixed = 0, k = 0;
    const double *state_ghosted = entries(phase_state_ghosted);
    for (auto it = relevant.begin(); it != relevant.end(); ++it, ++k)
      if (!constraints.is_constrained(*it))
        {
          const LinearPiece p =
            laws[law_of_node[k]].piece(static_cast<unsigned int>(state_ghosted[relevant_entry[k]]));
          if (p.fixed)
            {
              constraints.add_line(*it);
              constraints.set_inhomogeneity(*it, p.temperature);
              local_fixed += (*it >= first_owned && *it < first_owned + n_owned);
            }
        }
    constraints.close();

    const double *state = entries(phase_state), *h_old = entries(old_enthalpy);
    double       *diagonal = entries(nodal_diagonal), *rhs = entries(nodal_rhs);
    const auto    piece_at = [&](const unsigned int i) {
      return owned_node_law(i).piece(static_cast<unsigned int>(state[i]));
    };
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        const LinearPiece p = piece_at(i);
        diagonal[i]         = p.fixed ? 0. : p.capacity;
        rhs[i]              = p.fixed ? 0. : h_old[i] - p.offset;
      }

    // The matrix tau A + diag(m d) with these constraints: unchanged (same
    // tau, conductivity, constraint pattern and diagonal; a scene without
    // phase change, a front that stays put) it is neither re-assembled nor
    // re-factorised.
    const std::uint64_t signature = Fingerprint::combine(
      Fingerprint::combine(Fingerprint::constraints(constraints, owned, false, mpi_communicator),
                           Fingerprint::vector(nodal_diagonal)),
      Fingerprint::combine(Fingerprint::bits(time_step), conductivity_version));
    const bool assemble  = !(have_factorisation && signature == matrix_signature);
    bool       factorise = !(have_factorisation && signature == factorisation_signature);
    assemble_system(assemble);
    matrix_signature = signature;
    // Back to the values the current hierarchy was made for, after solves that
    // borrowed it: it serves them again, unless the linear solver has since
    // built another one (a CG failure, or CG over its budget): then set up as
    // for new values.
    if (!factorise && assemble && !linear_solver.recall(signature))
      factorise = true;
    if (factorise)
      {
        // The AMG hierarchy (iterative path) is built once per tau and
        // conductivity; while only the active set changes it is recomputed on
        // its aggregates (LinearSolver::update), which costs about half a build.
        const std::uint64_t operator_signature =
          Fingerprint::combine(Fingerprint::bits(time_step), conductivity_version);
        const bool keep = have_preconditioner && operator_signature == preconditioner_signature;
        // A set seen shortly before (the set without plateau nodes recurs
        // each time a front passes a row of nodes): its kept factorisation.
        // The section times the look-up (a hit swaps pointers; a miss costs
        // a comparison of keys) and counts the attempts.
        bool recalled = false;
        if (keep)
          {
            TimerOutput::Scope t(timer, "enthalpy step: recall factorisation");
            recalled = linear_solver.recall(signature);
          }
        // A loose solve (the set is still changing) borrows the current AMG
        // hierarchy instead of recomputing it for values that will
        // probably not be solved for again.
        const bool borrowed = !recalled && keep && tolerance > 0 &&
                              linear_solver.borrow_preconditioner(system_matrix, signature);
        if (!recalled && !borrowed)
          {
            TimerOutput::Scope t(timer, "enthalpy step: factorise");
            if (keep)
              linear_solver.update(system_matrix, signature);
            else
              linear_solver.initialize(system_matrix, signature);
            ++n_factorisations;
          }
        have_factorisation = true;
        if (!borrowed)
          factorisation_signature = signature;
        have_preconditioner      = true;
        preconditioner_signature = operator_signature;
      }
    {
      TimerOutput::Scope t(timer, "enthalpy step: linear solve");
      // A guess (the block correction's temperature, set_initial_guess())
      // that solves this system already stands: a matrix-vector product in
      // place of a solve, on the direct path too. Only the free rows count:
      // a constrained row holds what the condensation put there (0 for a
      // hanging node), not the value distribute() gives the guess, and the
      // condensed matrix has no column for a constrained DoF.
      bool accepted = false;
      if (guess_pending)
        {
          guess_pending = false;
          Vector residual(owned, mpi_communicator);
          system_matrix.residual(residual, temperature, system_rhs);
          constraints.set_zero(residual);
          accepted = residual.l2_norm() <= guess_tolerance * system_rhs.l2_norm();
          guesses_accepted += accepted;
        }
      if (!accepted)
        linear_solver.solve(temperature, system_rhs, tolerance);
      constraints.distribute(temperature);
    }
    to_ghosted(temperature, temperature_ghosted);

    Vector A_theta(owned, mpi_communicator);
    conductivity_times(A_theta);
    const double *theta = entries(temperature), *A = entries(A_theta), *m = entries(lumped_mass);
    const double *F = entries(heat_load), *G = entries(coupling_heat);
    double       *h = entries(h_new);
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        if (!owned_free[i])
          h[i] = owned_node_law(i).enthalpy(theta[i]);
        else if (const LinearPiece p = piece_at(i); p.fixed)
          // (step_heat() = tau F - G)
          h[i] = h_old[i] + (time_step * F[i] - G[i] - time_step * A[i]) / m[i];
        else
          h[i] = p.offset + p.capacity * theta[i];
      }
    return Utilities::MPI::sum(local_fixed, mpi_communicator);
  }



  // The relaxation iteration (Berger, Brezis & Rogers 1979; the form the
  // Nedoma-Dvorak paper writes the step in), the fallback of the active-set
  // method and, with 'Enthalpy solver = relaxation', a baseline. With
  // alpha_i <= the smallest heat capacity of node i's law and Theta^m = beta(h^m),
  // solve
  //     (alpha M + tau A) w = M (h^old - h^m + alpha Theta^m) + tau F
  // and set h^{m+1} = h^m + alpha (w - Theta^m). Its fixed point solves the step;
  // it contracts because beta_i is Lipschitz with constant 1/min c_i, but slowly
  // where tau/h^2 is large, so it stops on the residual of the step equations,
  // not on the size of the update. The matrix is the same in every iteration:
  // it is assembled and factorised (or its AMG built) once.
  template <int dim>
  unsigned int ThermalField<dim>::relaxation_fallback()
  {
    TimerOutput::Scope t(timer, "enthalpy step: relaxation");
    const double       fraction = step_prm.relaxation_parameter_fraction;
    constraints.clear();
    constraints.reinit(relevant);
    constraints.merge(dirichlet_constraints);
    constraints.close();
    for (const auto dof : owned)
      nodal_diagonal[dof] = fraction * law(dof).min_heat_capacity();
    nodal_diagonal.compress(VectorOperation::insert);

    Vector A_theta(owned, mpi_communicator), A_abs_theta(owned, mpi_communicator);

    for (unsigned int m = 1; m <= step_prm.relaxation_max_iterations; ++m)
      {
        for (const auto dof : owned)
          nodal_rhs[dof] = old_enthalpy[dof] - enthalpy[dof] +
                           nodal_diagonal[dof] * law(dof).temperature(enthalpy[dof]);
        nodal_rhs.compress(VectorOperation::insert);
        assemble_system(m == 1);
        if (m == 1)
          {
            linear_solver.initialize(system_matrix);
            have_factorisation = false; // not a matrix solve_for_pieces() can reuse
            ++n_factorisations;
          }
        linear_solver.solve(temperature, system_rhs);
        constraints.distribute(temperature);

        for (const auto dof : owned)
          {
            const EnthalpyLaw &l = law(dof);
            enthalpy[dof]        = dirichlet_constraints.is_constrained(dof) ?
                                     l.enthalpy(temperature[dof]) :
                                     enthalpy[dof] + nodal_diagonal[dof] *
                                                (temperature[dof] - l.temperature(enthalpy[dof]));
          }
        enthalpy.compress(VectorOperation::insert);
        set_nodal_state_from_enthalpy();

        // Residual of the step equations at Theta = beta(h), relative to the
        // size of their terms.
        conductivity_times(A_theta, A_abs_theta);
        double residual = 0, scale = 0;
        for (const auto dof : owned)
          if (!dirichlet_constraints.is_constrained(dof))
            {
              const double stored = lumped_mass[dof] * (enthalpy[dof] - old_enthalpy[dof]);
              residual =
                std::max(residual, std::abs(stored + time_step * A_theta[dof] - step_heat(dof)));
              scale = std::max(scale,
                               std::abs(stored) + std::abs(coupling_heat[dof]) +
                                 time_step * (std::abs(heat_load[dof]) + A_abs_theta[dof]));
            }
        residual = Utilities::MPI::max(residual, mpi_communicator);
        scale    = Utilities::MPI::max(scale, mpi_communicator);
        if (verbosity >= 1)
          pcout << "      relaxation " << m << ": residual " << residual << " (scale " << scale
                << ")" << std::endl;
        if (residual <= step_prm.relaxation_tolerance * scale)
          return m;
      }
    throw StepNotConverged("the relaxation iteration of the enthalpy step did not converge in "
                           "'Solver/Relaxation max iterations' = " +
                           std::to_string(step_prm.relaxation_max_iterations) +
                           " iterations at t = " + std::to_string(time));
  }



  // Energy balance of the step. With r = M (h - h^old) + tau A Theta - tau F, the
  // rows of free nodes must vanish; the rows of Dirichlet nodes are the heat that
  // entered through them (the reaction). So
  //     (stored heat) - (sources and fluxes) - (Dirichlet heat) = sum over free r_i.
  // We report sum |r_i| over the free nodes (no cancellation) relative to the heat
  // moved in the step, and separately count the nodes whose h_i is not in
  // H_i(Theta_i) (must be zero): together they check the equations and the
  // enthalpy bookkeeping on the plateaus.
  template <int dim>
  double ThermalField<dim>::compute_energy_balance(unsigned int &inconsistent) const
  {
    Vector A_theta(owned, mpi_communicator), A_abs_theta(owned, mpi_communicator);
    conductivity_times(A_theta, A_abs_theta);
    double        free_sum = 0, scale = 0;
    unsigned int  inconsistent_nodes = 0;
    const double *h = entries(enthalpy), *h_old = entries(old_enthalpy), *m = entries(lumped_mass);
    const double *A = entries(A_theta), *A_abs = entries(A_abs_theta),
                 *theta = entries(temperature);
    const double *F = entries(heat_load), *G = entries(coupling_heat);
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        const types::global_dof_index dof = first_owned + i;
        if (hanging_node_constraints.is_constrained(dof))
          continue;
        const double stored = m[i] * (h[i] - h_old[i]);
        // (step_heat() = tau F - G)
        const double r = stored + time_step * A[i] - (time_step * F[i] - G[i]);
        if (owned_free[i])
          {
            free_sum += std::abs(r);
            // h in H([Theta - e, Theta + e]) with e the round-off of Theta: at a
            // kink a temperature 1e-18 below the transition is on the plateau.
            const double e =
              round_off_factor * std::numeric_limits<double>::epsilon() * (1 + std::abs(theta[i]));
            const std::pair<double, double> range{
              owned_node_law(i).enthalpy_range(theta[i] - e).first,
              owned_node_law(i).enthalpy_range(theta[i] + e).second};
            const double slack = round_off_factor * std::numeric_limits<double>::epsilon() *
                                 (1 + std::abs(range.first) + std::abs(range.second));
            const bool outside = (h[i] < range.first - slack || h[i] > range.second + slack);
            if (outside && verbosity >= 2)
              std::cout << "      node " << dof << ": h = " << h[i] << " outside [" << range.first
                        << ", " << range.second << "] of Theta = " << theta[i] << std::endl;
            inconsistent_nodes += outside;
          }
        else
          scale += std::abs(r);
        scale += std::abs(stored) + std::abs(G[i]) + time_step * (std::abs(F[i]) + A_abs[i]);
      }
    free_sum     = Utilities::MPI::sum(free_sum, mpi_communicator);
    scale        = Utilities::MPI::sum(scale, mpi_communicator);
    inconsistent = Utilities::MPI::sum(inconsistent_nodes, mpi_communicator);
    return scale > 0 ? std::abs(free_sum) / scale : 0.;
  }



  // The size of enthalpy changes that matter: the largest latent heat or, without
  // transitions, the sensible heat of a unit temperature change.
  template <int dim>
  double ThermalField<dim>::enthalpy_change_scale() const
  {
    double enthalpy_scale = 0;
    for (const auto &l : laws)
      {
        enthalpy_scale = std::max(enthalpy_scale, l.max_heat_capacity());
        for (unsigned int j = 0; j < l.n_transitions(); ++j)
          enthalpy_scale = std::max(enthalpy_scale, l.latent_heat(j));
      }
    return enthalpy_scale;
  }



  // A target whose every free node lies on the piece it was computed with
  // solves the step exactly: take it. (Near convergence the decrease of E can
  // be below its round-off, so the line search must not judge it.) Collective.
  template <int dim>
  bool ThermalField<dim>::newton_target_consistent(const Vector &h_new) const
  {
    // The per-node loops below run over the owned entries directly (see
    // index_local_entries()).
    const double *hn = entries(h_new), *state = entries(phase_state);
    const char   *free               = owned_free.data();
    unsigned int  local_inconsistent = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      if (free[i])
        local_inconsistent +=
          (owned_node_law(i).state_of_enthalpy(hn[i]) != static_cast<unsigned int>(state[i]));
    return Utilities::MPI::sum(local_inconsistent, mpi_communicator) == 0;
  }



  // A Newton step that moves no enthalpy beyond round-off ends the iteration
  // even if states flip: that happens where the solution sits exactly on a
  // kink of H (e.g. an equilibrium at a transition temperature), where
  // neighbouring pieces give the same (Theta, h). Collective.
  template <int dim>
  bool ThermalField<dim>::newton_step_negligible(const Vector &h_new,
                                                 const double  enthalpy_scale) const
  {
    const double *h = entries(enthalpy), *hn = entries(h_new);
    const char   *free       = owned_free.data();
    double        local_step = 0, local_size = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      if (free[i])
        {
          local_step = std::max(local_step, std::abs(hn[i] - h[i]));
          local_size = std::max(local_size, std::abs(hn[i]));
        }
    return Utilities::MPI::max(local_step, mpi_communicator) <=
           step_prm.active_set_step_tolerance *
             (Utilities::MPI::max(local_size, mpi_communicator) + enthalpy_scale);
  }



  // The Armijo line search on E along the Newton step h_new - h: the step
  // length alpha, halved from 1 until E decreases sufficiently (or down to
  // 'Line search min step'). E is quadratic in g apart from the Psi terms, so
  // one pass gives its slope and quadratic coefficients; each trial length
  // only sums the Psi terms. Collective.
  template <int dim>
  double ThermalField<dim>::line_search_step(const Vector &h_new, const Vector &z) const
  {
    const double *h = entries(enthalpy), *zz = entries(z);
    const double *hn = entries(h_new), *theta = entries(temperature), *m = entries(lumped_mass);
    const char   *free = owned_free.data();
    // Slope and the two quadratic coefficients of E along h_new - h.
    double local[3] = {0, 0, 0}; // grad E . d,  d . z,  d . K^{-1} d
    for (unsigned int i = 0; i < n_owned; ++i)
      if (free[i])
        {
          const double d = m[i] * (hn[i] - h[i]);
          local[0] += d * (zz[i] + owned_node_law(i).temperature(h[i]));
          local[1] += d * zz[i];
          local[2] += d * (-zz[i] - theta[i]);
        }
    double global[3];
    Utilities::MPI::sum(ArrayView<const double>(local, 3),
                        mpi_communicator,
                        ArrayView<double>(global, 3));
    // Armijo: E(alpha) - E(0) <= sigma alpha slope, up to the round-off of
    // the terms that make up the difference.
    const double round_off    = round_off_factor * std::numeric_limits<double>::epsilon();
    const auto   armijo_holds = [&](const double a) {
      double psi[2] = {0, 0}; // sum m (Psi(h + a d) - Psi(h)), sum m (|..| + |..|)
      for (unsigned int i = 0; i < n_owned; ++i)
        if (free[i])
          {
            const EnthalpyLaw &l      = owned_node_law(i);
            const double       before = l.beta_primitive(h[i]);
            const double       after  = l.beta_primitive(h[i] + a * (hn[i] - h[i]));
            psi[0] += m[i] * (after - before);
            psi[1] += m[i] * (std::abs(after) + std::abs(before));
          }
      double sums[2];
      Utilities::MPI::sum(ArrayView<const double>(psi, 2),
                          mpi_communicator,
                          ArrayView<double>(sums, 2));
      const double linear = a * global[1], quadratic = 0.5 * a * a * global[2];
      return linear + quadratic + sums[0] <=
             step_prm.line_search_sufficient_decrease * a * global[0] +
               round_off * (sums[1] + std::abs(linear) + std::abs(quadratic));
    };
    double alpha = 1;
    while (alpha > step_prm.line_search_min_step && !armijo_holds(alpha))
      alpha *= 0.5;
    return alpha;
  }



  // Take the (damped) step, h <- h + alpha (h_new - h), z <- (1 - alpha) z -
  // alpha Theta_new, and move every node to the piece of its graph that holds
  // its new enthalpy (a prescribed node: its temperature). Returns how many
  // free nodes changed state. Collective.
  template <int dim>
  unsigned int
  ThermalField<dim>::take_step_and_update_states(const Vector &h_new, Vector &z, const double alpha)
  {
    double       *h = entries(enthalpy), *zz = entries(z), *state = entries(phase_state);
    const double *hn = entries(h_new), *theta = entries(temperature);
    const char   *free          = owned_free.data();
    unsigned int  local_changes = 0;
    for (unsigned int i = 0; i < n_owned; ++i)
      {
        zz[i]                    = (1 - alpha) * zz[i] - alpha * theta[i];
        h[i]                     = h[i] + alpha * (hn[i] - h[i]);
        const unsigned int s_new = free[i] ? owned_node_law(i).state_of_enthalpy(h[i]) :
                                             owned_node_law(i).state_of_temperature(theta[i]);
        if (s_new != static_cast<unsigned int>(state[i]))
          {
            state[i] = s_new;
            // Prescribed nodes follow their data; they are not unknowns.
            local_changes += free[i];
          }
      }
    to_ghosted(enthalpy, enthalpy_ghosted);
    to_ghosted(phase_state, phase_state_ghosted);
    return Utilities::MPI::sum(local_changes, mpi_communicator);
  }



  // The active-set iteration with its globalisation.
  //
  // With g = M h on the free nodes, K = tau A restricted to them and c collecting
  // h^old, the heat load and the Dirichlet data, the step is the optimality
  // condition of the strongly convex, C^1, piecewise quadratic functional
  //     E(g) = 1/2 (g - c)^T K^{-1} (g - c) + sum_i m_i Psi_i(g_i / m_i),  Psi_i' = beta_i,
  // and the active-set iteration is exactly the semismooth Newton method for
  // grad E = 0: the phase states choose the generalized derivative of beta. Full
  // Newton steps can cycle (entering a plateau is a concave kink of beta), so
  // every step is checked by an Armijo line search on E. K^{-1} is never applied:
  // z = K^{-1}(g - c) equals -Theta after a full step and moves linearly along a
  // damped one, and K^{-1} (g_new - g) = -z - Theta_new. Where the full step is
  // accepted this is the plain active-set method; the line search only acts
  // when it would overshoot.
  //
  // Each iteration: solve with every node on its piece (solve_for_pieces), judge
  // the Newton target (newton_target_consistent, newton_step_negligible), damp
  // it where needed (line_search_step), take it and move the nodes to their new
  // pieces (take_step_and_update_states), and stop when none moved.
  template <int dim>
  bool ThermalField<dim>::active_set_iteration(EnthalpyStepReport &report,
                                               const unsigned int  max_iterations)
  {
    Vector       h_new(owned, mpi_communicator);
    Vector       z(owned, mpi_communicator);
    const double enthalpy_scale = enthalpy_change_scale();

    // While the set changes, the solves need only a loose tolerance (they
    // decide the next set, not the result): after the first iteration, CG
    // solves to 'CG tolerance while the enthalpy set changes' on the AMG
    // hierarchy it has, and the set it settles on is confirmed by a solve to
    // 'CG tolerance'. A set that recurs while the solves are loose switches
    // to tight solves (no cycling on inexact data).
    // The first solve is loose too where the warm start moved nodes to
    // another piece: that guess of a front reaching new nodes is often wrong
    // (the heat runs ahead while no node absorbs latent heat).
    const double loose_tolerance = step_prm.cg_enthalpy_set_tolerance;
    // (Decided from the system's size, not from the solver's last set-up:
    // a run resumed from a checkpoint has none yet and must take the same path.)
    // Later passes of a fixed-point coupling loop start from the last pass's set.
    const bool iterative = !linear_solver.direct_for(dof_handler.n_dofs());
    bool loose = first_pass_of_step && predicted_set_changed && loose_tolerance > 0 && iterative;
    std::vector<std::uint64_t> loose_sets;
    for (unsigned int it = 1; it <= max_iterations; ++it)
      {
        // The last allowed iteration is tight, so that it can end the step.
        loose                        = loose && it < max_iterations;
        report.plateau_nodes         = solve_for_pieces(h_new, loose ? loose_tolerance : 0.);
        report.active_set_iterations = it;

        const bool   target_consistent = newton_target_consistent(h_new);
        const bool   step_negligible   = it > 1 && newton_step_negligible(h_new, enthalpy_scale);
        const double alpha =
          (it > 1 && !target_consistent && !step_negligible) ? line_search_step(h_new, z) : 1.;
        const unsigned int n_changes = take_step_and_update_states(h_new, z, alpha);
        report.state_changes += n_changes;
        report.damped_steps += (alpha < 1);
        if (verbosity >= 1)
          pcout << "      active set " << it << ": " << report.plateau_nodes
                << " plateau nodes, step " << alpha << ", " << n_changes << " state changes"
                << std::endl;
        const bool was_loose = loose;
        if ((n_changes == 0 && alpha == 1) || step_negligible)
          {
            if (!was_loose)
              return true;
            loose = false; // confirm the set with a tight solve
            continue;
          }
        // The next solve is loose while the set is new. Once tight after the
        // first iteration (a recurring set, or a settled set that its
        // confirming solve moved), the iteration stays tight.
        if (loose_tolerance > 0 && iterative && (was_loose || it == 1))
          {
            const std::uint64_t set = Fingerprint::vector(phase_state);
            loose = std::find(loose_sets.begin(), loose_sets.end(), set) == loose_sets.end();
            loose_sets.push_back(set);
          }
      }
    return false;
  }



  // The enthalpy step with the conductances of the interfaces evaluated from
  // the state of the last iterate (gap and pressure of the contact step,
  // temperatures, phases). Where a conductance depends on the temperatures or
  // phases and the scheme is the fixed point, the step is repeated with h
  // re-evaluated until h settles (a secant iteration: radiation, k_gas(T),
  // the phase-aware contact), so that the step is implicit in h too; the
  // staggered scheme lags it (doc/interface_heat.md).
  template <int dim>
  EnthalpyStepReport ThermalField<dim>::solve()
  {
    update_conductances();
    EnthalpyStepReport report = solve_enthalpy_step();
    if (!iterate_conductances)
      return report;
    const double tolerance = prm.coupling.fixed_point_tolerance;
    for (unsigned int it = 1;; ++it)
      {
        const double change = update_conductances();
        if (change <= tolerance + 64 * std::numeric_limits<double>::epsilon())
          break;
        if (it == prm.coupling.max_fixed_point_iterations)
          throw std::runtime_error(
            "the conductances of the interfaces did not settle in 'Coupling/Max fixed-point "
            "iterations' = " +
            std::to_string(it) + " enthalpy steps at t = " + number(time) +
            " (last relative change of h: " + number(change) + ")");
        const EnthalpyStepReport again = solve_enthalpy_step();
        report.active_set_iterations += again.active_set_iterations;
        report.damped_steps += again.damped_steps;
        report.relaxation_iterations += again.relaxation_iterations;
        report.state_changes += again.state_changes;
        report.factorisations += again.factorisations;
        report.linear += again.linear;
        report.plateau_nodes      = again.plateau_nodes;
        report.energy_residual    = std::max(report.energy_residual, again.energy_residual);
        report.inconsistent_nodes = again.inconsistent_nodes;
        report.thermoelastic_heat = again.thermoelastic_heat;
        report.truncated_newton   = report.truncated_newton || again.truncated_newton;
      }
    return report;
  }



  template <int dim>
  EnthalpyStepReport ThermalField<dim>::solve_enthalpy_step()
  {
    EnthalpyStepReport report;
    n_factorisations = 0;
    assemble_conductivity_matrix();
    assemble_step_load();
    using EnthalpySolver = Parameters::EnthalpyStep::EnthalpySolver;
    const auto solver    = step_prm.enthalpy_solver;
    bool       converged = false;
    // The large-step mode of the active-set method: where the front crosses
    // many cells in one step the active-set iteration advances it about a
    // column of nodes per solve; the truncated Newton method does not
    // (doc/algorithms.md). A step that needs more than 'Truncated Newton
    // hand-over' solves is handed over, and so are the steps after it, until
    // one is solved in at most 'Active set hand-back' solves. The mode is
    // decided per step (begin_time_step()): every pass of a coupling loop
    // uses the method that solved the step's first pass.
    const unsigned int hand_over      = step_prm.truncated_newton_hand_over;
    const unsigned int max_iterations = step_prm.max_active_set_iterations;
    // (A later pass starts warm and is cheap: only the first judges the hand-back.)
    const bool first_pass = first_pass_of_step;
    // Another method continues a step: its solves add to the ones spent.
    const auto continue_with = [&](const auto &method) {
      const unsigned int spent = report.active_set_iterations;
      const bool         done  = method();
      report.active_set_iterations += spent;
      return done;
    };
    const auto truncated_newton = [&]() { return truncated_newton_iteration(report); };
    const auto active_set       = [&]() { return active_set_iteration(report, max_iterations); };
    // Should the truncated Newton method not converge where the mode chose
    // it: the active-set iteration with its full limit, before the relaxation;
    // the mode ends.
    const auto active_set_after_failure = [&]() {
      pcout << "   Enthalpy step: the truncated Newton method did not converge in 'Solver/Max "
               "active-set iterations' = "
            << max_iterations << " at t = " << time
            << "; the active-set iteration takes the step over" << std::endl;
      large_step_mode = step_in_large_step_mode = false;
      return continue_with(active_set);
    };
    if (solver == EnthalpySolver::active_set && hand_over > 0 && step_in_large_step_mode)
      {
        converged               = truncated_newton();
        report.truncated_newton = converged;
        if (!converged)
          converged = active_set_after_failure();
        else if (first_pass && report.active_set_iterations <= step_prm.active_set_hand_back)
          {
            large_step_mode = false;
            if (verbosity >= 1)
              pcout << "   Enthalpy step: " << report.active_set_iterations
                    << " truncated Newton solve(s) at t = " << time
                    << " ('Solver/Active set hand-back'); the next time step starts with the "
                       "active-set method"
                    << std::endl;
          }
      }
    else if (solver == EnthalpySolver::active_set)
      {
        const unsigned int limit =
          hand_over > 0 ? std::min(hand_over, max_iterations) : max_iterations;
        converged = active_set_iteration(report, limit);
        if (!converged)
          {
            if (limit < max_iterations)
              {
                if (verbosity >= 1)
                  pcout << "   Enthalpy step: " << limit << " active-set solves at t = " << time
                        << " ('Solver/Truncated Newton hand-over'); this step and the next "
                           "ones go to the truncated Newton method"
                        << std::endl;
              }
            else
              pcout << "   Enthalpy step: no convergence in 'Solver/Max active-set iterations' = "
                    << max_iterations << " at t = " << time
                    << "; switching to the truncated Newton method" << std::endl;
            converged               = continue_with(truncated_newton);
            report.truncated_newton = converged;
            if (hand_over > 0)
              large_step_mode = step_in_large_step_mode = true;
            // After a hand-over below the limit, the active-set iteration has
            // solves left.
            if (!converged && limit < max_iterations)
              converged = active_set_after_failure();
          }
      }
    else if (solver == EnthalpySolver::truncated_newton)
      {
        converged               = truncated_newton();
        report.truncated_newton = converged;
      }
    first_pass_of_step = false;
    if (solver == EnthalpySolver::relaxation)
      report.relaxation_iterations = relaxation_fallback();
    else if (!converged)
      {
        pcout << "   Enthalpy step: no convergence of the "
              << (solver == EnthalpySolver::truncated_newton ? "truncated Newton method" :
                                                               "active-set and truncated Newton "
                                                               "methods")
              << " in 'Solver/Max active-set iterations' = " << step_prm.max_active_set_iterations
              << " at t = " << time << "; switching to the relaxation fallback" << std::endl;
        report.relaxation_iterations = relaxation_fallback();
        unsigned int local_plateau   = 0;
        for (const auto dof : owned)
          local_plateau += EnthalpyLaw::is_plateau(static_cast<unsigned int>(phase_state[dof]));
        report.plateau_nodes = Utilities::MPI::sum(local_plateau, mpi_communicator);
      }
    interpolate_mortar_slave_enthalpies(); // (mortar.cc)
    report.energy_residual    = compute_energy_balance(report.inconsistent_nodes);
    report.factorisations     = n_factorisations;
    report.linear             = linear_solver.take_statistics();
    report.thermoelastic_heat = thermoelastic_heat();
    return report;
  }



  template void ThermalField<2>::assemble_system(const bool assemble_matrix);
  template void ThermalField<2>::assemble_conductivity_matrix();
  template void ThermalField<2>::assemble_step_load();
  template void ThermalField<2>::apply_conductivity(const Vector &theta, Vector &result) const;
  template void ThermalField<2>::to_columns(const Epetra_Vector &values,
                                            std::vector<double> &result) const;
  template void         ThermalField<2>::conductivity_times(Vector &result) const;
  template void         ThermalField<2>::conductivity_times(Vector &product,
                                                    Vector &absolute_product) const;
  template void         ThermalField<2>::to_ghosted(const Vector &values, Vector &ghosted) const;
  template unsigned int ThermalField<2>::solve_for_pieces(Vector &h_new, const double tolerance);
  template unsigned int ThermalField<2>::relaxation_fallback();
  template double       ThermalField<2>::compute_energy_balance(unsigned int &inconsistent) const;
  template double       ThermalField<2>::enthalpy_change_scale() const;
  template bool         ThermalField<2>::newton_target_consistent(const Vector &h_new) const;
  template bool         ThermalField<2>::newton_step_negligible(const Vector &h_new,
                                                        const double  enthalpy_scale) const;
  template double ThermalField<2>::line_search_step(const Vector &h_new, const Vector &z) const;
  template unsigned int
  ThermalField<2>::take_step_and_update_states(const Vector &h_new, Vector &z, const double alpha);
  template bool         ThermalField<2>::active_set_iteration(EnthalpyStepReport &report,
                                                      const unsigned int  max_iterations);
  template EnthalpyStepReport ThermalField<2>::solve();
  template EnthalpyStepReport ThermalField<2>::solve_enthalpy_step();
} // namespace ContactStefan
