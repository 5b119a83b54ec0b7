// CoupledBlock: the block correction of the fixed-point coupling (see the
// header and doc/coupling.md).
#include <deal.II/dofs/dof_handler.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparse_matrix.h>
#include <deal.II/lac/sparsity_pattern.h>

#include <contact-stefan/coupling/coupled_block.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Epetra_CrsMatrix.h>
#include <cholmod.h>


namespace ContactStefan
{
  template <int dim>
  CoupledBlock<dim>::CoupledBlock(const MechanicalField<dim> &mechanical,
                                  const ThermalField<dim>    &thermal,
                                  TimerOutput                &timer)
    : mechanical(mechanical)
    , thermal(thermal)
    , timer(timer)
  {}



  template <int dim>
  std::string CoupledBlock<dim>::not_applicable(const AllParameters        &prm,
                                                const MechanicalField<dim> &mechanical,
                                                const ThermalField<dim>    &thermal,
                                                const unsigned int          n_ranks)
  {
    if (prm.coupling.scheme != Parameters::Coupling::Scheme::fixed_point)
      return "staggered scheme";
    if (prm.coupling.acceleration != Parameters::Coupling::Acceleration::block)
      return "'Coupling/Fixed-point acceleration' = none";
    if (!(prm.thermal_stress_active() && prm.thermoelastic_heating_active()))
      return "one-way coupling (one pass is exact)";
    if (!mechanical.get_contact_groups().empty())
      return "contact conditions or tied interfaces (solved by the contact step's active set)";
    if (thermal.phase_change_present())
      return "phase change (the plateau set may change within a step)";
    // The block system has no row or column for the bodies' e_zz (its heating
    // and its thermal force): as an accelerator it would still converge, but
    // not in the two passes it promises.
    if (mechanical.out_of_plane_free())
      return "generalized plane strain (the block system has no e_zz)";
    if (prm.enthalpy_step.enthalpy_solver == Parameters::EnthalpyStep::EnthalpySolver::relaxation)
      return "the relaxation enthalpy solver (its matrix is not the enthalpy step's)";
    if (n_ranks != 1)
      return "more than one MPI rank (the block solve is serial)";
    return "";
  }



  template <int dim>
  std::uint64_t CoupledBlock<dim>::signature() const
  {
    return Fingerprint::combine(
      Fingerprint::combine(mechanical.get_matrix_signature(), thermal.get_matrix_signature()),
      Fingerprint::combine(Fingerprint::combine(thermal.mesh_generation(),
                                                mechanical.get_dof_handler().n_dofs()),
                           thermal.get_dof_handler().n_dofs()));
  }



  // CHOLMOD's workspace, the symmetric matrix's lower triangle and its factor.
  template <int dim>
  struct CoupledBlock<dim>::Cholmod
  {
    cholmod_common  common;
    cholmod_sparse *A = nullptr;
    cholmod_factor *L = nullptr;
    Cholmod()
    {
      cholmod_start(&common);
    }
    ~Cholmod()
    {
      if (L != nullptr)
        cholmod_free_factor(&L, &common);
      if (A != nullptr)
        cholmod_free_sparse(&A, &common);
      cholmod_finish(&common);
    }
    Cholmod(const Cholmod &)            = delete;
    Cholmod &operator=(const Cholmod &) = delete;
  };



  // The block matrix with its thermal rows multiplied by -1/Theta_0 is
  // [K, -B; -B^T, -S/Theta_0] for a constant Theta_0: symmetric, with a
  // positive definite and a negative definite diagonal block
  // (quasi-definite), so an LDL^T factorisation without pivoting exists for
  // any symmetric ordering (Vanderbei 1995) and is far cheaper than a general
  // LU. (Hanging-node constraints keep it symmetric: the condensed coupling
  // blocks stay each other's transposes.) False (nothing set up) where Theta_0
  // varies, the scaled matrix is not symmetric to round-off, or the pivots'
  // signs are not those of the two blocks.
  template <int dim>
  bool CoupledBlock<dim>::factorise_symmetric()
  {
    const auto &reference = thermal.get_absolute_reference();
    double      theta0    = 0;
    for (const auto &cell : reference)
      for (const double v : cell)
        {
          if (theta0 == 0)
            theta0 = v;
          if (v != theta0)
            return false;
        }
    if (!(theta0 > 0))
      return false;
    const auto n_u    = static_cast<PetscInt>(mechanical.get_dof_handler().n_dofs());
    const auto n      = static_cast<PetscInt>(row_start.size() - 1);
    thermal_row_scale = -1. / theta0;
    const auto scaled = [&](const PetscInt row, const PetscInt k) {
      return row < n_u ? values[k] : thermal_row_scale * values[k];
    };
    // Symmetry, entry by entry (each row's columns are sorted), and the lower
    // triangle by columns: column r holds row r's entries right of and on the
    // diagonal.
    // Round-off is judged against the largest scaled entry of the two rows
    // an entry and its mirror lie in. Every entry left of the diagonal must
    // be the mirror of one right of it (the factorisation reads the upper
    // ones only).
    std::vector<double> row_largest(n, 0.);
    for (PetscInt r = 0; r < n; ++r)
      for (PetscInt k = row_start[r]; k < row_start[r + 1]; ++k)
        row_largest[r] = std::max(row_largest[r], std::abs(scaled(r, k)));
    std::size_t upper = 0, left = 0, mirrored = 0;
    for (PetscInt r = 0; r < n; ++r)
      for (PetscInt k = row_start[r]; k < row_start[r + 1]; ++k)
        if (const PetscInt c = column_index[k]; c < r)
          ++left;
        else
          {
            ++upper;
            if (c == r)
              continue;
            const auto begin  = column_index.begin() + row_start[c];
            const auto end    = column_index.begin() + row_start[c + 1];
            const auto at     = std::lower_bound(begin, end, r);
            const bool paired = at != end && *at == r;
            mirrored += paired;
            const double mirror = paired ? scaled(c, at - column_index.begin()) : 0.;
            if (std::abs(scaled(r, k) - mirror) >
                1e-12 * (std::abs(scaled(r, k)) + std::abs(mirror)) +
                  1e-14 * (row_largest[r] + row_largest[c]))
              return false;
          }
    if (mirrored != left)
      return false;
    const std::size_t lower = upper;
    cholmod                = std::make_shared<Cholmod>();
    cholmod_common &common = cholmod->common;
    cholmod->A = cholmod_allocate_sparse(n, n, lower, true, true, -1, CHOLMOD_REAL, &common);
    if (cholmod->A == nullptr)
      throw std::runtime_error("the block correction of the coupling: CHOLMOD could not allocate "
                               "the block matrix (out of memory?)");
    auto       *Ap       = static_cast<int *>(cholmod->A->p);
    auto       *Ai       = static_cast<int *>(cholmod->A->i);
    auto       *Ax       = static_cast<double *>(cholmod->A->x);
    std::size_t position = 0;
    for (PetscInt r = 0; r < n; ++r)
      {
        Ap[r] = static_cast<int>(position);
        for (PetscInt k = row_start[r]; k < row_start[r + 1]; ++k)
          if (column_index[k] >= r)
            {
              Ai[position] = static_cast<int>(column_index[k]);
              Ax[position] = scaled(r, k);
              ++position;
            }
      }
    Ap[n]                     = static_cast<int>(position);
    common.supernodal         = CHOLMOD_SIMPLICIAL;
    common.final_ll           = false;
    common.nmethods           = 1;
    common.method[0].ordering = CHOLMOD_METIS;
    cholmod->L                = cholmod_analyze(cholmod->A, &common);
    if (cholmod->L == nullptr)
      {
        common.nmethods = 0;
        cholmod->L      = cholmod_analyze(cholmod->A, &common);
      }
    if (cholmod->L == nullptr || !cholmod_factorize(cholmod->A, cholmod->L, &common) ||
        common.status != CHOLMOD_OK)
      {
        cholmod.reset();
        return false;
      }
    // (The solves need the factor only; the residual check reads the
    // compressed rows.)
    cholmod_free_sparse(&cholmod->A, &common);
    // The inertia: n_u positive pivots (K) and n_T negative ones (-S/Theta_0).
    const auto *Lp       = static_cast<const int *>(cholmod->L->p);
    const auto *Lx       = static_cast<const double *>(cholmod->L->x);
    PetscInt    positive = 0, negative = 0;
    for (PetscInt j = 0; j < n; ++j)
      {
        positive += Lx[Lp[j]] > 0;
        negative += Lx[Lp[j]] < 0;
      }
    if (positive != n_u || negative != n - n_u)
      {
        cholmod.reset();
        return false;
      }
    return true;
  }



  template <int dim>
  void CoupledBlock<dim>::free_factorisation()
  {
    cholmod.reset();
    if (petsc_solver != nullptr)
      KSPDestroy(&petsc_solver);
    if (petsc_matrix != nullptr)
      MatDestroy(&petsc_matrix);
    petsc_solver       = nullptr;
    petsc_matrix       = nullptr;
    have_factorisation = false;
  }



  namespace
  {
    // A PETSc call that failed: one line naming what failed.
    void check_petsc(const PetscErrorCode code, const char *what)
    {
      if (code != 0)
        throw std::runtime_error(std::string("the block correction of the coupling: PETSc "
                                             "failed to ") +
                                 what + " (error " + std::to_string(code) +
                                 "); set 'Coupling/Fixed-point acceleration' = none");
    }
  } // namespace



  // The block matrix [K, -C_u^T B C_T; C_T^T G C_u, S]: K and S are the two
  // fields' system matrices as their last solves used them (constraints
  // condensed, a constrained row its diagonal alone); the coupling blocks are
  // assembled from the cell operators B_K with the constraints of the rows'
  // field on the rows and of the columns' field on the columns, which is what
  // the loads of the two fields do with a change of the other field.
  template <int dim>
  void CoupledBlock<dim>::build()
  {
    TimerOutput::Scope               t(timer, "coupling: block factorise");
    const DoFHandler<dim>           &u_dofs = mechanical.get_dof_handler();
    const DoFHandler<dim>           &T_dofs = thermal.get_dof_handler();
    const auto                       n_u = u_dofs.n_dofs(), n_T = T_dofs.n_dofs();
    const AffineConstraints<double> &u_constraints = mechanical.get_constraints();
    const AffineConstraints<double> &T_constraints = thermal.get_constraints();
    const auto                      &reference     = thermal.get_absolute_reference();

    // Each cell's DoFs in both fields.
    std::vector<types::global_dof_index> dofs_u, dofs_T(T_dofs.get_fe().n_dofs_per_cell());
    const auto                           for_each_cell = [&](const auto &visit) {
      for (const auto &cell : u_dofs.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            dofs_u.resize(cell->get_fe().n_dofs_per_cell());
            cell->get_dof_indices(dofs_u);
            const typename DoFHandler<dim>::active_cell_iterator T_cell(&u_dofs.get_triangulation(),
                                                                        cell->level(),
                                                                        cell->index(),
                                                                        &T_dofs);
            T_cell->get_dof_indices(dofs_T);
            visit(cell->active_cell_index());
          }
    };

    // The coupling blocks, assembled as deal.II does with two constraint sets.
    DynamicSparsityPattern uT(n_u, n_T), Tu(n_T, n_u);
    for_each_cell([&](const unsigned int) {
      u_constraints.add_entries_local_to_global(dofs_u, T_constraints, dofs_T, uT, false);
      T_constraints.add_entries_local_to_global(dofs_T, u_constraints, dofs_u, Tu, false);
    });
    SparsityPattern      uT_pattern, Tu_pattern;
    SparseMatrix<double> uT_matrix, Tu_matrix;
    uT_pattern.copy_from(uT);
    Tu_pattern.copy_from(Tu);
    uT_matrix.reinit(uT_pattern);
    Tu_matrix.reinit(Tu_pattern);
    FullMatrix<double> minus_B, G;
    for_each_cell([&](const unsigned int c) {
      const auto &B = mechanical.thermal_operator(c);
      minus_B.reinit(B.size(), 4);
      G.reinit(4, B.size());
      for (unsigned int i = 0; i < B.size(); ++i)
        for (unsigned int v = 0; v < 4; ++v)
          {
            minus_B(i, v) = -B[i][v];
            G(v, i)       = reference[c][v] * B[i][v];
          }
      u_constraints.distribute_local_to_global(minus_B, dofs_u, T_constraints, dofs_T, uT_matrix);
      T_constraints.distribute_local_to_global(G, dofs_T, u_constraints, dofs_u, Tu_matrix);
    });

    // The whole matrix in compressed rows, each row sorted by column.
    row_start.assign(1, 0);
    column_index.clear();
    values.clear();
    std::vector<std::pair<PetscInt, PetscScalar>> row_entries;
    const auto append_rows = [&](const TrilinosWrappers::SparseMatrix &own,
                                 const types::global_dof_index         own_offset,
                                 const SparseMatrix<double>           &coupling,
                                 const types::global_dof_index         coupling_offset) {
      const Epetra_CrsMatrix &A = own.trilinos_matrix();
      for (int r = 0; r < A.NumMyRows(); ++r)
        {
          int     n;
          double *a;
          int    *columns;
          A.ExtractMyRowView(r, n, a, columns);
          row_entries.clear();
          for (int k = 0; k < n; ++k)
            row_entries.emplace_back(own_offset + A.ColMap().GID(columns[k]), a[k]);
          const auto row = static_cast<types::global_dof_index>(A.RowMap().GID(r));
          for (auto entry = coupling.begin(row); entry != coupling.end(row); ++entry)
            row_entries.emplace_back(coupling_offset + entry->column(), entry->value());
          std::sort(row_entries.begin(), row_entries.end());
          for (const auto &[column, value] : row_entries)
            {
              column_index.push_back(column);
              values.push_back(value);
            }
          row_start.push_back(column_index.size());
        }
    };
    append_rows(mechanical.get_system_matrix(), 0, uT_matrix, n_u);
    append_rows(thermal.get_system_matrix(), n_u, Tu_matrix, 0);
    AssertThrow(row_start.size() == n_u + n_T + 1, ExcInternalError());

    // Elsewhere: LU with a nested-dissection ordering (2D meshes: far less
    // fill than minimum degree), without pivoting. For a constant Theta_0 on a mesh
    // without hanging nodes the matrix with its thermal rows divided by
    // Theta_0 has a positive definite symmetric part (K and S are, and the two
    // coupling blocks are each other's negative transpose), so no pivot
    // vanishes; elsewhere that is not proven (it held on every case tried,
    // Theta_0 = 1 + 1000 x^4 included), and a zero pivot or a non-finite
    // correction stops the run in correct() with a message naming the remedy.
    free_factorisation();
    factor_accurate = false;
    if (factorise_symmetric())
      {
        ++factorisations;
        ++symmetric_factorisations;
        have_factorisation = true;
        built_signature    = signature();
        return;
      }
    const auto n = static_cast<PetscInt>(n_u + n_T);
    check_petsc(
      MatCreateSeqAIJWithArrays(
        PETSC_COMM_SELF, n, n, row_start.data(), column_index.data(), values.data(), &petsc_matrix),
      "create the block matrix");
    check_petsc(KSPCreate(PETSC_COMM_SELF, &petsc_solver), "create a solver");
    check_petsc(KSPSetOperators(petsc_solver, petsc_matrix, petsc_matrix), "set the matrix");
    check_petsc(KSPSetType(petsc_solver, KSPPREONLY), "select a direct solve");
    PC preconditioner;
    check_petsc(KSPGetPC(petsc_solver, &preconditioner), "get the factorisation");
    check_petsc(PCSetType(preconditioner, PCLU), "select LU");
    check_petsc(PCFactorSetMatSolverType(preconditioner, MATSOLVERPETSC), "select PETSc's LU");
    check_petsc(PCFactorSetMatOrderingType(preconditioner, MATORDERINGND),
                "select the nested-dissection ordering");
    check_petsc(KSPSetUp(petsc_solver), "factorise the block matrix");
    ++factorisations;
    have_factorisation = true;
    built_signature    = signature();
  }



  template <int dim>
  void CoupledBlock<dim>::correct(const CellVertexValues &theta_in,
                                  const CellVertexValues &theta_out,
                                  const Vector           &u,
                                  const Vector           &theta,
                                  Vector                 &u_star,
                                  Vector                 &theta_star)
  {
    if (!have_factorisation || signature() != built_signature)
      build();
    TimerOutput::Scope t(timer, "coupling: block solve");
    ++corrections;
    Vector change;
    mechanical.thermal_load_change(theta_out, theta_in, change);
    const auto               n_u = change.size(), n_T = theta.size();
    std::vector<PetscScalar> b(n_u + n_T, 0.), x(n_u + n_T);
    const double *const      load = change.trilinos_vector()[0];
    std::copy(load, load + n_u, b.begin());
    if (cholmod)
      {
        // (The thermal rows of b are zero: nothing to scale.)
        cholmod_common &common = cholmod->common;
        cholmod_dense  *B = cholmod_allocate_dense(b.size(), 1, b.size(), CHOLMOD_REAL, &common);
        if (B == nullptr)
          throw std::runtime_error("the block correction of the coupling: CHOLMOD could not "
                                   "allocate a vector (out of memory?)");
        std::copy(b.begin(), b.end(), static_cast<double *>(B->x));
        cholmod_dense *X = cholmod_solve(CHOLMOD_A, cholmod->L, B, &common);
        cholmod_free_dense(&B, &common);
        if (X == nullptr)
          throw std::runtime_error("the block correction of the coupling: CHOLMOD's solve failed");
        std::copy(static_cast<double *>(X->x), static_cast<double *>(X->x) + x.size(), x.begin());
        cholmod_free_dense(&X, &common);
        // No pivoting: LDL^T of a quasi-definite matrix exists for any
        // ordering but its stability depends on how the blocks compare. The
        // backward error |b - A x| / (|A| |x| + |b|) (max norms, on the
        // unscaled compressed rows) is checked, and one step of iterative
        // refinement taken where it exceeds 1e-12; once a solve with this
        // factor was at round-off, later ones are not checked. A correction
        // that stays inaccurate costs fixed-point passes, not accuracy: the
        // fixed-point test decides the step.
        std::vector<double> residual(b.size());
        double              matrix_norm    = 0;
        const auto          backward_error = [&]() {
          double r_max = 0, x_max = 0, b_max = 0;
          matrix_norm = 0;
          for (std::size_t i = 0; i + 1 < row_start.size(); ++i)
            {
              double sum = b[i], row = 0;
              for (PetscInt k = row_start[i]; k < row_start[i + 1]; ++k)
                {
                  sum -= values[k] * x[column_index[k]];
                  row += std::abs(values[k]);
                }
              residual[i] = sum;
              r_max       = std::max(r_max, std::abs(sum));
              x_max       = std::max(x_max, std::abs(x[i]));
              b_max       = std::max(b_max, std::abs(b[i]));
              matrix_norm = std::max(matrix_norm, row);
            }
          const double scale = matrix_norm * x_max + b_max;
          return scale > 0 ? r_max / scale : 0.;
        };
        const bool refine = !factor_accurate && backward_error() > 1e-12;
        factor_accurate   = !refine;
        if (refine)
          {
            cholmod_dense *R = cholmod_allocate_dense(b.size(), 1, b.size(), CHOLMOD_REAL, &common);
            if (R == nullptr)
              throw std::runtime_error("the block correction of the coupling: CHOLMOD could "
                                       "not allocate a vector (out of memory?)");
            auto *r = static_cast<double *>(R->x);
            for (std::size_t i = 0; i < b.size(); ++i)
              r[i] = i < n_u ? residual[i] : thermal_row_scale * residual[i];
            cholmod_dense *D = cholmod_solve(CHOLMOD_A, cholmod->L, R, &common);
            cholmod_free_dense(&R, &common);
            if (D == nullptr)
              throw std::runtime_error(
                "the block correction of the coupling: CHOLMOD's solve failed");
            for (std::size_t i = 0; i < x.size(); ++i)
              x[i] += static_cast<double *>(D->x)[i];
            cholmod_free_dense(&D, &common);
          }
        if (!std::all_of(x.begin(), x.end(), [](const double v) { return std::isfinite(v); }))
          throw std::runtime_error("the block correction of the coupling failed (a non-finite "
                                   "correction); set 'Coupling/Fixed-point acceleration' = none");
      }
    else
      {
        Vec petsc_b, petsc_x;
        check_petsc(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, b.size(), b.data(), &petsc_b),
                    "wrap the right-hand side");
        check_petsc(VecCreateSeqWithArray(PETSC_COMM_SELF, 1, x.size(), x.data(), &petsc_x),
                    "wrap the solution");
        const PetscErrorCode code = KSPSolve(petsc_solver, petsc_b, petsc_x);
        VecDestroy(&petsc_b);
        VecDestroy(&petsc_x);
        check_petsc(code, "solve with the block matrix");
        KSPConvergedReason reason;
        check_petsc(KSPGetConvergedReason(petsc_solver, &reason), "report the solve");
        if (reason < 0 ||
            !std::all_of(x.begin(), x.end(), [](const double v) { return std::isfinite(v); }))
          throw std::runtime_error("the block correction of the coupling failed (a zero pivot or a "
                                   "non-finite correction; PETSc reason " +
                                   std::to_string(static_cast<int>(reason)) +
                                   "); set 'Coupling/Fixed-point acceleration' = none");
      }

    // (u, Theta) + correction; the constrained entries from their masters and
    // prescribed values (u and Theta satisfy the constraints already, so this
    // adds the homogeneous part of the correction there).
    u_star.reinit(mechanical.get_dof_handler().locally_owned_dofs(), u.get_mpi_communicator());
    theta_star.reinit(thermal.get_dof_handler().locally_owned_dofs(), theta.get_mpi_communicator());
    u_star           = u;
    theta_star       = theta;
    double *const us = u_star.trilinos_vector()[0];
    double *const ts = theta_star.trilinos_vector()[0];
    for (types::global_dof_index i = 0; i < n_u; ++i)
      us[i] += x[i];
    for (types::global_dof_index i = 0; i < n_T; ++i)
      ts[i] += x[n_u + i];
    mechanical.get_constraints().distribute(u_star);
    thermal.get_constraints().distribute(theta_star);
  }



  template class CoupledBlock<2>;
} // namespace ContactStefan
