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
    // The key of L's matrix values (0: none), and earlier factors of the same
    // symbolic analysis with their keys, the most recently used first.
    std::uint64_t                                           key = 0;
    std::vector<std::pair<std::uint64_t, cholmod_factor *>> kept;
    Cholmod()
    {
      cholmod_start(&common);
    }
    ~Cholmod()
    {
      if (L != nullptr)
        cholmod_free_factor(&L, &common);
      for (auto &entry : kept)
        cholmod_free_factor(&entry.second, &common);
      if (A != nullptr)
        cholmod_free_sparse(&A, &common);
      cholmod_finish(&common);
    }
    Cholmod(const Cholmod &)            = delete;
    Cholmod &operator=(const Cholmod &) = delete;
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
      }
    auto *value = static_cast<double *>(cholmod->A->x);
    if (!analyse)
      {
        // New values on the analysed pattern: a gather through the map built
        // with the pattern (no index lookups, no sorting).
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
    else
      {
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
      }
    if (analyse)
      {
        // Simplicial, not supernodal: the supernodal factorisation calls the
        // BLAS, and with Debian's reference BLAS it took 2.7x longer on the Stefan
        // strip (16 441 unknowns). The ordering is CHOLMOD's choice (AMD here).
        cholmod->common.supernodal = CHOLMOD_SIMPLICIAL;
        cholmod->L                 = cholmod_analyze(cholmod->A, &cholmod->common);
        if (cholmod->L == nullptr)
          throw std::runtime_error("cholmod could not analyse the " + name + " matrix");
      }
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
          std::pair<std::uint64_t, cholmod_factor *> recalled = kept[i];
          kept.erase(kept.begin() + i);
          if (cholmod->key != 0)
            kept.insert(kept.begin(), {cholmod->key, cholmod->L});
          else if (cholmod->L != nullptr)
            cholmod_free_factor(&cholmod->L, &cholmod->common);
          cholmod->key = recalled.first;
          cholmod->L   = recalled.second;
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
  // factorisations' are kept: all share the one symbolic analysis.
  void LinearSolver::refactorise_cholmod(const std::uint64_t key)
  {
    auto &kept = cholmod->kept;
    if (prm.kept_factorisations > 0 && cholmod->key != 0)
      {
        cholmod_factor *storage = nullptr;
        if (kept.size() < prm.kept_factorisations)
          {
            storage = cholmod_copy_factor(cholmod->L, &cholmod->common);
            if (storage == nullptr)
              throw std::runtime_error("cholmod could not copy a factor of the " + name +
                                       " matrix (out of memory?)");
          }
        else
          {
            storage = kept.back().second;
            kept.pop_back();
          }
        kept.insert(kept.begin(), {cholmod->key, cholmod->L});
        cholmod->L = storage;
      }
    cholmod->key = 0;
    cholmod_factorise(false);
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
