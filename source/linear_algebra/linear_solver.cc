#include <deal.II/lac/solver_cg.h>

#include <contact-stefan/linear_algebra/linear_solver.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <Amesos.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>
#include <cholmod.h>
#include <ml_MultiLevelPreconditioner.h>

namespace ContactStefan
{
  using LinearSolverType = Parameters::LinearSolvers::LinearSolverType;

  // SuiteSparse's CHOLMOD: the matrix (lower triangle, by columns), its factor
  // and the library's workspace.
  struct LinearSolver::Cholmod
  {
    cholmod_common  common;
    cholmod_sparse *A = nullptr;
    cholmod_factor *L = nullptr;
    // Where each stored entry of the matrix's rows (in their storage order)
    // goes in A's values; -1: not in the lower triangle.
    std::vector<int> position_of_entry;
    // The whole symmetric pattern by rows: row r's entries are
    // [row_start[r], row_start[r+1]) of row_column (their columns) and
    // row_position (where their values are in A), the diagonal included once.
    std::vector<int> row_start, row_column, row_position;
    // The position of each unknown in the factor's fill-reducing order.
    std::vector<int> factor_index;
    // A factor with the values of A it factors (empty: not known) and whether
    // it was modified row by row and has not yet passed a solve's backward
    // error check.
    struct Factor
    {
      cholmod_factor     *L = nullptr;
      std::vector<double> values;
      bool                unchecked = false;
    };
    std::vector<double> values;
    bool                unchecked = false;
    // The key of L's matrix values (0: none), and earlier factors of the same
    // symbolic analysis with their keys, the most recently used first.
    std::uint64_t                                   key = 0;
    std::vector<std::pair<std::uint64_t, Factor>>   kept;
    // CHOLMOD's flop count of one numeric factorisation (from the analysis),
    // whether the ordering is nested dissection, and the flops of the
    // factorisations on this analysis that were too expensive as row
    // modifications (Solver/Reordering cost).
    double factorisation_flops = 0;
    bool   nested_dissection   = false;
    double rejected_flops      = 0;
    // Work space of the row modifications: a column of pattern and one of
    // values (n x 1 each), a mark per unknown.
    cholmod_sparse  *row_pattern = nullptr, *row_values = nullptr;
    std::vector<std::uint64_t> mark;
    std::uint64_t              stamp = 0;
    Cholmod()
    {
      cholmod_start(&common);
    }
    ~Cholmod()
    {
      if (L != nullptr)
        cholmod_free_factor(&L, &common);
      for (auto &entry : kept)
        cholmod_free_factor(&entry.second.L, &common);
      if (A != nullptr)
        cholmod_free_sparse(&A, &common);
      if (row_pattern != nullptr)
        cholmod_free_sparse(&row_pattern, &common);
      if (row_values != nullptr)
        cholmod_free_sparse(&row_values, &common);
      cholmod_finish(&common);
    }
    Cholmod(const Cholmod &)            = delete;
    Cholmod &operator=(const Cholmod &) = delete;

    // The ordering and the symbolic factor of A's pattern: CHOLMOD's choice
    // (AMD on our matrices), or nested dissection by METIS.
    void analyse(const bool nested, const std::string &name)
    {
      for (auto &entry : kept)
        cholmod_free_factor(&entry.second.L, &common);
      kept.clear();
      if (L != nullptr)
        cholmod_free_factor(&L, &common);
      values.clear();
      key       = 0;
      unchecked = false;
      // Simplicial, not supernodal: the supernodal factorisation calls the
      // BLAS, and with Debian's reference BLAS it took 2.7x longer on the
      // Stefan strip (16 441 unknowns); the row modifications need it too.
      common.supernodal = CHOLMOD_SIMPLICIAL;
      common.nmethods   = nested ? 1 : 0;
      if (nested)
        common.method[0].ordering = CHOLMOD_METIS;
      L = cholmod_analyze(A, &common);
      if (L == nullptr && nested)
        {
          // (A CHOLMOD without METIS: its own choice again.)
          common.nmethods = 0;
          L               = cholmod_analyze(A, &common);
        }
      if (L == nullptr)
        throw std::runtime_error("cholmod could not analyse the " + name + " matrix");
      nested_dissection   = nested;
      factorisation_flops = common.fl;
      rejected_flops      = 0;
      const int   n       = static_cast<int>(A->ncol);
      const auto *perm    = static_cast<const int *>(L->Perm);
      factor_index.resize(n);
      for (int i = 0; i < n; ++i)
        factor_index[perm[i]] = i;
    }

    std::size_t n_values() const
    {
      return static_cast<std::size_t>(static_cast<const int *>(A->p)[A->ncol]);
    }

    // The rows (unknowns) whose row and column must be replaced to turn the
    // matrix with values `old` into A: every row whose diagonal changed, and
    // for each other changed entry (i, j) one of i and j (the one with more
    // changed entries). A changed entry of a row that becomes a constraint
    // (its row and column cleared) is covered by that row alone.
    std::vector<int> rows_to_replace(const std::vector<double> &old)
    {
      const int     n    = static_cast<int>(A->ncol);
      const int    *Ap   = static_cast<const int *>(A->p);
      const int    *Ai   = static_cast<const int *>(A->i);
      const double *now  = static_cast<const double *>(A->x);
      std::vector<int>                 changed(n, 0);
      std::vector<char>                replaced(n, 0);
      std::vector<std::pair<int, int>> off_diagonal;
      for (int c = 0; c < n; ++c)
        for (int p = Ap[c]; p < Ap[c + 1]; ++p)
          if (now[p] != old[p])
            {
              if (Ai[p] == c)
                replaced[c] = 1;
              else
                off_diagonal.emplace_back(Ai[p], c);
              ++changed[Ai[p]];
              ++changed[c];
            }
      for (const auto &[r, c] : off_diagonal)
        if (!replaced[r] && !replaced[c])
          replaced[changed[r] >= changed[c] ? r : c] = 1;
      std::vector<int> rows;
      for (int r = 0; r < n; ++r)
        if (replaced[r])
          rows.push_back(r);
      return rows;
    }

    // Estimated flops of replacing these rows in factor F (a deletion and an
    // addition each, each a rank-one update of the columns on the row's path
    // to the root of the elimination tree, about 4 flops per entry), counted
    // only up to `budget`.
    double replacement_work(const cholmod_factor *F, const std::vector<int> &rows, const double budget) const
    {
      const int *Lp  = static_cast<const int *>(F->p);
      const int *Li  = static_cast<const int *>(F->i);
      const int *Lnz = static_cast<const int *>(F->nz);
      double     work = 0;
      for (const int r : rows)
        for (int j = factor_index[r]; j != -1 && work <= budget;
             j = Lnz[j] > 1 ? Li[Lp[j] + 1] : -1)
          work += 8. * Lnz[j];
      return work;
    }

    // Replace the rows in factor F (which factors the values the rows were
    // found against) by those of A: delete them all, then add them back one by
    // one with the entries of A towards the rows already present. Every
    // intermediate matrix is a principal submatrix of A or of the old matrix
    // bordered by the identity, so positive definite when they are. False if
    // CHOLMOD failed or a pivot is not positive (F must then be factorised afresh).
    bool replace_rows(cholmod_factor *F, const std::vector<int> &rows)
    {
      const int     n   = static_cast<int>(A->ncol);
      const double *now = static_cast<const double *>(A->x);
      if (row_pattern == nullptr)
        {
          row_pattern = cholmod_allocate_sparse(n, 1, n, false, true, 0, CHOLMOD_PATTERN, &common);
          row_values  = cholmod_allocate_sparse(n, 1, n, false, true, 0, CHOLMOD_REAL, &common);
          if (row_pattern == nullptr || row_values == nullptr)
            return false;
          mark.assign(n, 0);
        }
      auto *pattern_start = static_cast<int *>(row_pattern->p);
      auto *pattern_index = static_cast<int *>(row_pattern->i);
      auto *values_start  = static_cast<int *>(row_values->p);
      auto *values_index  = static_cast<int *>(row_values->i);
      auto *values_value  = static_cast<double *>(row_values->x);
      pattern_start[0] = values_start[0] = 0;
      std::vector<char> pending(n, 0);
      for (const int r : rows)
        pending[r] = 1;
      for (const int r : rows)
        {
          // Row k of L is the union of the paths from the row's entries
          // left of the diagonal towards k in the elimination tree (the
          // parent of j: the first row below the diagonal in column j).
          const int  k   = factor_index[r];
          const int *Lp  = static_cast<const int *>(F->p);
          const int *Li  = static_cast<const int *>(F->i);
          const int *Lnz = static_cast<const int *>(F->nz);
          int        count = 0;
          ++stamp;
          for (int e = row_start[r]; e < row_start[r + 1]; ++e)
            for (int i = factor_index[row_column[e]]; i != -1 && i < k && mark[i] != stamp;
                 i = Lnz[i] > 1 ? Li[Lp[i] + 1] : -1)
              {
                mark[i]                = stamp;
                pattern_index[count++] = i;
              }
          pattern_start[1] = count;
          if (!cholmod_rowdel(k, row_pattern, F, &common))
            return false;
        }
      for (const int r : rows)
        {
          int count = 0;
          for (int e = row_start[r]; e < row_start[r + 1]; ++e)
            if (const int c = row_column[e]; c == r || !pending[c])
              {
                values_index[count] = factor_index[c];
                values_value[count] = now[row_position[e]];
                ++count;
              }
          values_start[1] = count;
          pending[r]      = 0;
          if (!cholmod_rowadd(factor_index[r], row_values, F, &common))
            return false;
        }
      const int    *Lp = static_cast<const int *>(F->p);
      const double *Lx = static_cast<const double *>(F->x);
      for (int j = 0; j < n; ++j)
        if (!(Lx[Lp[j]] > 0))
          return false;
      return true;
    }
  };



  std::string LinearSolver::direct_type() const
  {
    if (prm.direct_solver_type != "automatic")
      return prm.direct_solver_type;
    return (matrix != nullptr && matrix->trilinos_matrix().Comm().NumProc() == 1) ? "cholmod" :
                                                                                    "Amesos_Klu";
  }



  void LinearSolver::cholmod_factorise(const bool analyse)
  {
    const Epetra_CrsMatrix &M = matrix->trilinos_matrix();
    const int               n = M.NumMyRows();
    AssertThrow(M.Comm().NumProc() == 1 && M.RowMap().MinMyGID() == 0,
                ExcMessage("the cholmod direct solver runs on one MPI rank only"));
    if (analyse)
      {
        cholmod = std::make_shared<Cholmod>();
        // Column r of the lower triangle is the upper part of row r (the
        // matrix is symmetric).
        std::size_t nnz = 0;
        for (int r = 0; r < n; ++r)
          {
            int     length;
            double *values;
            int    *columns;
            M.ExtractMyRowView(r, length, values, columns);
            for (int k = 0; k < length; ++k)
              nnz += (M.ColMap().GID(columns[k]) >= r);
          }
        cholmod->A =
          cholmod_allocate_sparse(n, n, nnz, true, true, -1, CHOLMOD_REAL, &cholmod->common);
        if (cholmod->A == nullptr)
          throw std::runtime_error("cholmod could not allocate the " + name + " matrix");
        auto                            *value = static_cast<double *>(cholmod->A->x);
        auto                            *start = static_cast<int *>(cholmod->A->p);
        auto                            *row   = static_cast<int *>(cholmod->A->i);
        std::vector<std::pair<int, int>> entries; // (column, entry within the row)
        std::size_t                      position = 0, first_entry = 0;
        cholmod->position_of_entry.clear();
        for (int r = 0; r < n; ++r)
          {
            int     length;
            double *values;
            int    *columns;
            M.ExtractMyRowView(r, length, values, columns);
            entries.clear();
            for (int k = 0; k < length; ++k)
              if (const int c = M.ColMap().GID(columns[k]); c >= r)
                entries.emplace_back(c, k);
            std::sort(entries.begin(), entries.end());
            cholmod->position_of_entry.resize(first_entry + length, -1);
            start[r] = static_cast<int>(position);
            AssertThrow(position + entries.size() <= cholmod->A->nzmax, ExcInternalError());
            for (const auto &[c, k] : entries)
              {
                row[position]                               = c;
                value[position]                             = values[k];
                cholmod->position_of_entry[first_entry + k] = static_cast<int>(position);
                ++position;
              }
            first_entry += length;
          }
        AssertThrow(position == cholmod->A->nzmax, ExcInternalError());
        start[n] = static_cast<int>(position);
        // The whole symmetric pattern by rows, for the row modifications.
        auto &row_start = cholmod->row_start;
        row_start.assign(n + 1, 0);
        for (int c = 0; c < n; ++c)
          for (int p = start[c]; p < start[c + 1]; ++p)
            {
              ++row_start[row[p] + 1];
              if (row[p] != c)
                ++row_start[c + 1];
            }
        for (int r = 0; r < n; ++r)
          row_start[r + 1] += row_start[r];
        cholmod->row_column.resize(row_start[n]);
        cholmod->row_position.resize(row_start[n]);
        std::vector<int> next(row_start.begin(), row_start.end() - 1);
        for (int c = 0; c < n; ++c)
          for (int p = start[c]; p < start[c + 1]; ++p)
            {
              cholmod->row_column[next[row[p]]]     = c;
              cholmod->row_position[next[row[p]]++] = p;
              if (row[p] != c)
                {
                  cholmod->row_column[next[c]]     = row[p];
                  cholmod->row_position[next[c]++] = p;
                }
            }
        cholmod->analyse(false, name);
      }
    else
      {
        // New values on the analysed pattern: a gather through the map built
        // with the pattern (no index lookups, no sorting).
        auto       *value  = static_cast<double *>(cholmod->A->x);
        const int  *target = cholmod->position_of_entry.data();
        std::size_t entry  = 0;
        for (int r = 0; r < n; ++r)
          {
            int     length;
            double *values;
            int    *columns;
            M.ExtractMyRowView(r, length, values, columns);
            // A pattern unlike the analysed one (the owner must call clear()
            // before it reinitialises the matrix) is an internal error, not a
            // buffer overrun.
            AssertThrow(entry + length <= cholmod->position_of_entry.size(), ExcInternalError());
            for (int k = 0; k < length; ++k, ++entry)
              if (target[entry] >= 0)
                value[target[entry]] = values[k];
          }
        AssertThrow(entry == cholmod->position_of_entry.size(), ExcInternalError());
      }
  }



  // Factorise A's current values into L numerically, afresh.
  void LinearSolver::cholmod_numeric()
  {
    const int n = static_cast<int>(cholmod->A->ncol);
    cholmod->values.clear();
    cholmod->unchecked = false;
    cholmod_factorize(cholmod->A, cholmod->L, &cholmod->common);
    if (cholmod->common.status == CHOLMOD_NOT_POSDEF)
      throw std::runtime_error("the " + name +
                               " system is not positive definite (cholmod failed at column " +
                               std::to_string(cholmod->L->minor) + ")");
    if (cholmod->common.status < CHOLMOD_OK)
      throw std::runtime_error("cholmod could not factorise the " + name + " matrix (status " +
                               std::to_string(cholmod->common.status) + ")");
    // The simplicial factorisation is LDL^T, which CHOLMOD completes for an
    // indefinite matrix as long as no pivot vanishes. Our systems must be
    // positive definite: check D (the first entry of each column of L; L_jj > 0
    // too if CHOLMOD chose LL^T), so that any other matrix is reported, not
    // solved without pivoting.
    AssertThrow(!cholmod->L->is_super, ExcInternalError());
    const auto *L_start = static_cast<const int *>(cholmod->L->p);
    const auto *L_value = static_cast<const double *>(cholmod->L->x);
    for (int j = 0; j < n; ++j)
      if (!(L_value[L_start[j]] > 0))
        throw std::runtime_error(
          "the " + name + " system is not positive definite (cholmod: pivot " +
          std::to_string(L_value[L_start[j]]) + " at row " + std::to_string(j) + ")");
    const auto *value = static_cast<const double *>(cholmod->A->x);
    cholmod->values.assign(value, value + cholmod->n_values());
    ++factorisation_count;
  }



  LinearSolver::LinearSolver(const Parameters::LinearSolvers           &parameters,
                             const unsigned int                         verbosity,
                             const ConditionalOStream                  &pcout,
                             const std::string                         &name,
                             const Parameters::LinearSolvers::AMGUpdate automatic_amg_update,
                             const double                               aggregation_threshold,
                             const unsigned int                         smoother_sweeps,
                             const unsigned int                         reuse_limit)
    : prm(parameters)
    , verbosity(verbosity)
    , pcout(pcout)
    , name(name)
    , amg_update(parameters.amg_update == Parameters::LinearSolvers::AMGUpdate::automatic ?
                   automatic_amg_update :
                   parameters.amg_update)
    , aggregation_threshold(aggregation_threshold)
    , smoother_sweeps(smoother_sweeps)
    , reuse_limit(reuse_limit)
  {}



  // Nothing non-finite reaches Trilinos, whose error codes name nothing.
  void LinearSolver::check_finite_matrix(const TrilinosWrappers::SparseMatrix &A) const
  {
    if (!std::isfinite(A.linfty_norm()))
      throw std::runtime_error("the matrix of the " + name +
                               " system is not finite (overflow: are material values or the "
                               "time step extreme?)");
  }



  std::unique_ptr<Amesos_BaseSolver> LinearSolver::new_direct_solver() const
  {
    Amesos                             factory;
    std::unique_ptr<Amesos_BaseSolver> solver(factory.Create(direct_type().c_str(), *problem));
    AssertThrow(solver, ExcMessage("no " + direct_type() + " in Amesos"));
    // Later numeric factorisations of the same matrix object (update())
    // keep the pivot sequence of this one: our systems are symmetric
    // positive definite, which needs no pivoting (KLU's refactor).
    Teuchos::ParameterList parameters;
    parameters.set("Refactorize", true);
    solver->SetParameters(parameters);
    if (solver->SymbolicFactorization() != 0 || solver->NumericFactorization() != 0)
      throw std::runtime_error("Amesos reported an error");
    return solver;
  }



  bool LinearSolver::direct_for(const types::global_dof_index n_unknowns) const
  {
    return prm.linear_solver == LinearSolverType::direct ||
           (prm.linear_solver == LinearSolverType::automatic &&
            n_unknowns < prm.automatic_direct_limit);
  }



  bool LinearSolver::borrow_preconditioner(const TrilinosWrappers::SparseMatrix &A,
                                           const std::uint64_t                   key)
  {
    if (matrix != &A || use_direct || !amg_built)
      return false;
    check_finite_matrix(A);
    amg_stale           = true;
    amg_for_this_matrix = false;
    borrowed            = true;
    values_key          = key;
    return true;
  }



  bool LinearSolver::recall(const std::uint64_t key)
  {
    if (borrowed && amg_key == key && key != 0)
      {
        // The borrowed hierarchy is the one made for these values.
        borrowed                = false;
        amg_for_this_matrix     = true;
        values_key              = key;
        rows_changed_since_made = 0;
        return true;
      }
    if (use_direct && direct && key != 0)
      {
        for (std::size_t i = 0; i < kept_direct.size(); ++i)
          if (kept_direct[i].key == key)
            {
              KeptDirect recalled = std::move(kept_direct[i]);
              kept_direct.erase(kept_direct.begin() + i);
              // A factorisation without a key could never be recalled: drop it.
              if (direct_key != 0)
                kept_direct.insert(kept_direct.begin(),
                                   KeptDirect{direct_key, refactorised, std::move(direct)});
              direct_key   = recalled.key;
              refactorised = recalled.refactorised;
              direct       = std::move(recalled.solver);
              matrix_norm  = matrix->linfty_norm();
              return true;
            }
        return false;
      }
    if (!use_direct && amg_built && key != 0)
      {
        for (std::size_t i = 0; i < kept_amg.size(); ++i)
          if (kept_amg[i].key == key)
            {
              KeptAMG recalled = std::move(kept_amg[i]);
              kept_amg.erase(kept_amg.begin() + i);
              if (amg_key != 0)
                kept_amg.insert(kept_amg.begin(),
                                KeptAMG{amg_key,
                                        std::move(amg),
                                        iterations_per_decade_after_build});
              borrowed                          = false;
              values_key                        = recalled.key;
              amg_key                           = recalled.key;
              amg                               = std::move(recalled.preconditioner);
              iterations_per_decade_after_build = recalled.iterations_per_decade_after_build;
              // Possibly a recomputed hierarchy: a CG failure earns a fresh build.
              amg_stale               = true;
              amg_for_this_matrix     = true;
              rows_changed_since_made = 0;
              return true;
            }
        return false;
      }
    if (!(use_direct && cholmod && key != 0))
      return false;
    auto &kept = cholmod->kept;
    for (std::size_t i = 0; i < kept.size(); ++i)
      if (kept[i].first == key)
        {
          // The current factor takes the recalled one's place, which moves to
          // the front (most recently used).
          std::pair<std::uint64_t, Cholmod::Factor> recalled = std::move(kept[i]);
          kept.erase(kept.begin() + i);
          if (cholmod->key != 0)
            kept.insert(kept.begin(),
                        {cholmod->key,
                         Cholmod::Factor{cholmod->L,
                                         std::move(cholmod->values),
                                         cholmod->unchecked}});
          else if (cholmod->L != nullptr)
            cholmod_free_factor(&cholmod->L, &cholmod->common);
          cholmod->key       = recalled.first;
          cholmod->L         = recalled.second.L;
          cholmod->values    = std::move(recalled.second.values);
          cholmod->unchecked = recalled.second.unchecked;
          // A's values are those of the current factor (the next update()
          // refills them anyway).
          return true;
        }
    return false;
  }



  void LinearSolver::initialize(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key)
  {
    matrix                  = &A;
    borrowed                = false;
    values_key              = key;
    rows_changed_since_made = 0;
    check_finite_matrix(A);
    use_direct = direct_for(A.m());
    try
      {
        if (use_direct && direct_type() == "cholmod")
          {
            direct.reset();
            kept_direct.clear();
            problem.reset();
            refactorised = false;
            cholmod_factorise(true);
            cholmod_numeric();
            cholmod->key = key;
          }
        else if (use_direct)
          {
            cholmod.reset();
            // The solver first: its destructor may read the problem it was
            // built on (Amesos_Mumps does).
            direct.reset();
            kept_direct.clear();
            refactorised = false;
            problem      = std::make_unique<Epetra_LinearProblem>();
            problem->SetOperator(const_cast<Epetra_CrsMatrix *>(&A.trilinos_matrix()));
            direct     = new_direct_solver();
            direct_key = key;
          }
        else
          {
            amg_built                         = false;
            amg_stale                         = false;
            iterations_per_decade_after_build = 0;
            kept_amg.clear();
            build_amg(*amg, A);
            amg_built           = true;
            amg_for_this_matrix = true;
            amg_key             = key;
          }
      }
    catch (const std::exception &e)
      {
        throw std::runtime_error(
          "the " + name + " system could not be " +
          (use_direct ? "factorised by " + direct_type() : std::string("preconditioned by AMG")) +
          " (a singular or badly scaled matrix?): " + one_line(e.what()));
      }
  }



  void LinearSolver::build_amg(TrilinosWrappers::PreconditionAMG    &preconditioner,
                               const TrilinosWrappers::SparseMatrix &A)
  {
    ++statistics.amg_builds;
    TrilinosWrappers::PreconditionAMG::AdditionalData data;
    data.elliptic              = true;
    data.aggregation_threshold = aggregation_threshold;
    data.smoother_sweeps       = smoother_sweeps;
    if (null_space_dimension == 0)
      preconditioner.initialize(A, data);
    else
      {
        // deal.II's parameter list for ML, with the null space replaced
        // by the given vectors (deal.II 9.4 only builds constant modes).
        Teuchos::ParameterList              parameters;
        std::unique_ptr<Epetra_MultiVector> constant_modes;
        data.set_parameters(parameters, constant_modes, A);
        parameters.set("null space: type", "pre-computed");
        parameters.set("null space: dimension", static_cast<int>(null_space_dimension));
        parameters.set("null space: vectors", null_space.data());
        preconditioner.initialize(A, parameters);
      }
  }



  // The CHOLMOD path of update(): keep the current factor (if it has a key) and
  // factorise into the storage of the least recently used one once 'Kept
  // factorisations' are kept: all share the one symbolic analysis. Where
  // only a few rows changed against the current or a kept factor, that
  // factor is copied (or modified in place) and its rows replaced instead
  // (Solver/Row update limit).
  void LinearSolver::refactorise_cholmod(const std::uint64_t key)
  {
    cholmod_factorise(false);
    auto &kept = cholmod->kept;
    // The factor closest to the new values: the fewest rows to replace.
    int              base = -2; // -1: the current one; i: kept[i]
    std::vector<int> rows;
    if (prm.row_update_limit > 0)
      for (int i = -1; i < static_cast<int>(kept.size()); ++i)
        {
          const std::vector<double> &values = i < 0 ? cholmod->values : kept[i].second.values;
          if (values.size() != cholmod->n_values())
            continue;
          std::vector<int> candidate = cholmod->rows_to_replace(values);
          if (base == -2 || candidate.size() < rows.size())
            {
              base = i;
              rows = std::move(candidate);
            }
        }
    if (base != -2)
      {
        const double          budget = prm.row_update_limit * cholmod->factorisation_flops;
        const cholmod_factor *F      = base < 0 ? cholmod->L : kept[base].second.L;
        if (cholmod->replacement_work(F, rows, budget) > budget)
          {
            base = -2;
            // A factorisation that row modifications could not replace:
            // AMD's elimination trees are deep, so each modified row costs
            // a path through most of the factor; nested dissection's are
            // shallow (the Stefan strip's column of 41 nodes: 2.3 times a
            // factorisation's flops with AMD, 0.22 with METIS). Reorder once
            // the factorisations so lost have cost what a nested-dissection
            // analysis costs (at most twice what either choice alone would
            // have cost, as in renting against buying).
            if (!cholmod->nested_dissection && prm.reordering_cost > 0)
              {
                cholmod->rejected_flops += cholmod->factorisation_flops;
                if (cholmod->rejected_flops >=
                    prm.reordering_cost * static_cast<double>(cholmod->n_values()))
                  {
                    cholmod->analyse(true, name);
                    cholmod_numeric();
                    cholmod->key = key;
                    ++reordering_count;
                    return;
                  }
              }
          }
      }
    // The storage of the new factor: the current one's (nothing is kept), a
    // new one (fewer than 'Kept factorisations' are kept), or the least
    // recently used kept one's; the current factor is kept.
    const bool      keep_current = prm.kept_factorisations > 0 && cholmod->key != 0;
    Cholmod::Factor storage;
    if (!keep_current)
      storage = Cholmod::Factor{cholmod->L, std::move(cholmod->values), cholmod->unchecked};
    else if (kept.size() >= prm.kept_factorisations)
      {
        storage = std::move(kept.back().second);
        kept.pop_back();
        if (base == static_cast<int>(kept.size()))
          base = -3; // the storage itself
      }
    // A factor to copy into the storage: the one closest to the new values
    // unless that is the storage itself.
    cholmod_factor *source = base >= 0 ? kept[base].second.L :
                             (base == -1 && keep_current) ? cholmod->L :
                                                            nullptr;
    if (keep_current)
      kept.insert(kept.begin(),
                  {cholmod->key,
                   Cholmod::Factor{cholmod->L, std::move(cholmod->values), cholmod->unchecked}});
    if (source != nullptr || storage.L == nullptr)
      {
        // (To be factorised afresh into new storage: a copy of any factor
        // for its symbolic analysis, the one just kept.)
        cholmod_factor *copy =
          cholmod_copy_factor(source != nullptr ? source : kept.front().second.L, &cholmod->common);
        if (copy == nullptr)
          throw std::runtime_error("cholmod could not copy a factor of the " + name +
                                   " matrix (out of memory?)");
        if (storage.L != nullptr)
          cholmod_free_factor(&storage.L, &cholmod->common);
        storage.L = copy;
      }
    cholmod->L         = storage.L;
    cholmod->values    = {};
    cholmod->key       = 0;
    cholmod->unchecked = false;
    if (base != -2 && cholmod->replace_rows(cholmod->L, rows))
      {
        const auto *value = static_cast<const double *>(cholmod->A->x);
        cholmod->values.assign(value, value + cholmod->n_values());
        cholmod->unchecked = true;
        ++row_update_count;
        replaced_row_count += rows.size();
      }
    else
      cholmod_numeric();
    cholmod->key = key;
  }



  // The Amesos path of update(), as for cholmod: keep the current
  // factorisation, and refactorise the least recently used solver (or a new
  // one while fewer are kept).
  void LinearSolver::refactorise_direct(const TrilinosWrappers::SparseMatrix &A,
                                        const std::uint64_t                   key)
  {
    if (prm.kept_factorisations > 0 && direct_key != 0)
      {
        std::unique_ptr<Amesos_BaseSolver> solver;
        bool                               fresh = false;
        if (kept_direct.size() < prm.kept_factorisations)
          {
            try
              {
                solver = new_direct_solver();
              }
            catch (const std::exception &e)
              {
                throw std::runtime_error("the " + name + " system could not be factorised by " +
                                         direct_type() + ": " + one_line(e.what()));
              }
            fresh = true;
          }
        else
          {
            solver = std::move(kept_direct.back().solver);
            kept_direct.pop_back();
          }
        kept_direct.insert(kept_direct.begin(),
                           KeptDirect{direct_key, refactorised, std::move(direct)});
        direct = std::move(solver);
        if (fresh)
          {
            direct_key   = key;
            refactorised = false;
            return;
          }
      }
    // The key names the values only once they are factorised: a failed
    // factorisation must not be recalled under it.
    direct_key = 0;
    if (direct->NumericFactorization() != 0)
      throw std::runtime_error("the " + name + " system could not be factorised by " +
                               direct_type() + " (a singular matrix?)");
    direct_key   = key;
    refactorised = true;
    matrix_norm  = A.linfty_norm();
  }



  // 'AMG update = recompute' with kept hierarchies: keep the current hierarchy
  // for recall(); recompute the least recently used one on the new values (or
  // build a new one while fewer are kept).
  void LinearSolver::keep_and_recompute_amg(const TrilinosWrappers::SparseMatrix &A,
                                            const std::uint64_t                   key)
  {
    std::unique_ptr<TrilinosWrappers::PreconditionAMG> preconditioner;
    double                                             after_build = 0;
    bool                                               recomputed  = false;
    if (kept_amg.size() >= prm.kept_factorisations)
      {
        preconditioner = std::move(kept_amg.back().preconditioner);
        after_build    = kept_amg.back().iterations_per_decade_after_build;
        kept_amg.pop_back();
        recomputed = recompute_amg(*preconditioner);
      }
    else
      preconditioner = std::make_unique<TrilinosWrappers::PreconditionAMG>();
    kept_amg.insert(kept_amg.begin(),
                    KeptAMG{amg_key, std::move(amg), iterations_per_decade_after_build});
    amg = std::move(preconditioner);
    if (recomputed)
      {
        amg_stale                         = true;
        iterations_per_decade_after_build = after_build;
      }
    else
      {
        try
          {
            build_amg(*amg, A);
          }
        catch (const std::exception &e)
          {
            throw std::runtime_error(
              "the " + name + " system could not be preconditioned by AMG: " + one_line(e.what()));
          }
        amg_stale                         = false;
        iterations_per_decade_after_build = 0;
      }
    amg_key             = key;
    amg_for_this_matrix = true;
  }



  // The iterative path of update() for the matrix of the last initialize()
  // with a hierarchy at hand: keep it ('AMG update = reuse'), recompute it on
  // its aggregates, or keep it for recall() and recompute another one ('AMG
  // update = recompute'). False if none of these applies or a recomputation
  // failed: update() then builds afresh.
  bool LinearSolver::update_amg(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key)
  {
    const bool degraded =
      iterations_per_decade_after_build > 0 &&
      last_iterations_per_decade > prm.amg_rebuild_ratio * iterations_per_decade_after_build + 0.5;
    // Rows changed since the hierarchy was made for its values: the extra CG
    // iterations of keeping it grow with their number (a rank-m change of the
    // matrix moves at most m eigenvalues of the preconditioned operator), so
    // a limit that does not depend on the mesh keeps them bounded under
    // refinement, where a fixed fraction of the contact nodes would not.
    const bool over_reuse_limit = reuse_limit > 0 && rows_changed_since_made > reuse_limit;
    if (degraded)
      return false;
    using AMGUpdate = Parameters::LinearSolvers::AMGUpdate;
    if (amg_update == AMGUpdate::reuse && iterations_per_decade_after_build > 0 &&
        !over_reuse_limit)
      {
        // The hierarchy of an earlier active set preconditions the new matrix
        // (CG runs on the new one): a few rows differ.
        check_finite_matrix(A);
        amg_stale           = true;
        amg_for_this_matrix = false;
        return true;
      }
    if (amg_update == AMGUpdate::reuse)
      {
        // No solve has yet measured how fast CG runs with a hierarchy made for
        // its matrix, so reuse could not be judged, or more rows changed than
        // the reuse limit: recompute it for these values on its aggregates.
        check_finite_matrix(A);
        amg_stale           = true;
        amg_for_this_matrix = true;
        if (recompute_amg(*amg))
          {
            amg_key                 = key; // now made for these values
            rows_changed_since_made = 0;
            if (verbosity >= 2)
              pcout << "      AMG (" << name << "): recomputed on its aggregates" << std::endl;
            return true;
          }
        return false;
      }
    if (amg_update == AMGUpdate::recompute && prm.kept_factorisations > 0 && amg_key != 0)
      {
        check_finite_matrix(A);
        keep_and_recompute_amg(A, key);
        return true;
      }
    if (amg_update == AMGUpdate::recompute)
      {
        check_finite_matrix(A);
        amg_stale           = true;
        amg_for_this_matrix = true;
        // Built afresh if the recomputation failed.
        if (recompute_amg(*amg))
          {
            amg_key = key; // now made for these values
            return true;
          }
      }
    return false;
  }



  // New values in the matrix of the last initialize() (or another matrix):
  // refactorise on the direct path, keep or recompute the AMG hierarchy on the
  // iterative one; anything else is initialised afresh.
  void LinearSolver::update(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key)
  {
    borrowed   = false;
    values_key = key;
    if (matrix == &A && use_direct && cholmod)
      {
        check_finite_matrix(A);
        refactorise_cholmod(key);
        return;
      }
    if (matrix == &A && use_direct && direct)
      {
        check_finite_matrix(A);
        refactorise_direct(A, key);
        return;
      }
    if (matrix == &A && !use_direct && amg_built && update_amg(A, key))
      return;
    initialize(A, key);
  }



  bool LinearSolver::recompute_amg(TrilinosWrappers::PreconditionAMG &preconditioner)
  {
    // deal.II's PreconditionAMG::reinit() drops ML's return code: call ML
    // directly.
    auto *ml = dynamic_cast<ML_Epetra::MultiLevelPreconditioner *>(
      const_cast<Epetra_Operator *>(&preconditioner.trilinos_operator()));
    const bool recomputed = ml != nullptr && ml->ReComputePreconditioner() == 0;
    statistics.amg_recomputations += recomputed;
    return recomputed;
  }



  LinearSolverStatistics LinearSolver::take_statistics()
  {
    const LinearSolverStatistics taken = statistics;
    statistics                         = LinearSolverStatistics();
    return taken;
  }



  void LinearSolver::set_near_null_space(std::vector<std::vector<double>> modes)
  {
    null_space_dimension = modes.size();
    null_space.clear();
    for (const auto &mode : modes)
      null_space.insert(null_space.end(), mode.begin(), mode.end());
  }



  void LinearSolver::clear()
  {
    matrix = nullptr;
    direct.reset();
    kept_direct.clear();
    problem.reset();
    cholmod.reset();
    amg->clear();
    kept_amg.clear();
    amg_built               = false;
    rows_changed_since_made = 0;
  }



  void LinearSolver::solve(Vector &x, const Vector &b, const double relative_tolerance)
  {
    if (matrix == nullptr)
      throw std::logic_error("LinearSolver::solve() before initialize()");
    // Nothing non-finite reaches Trilinos (whose error codes name nothing).
    check_finite(b, "the right-hand side of the " + name + " system");
    AssertThrow(!x.has_ghost_elements(),
                ExcMessage("LinearSolver::solve() needs a vector without ghost entries"));
    if (use_direct && cholmod)
      {
        cholmod_common &common = cholmod->common;
        const auto      n      = static_cast<std::size_t>(matrix->trilinos_matrix().NumMyRows());
        cholmod_dense  *B      = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &common);
        if (B == nullptr)
          throw std::runtime_error("cholmod could not allocate a vector");
        std::copy(b.trilinos_vector()[0], b.trilinos_vector()[0] + n, static_cast<double *>(B->x));
        cholmod_dense *X = cholmod_solve(CHOLMOD_A, cholmod->L, B, &common);
        cholmod_free_dense(&B, &common);
        if (X == nullptr)
          throw std::runtime_error("the direct solver failed on the " + name + " system");
        std::copy(static_cast<double *>(X->x),
                  static_cast<double *>(X->x) + n,
                  x.trilinos_vector()[0]);
        cholmod_free_dense(&X, &common);
        // The first solve with a factor modified row by row checks its
        // backward error, as a refactorisation's; far above round-off the
        // matrix is factorised afresh and solved again.
        if (cholmod->unchecked)
          {
            Vector r(b);
            matrix->residual(r, x, b);
            const double scale = matrix->linfty_norm() * x.linfty_norm() + b.linfty_norm();
            if (r.linfty_norm() <= prm.refactorisation_backward_error * scale)
              cholmod->unchecked = false;
            else
              {
                if (verbosity >= 1)
                  pcout << "      " << name << ": modified factor inaccurate (residual "
                        << r.linfty_norm() << " of " << scale << "), factorising afresh"
                        << std::endl;
                std::copy(cholmod->values.begin(),
                          cholmod->values.end(),
                          static_cast<double *>(cholmod->A->x));
                cholmod_numeric();
                solve(x, b, relative_tolerance);
                return;
              }
          }
      }
    else if (use_direct)
      {
        problem->SetLHS(&x.trilinos_vector());
        problem->SetRHS(const_cast<Epetra_MultiVector *>(&b.trilinos_vector()));
        if (direct->Solve() != 0)
          throw std::runtime_error("the direct solver failed on the " + name + " system");
        // A refactorisation reuses the pivot sequence of the last full
        // factorisation, and nothing inside KLU checks its element growth:
        // check the backward error, and factorise afresh (with pivoting) if it
        // is far above round-off.
        if (refactorised)
          {
            Vector       r(b);
            const double residual = matrix->residual(r, x, b);
            (void)residual;
            const double scale = matrix_norm * x.linfty_norm() + b.linfty_norm();
            if (!(r.linfty_norm() <= prm.refactorisation_backward_error * scale))
              {
                if (verbosity >= 1)
                  pcout << "      " << name << ": refactorisation inaccurate (residual "
                        << r.linfty_norm() << " of " << scale << "), factorising afresh"
                        << std::endl;
                initialize(*matrix, direct_key);
                problem->SetLHS(&x.trilinos_vector());
                problem->SetRHS(const_cast<Epetra_MultiVector *>(&b.trilinos_vector()));
                if (direct->Solve() != 0)
                  throw std::runtime_error("the direct solver failed on the " + name + " system");
              }
          }
      }
    else
      {
        const double     tolerance = relative_tolerance > 0 ? relative_tolerance : prm.cg_tolerance;
        SolverControl    control(prm.cg_max_iterations, tolerance * b.l2_norm());
        SolverCG<Vector> cg(control);
        const Vector     x_start(x);
        // This call's iterations, a failed attempt's included.
        unsigned int iterations = 0;
        try
          {
            cg.solve(*matrix, x, b, *amg);
          }
        catch (const SolverControl::NoConvergence &)
          {
            // A hierarchy of an earlier matrix may precondition the new one
            // badly (or indefinitely): once more with a fresh hierarchy.
            if (!amg_stale)
              throw;
            if (verbosity >= 1)
              pcout << "      " << name << ": CG failed with the kept AMG hierarchy, "
                    << "building it afresh" << std::endl;
            iterations += control.last_step();
            initialize(*matrix, values_key);
            x = x_start;
            cg.solve(*matrix, x, b, *amg);
          }
        iterations += control.last_step();
        ++statistics.cg_solves;
        statistics.cg_iterations += iterations;
        statistics.max_cg_iterations = std::max(statistics.max_cg_iterations, iterations);
        // CG iterations per decade of residual reduction: comparable between
        // warm-started solves to different tolerances.
        const double decades =
          control.last_value() > 0 && control.initial_value() > control.last_value() ?
            std::log10(control.initial_value() / control.last_value()) :
            0.;
        if (decades >= 0.5 && !borrowed)
          {
            last_iterations_per_decade = control.last_step() / decades;
            // The baseline of the rebuild check: a solve whose hierarchy was
            // built or recomputed for its own matrix (not a reused one).
            if (iterations_per_decade_after_build == 0 && amg_for_this_matrix)
              iterations_per_decade_after_build = last_iterations_per_decade;
          }
        if (verbosity >= 2)
          pcout << "      CG (" << name << "): " << control.last_step() << " iterations"
                << std::endl;
      }
    check_finite(x, "the solution of the " + name + " system (overflow in the data?)");
  }
} // namespace ContactStefan
