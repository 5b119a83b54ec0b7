#include <deal.II/lac/solver_cg.h>

#include <contact-stefan/linear_algebra/cholmod_factor.h>
#include <contact-stefan/linear_algebra/linear_solver.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <Amesos.h>
#include <Epetra_CrsMatrix.h>
#include <Epetra_MultiVector.h>
#include <Teuchos_ParameterList.hpp>
#include <ml_MultiLevelPreconditioner.h>

namespace ContactStefan
{
  using LinearSolverType = Parameters::LinearSolvers::LinearSolverType;



  std::string LinearSolver::direct_type() const
  {
    if (prm.direct_solver_type != "automatic")
      return prm.direct_solver_type;
    return (matrix != nullptr && matrix->trilinos_matrix().Comm().NumProc() == 1) ? "cholmod" :
                                                                                    "Amesos_Klu";
  }



  LinearSolver::LinearSolver(const Parameters::LinearSolvers           &parameters,
                             const unsigned int                         verbosity,
                             const ConditionalOStream                  &pcout,
                             const std::string                         &name,
                             const Parameters::LinearSolvers::AMGUpdate automatic_amg_update,
                             const double                               aggregation_threshold,
                             const unsigned int                         smoother_sweeps,
                             const unsigned int                         reuse_limit,
                             const unsigned int                         direct_limit)
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
    , direct_limit(direct_limit != numbers::invalid_unsigned_int ?
                     direct_limit :
                     parameters.automatic_direct_limit)
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
           (prm.linear_solver == LinearSolverType::automatic && n_unknowns < direct_limit);
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
    if (!use_direct && amg_built && amg_key == key && key != 0)
      {
        // The current hierarchy is the one made for these values: borrowed
        // for others since, or built for them within a solve that borrowed
        // it (rebuild_amg()). Not to be shelved and recomputed for its own
        // values, which would keep two hierarchies under one key.
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
    return use_direct && cholmod && key != 0 && recall_cholmod(key);
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
    // Built before the current hierarchy is shelved: if ML fails, the
    // current one is still the one made for amg_key.
    if (!recomputed)
      try
        {
          build_amg(*preconditioner, A);
        }
      catch (const std::exception &e)
        {
          throw std::runtime_error("the " + name +
                                   " system could not be preconditioned by AMG: " +
                                   one_line(e.what()));
        }
    kept_amg.insert(kept_amg.begin(),
                    KeptAMG{amg_key, std::move(amg), iterations_per_decade_after_build});
    amg                               = std::move(preconditioner);
    amg_stale                         = recomputed;
    iterations_per_decade_after_build = recomputed ? after_build : 0;
    amg_key                           = key;
    amg_for_this_matrix               = true;
  }



  // A fresh hierarchy for the values the matrix holds, within a solve (the CG
  // budget or a CG failure): where hierarchies are kept for recall() ('AMG
  // update = recompute'), the current one joins them if it was made for
  // other values; the kept ones stay (initialize() would drop them).
  void LinearSolver::rebuild_amg()
  {
    using AMGUpdate = Parameters::LinearSolvers::AMGUpdate;
    // Built into a new object first: if ML fails, the current hierarchy and
    // the kept ones are as they were.
    auto fresh = std::make_unique<TrilinosWrappers::PreconditionAMG>();
    try
      {
        build_amg(*fresh, *matrix);
      }
    catch (const std::exception &e)
      {
        throw std::runtime_error("the " + name +
                                 " system could not be preconditioned by AMG (a singular or "
                                 "badly scaled matrix?): " +
                                 one_line(e.what()));
      }
    // A kept hierarchy of these values would have been recalled; should one
    // be there, the fresh one replaces it.
    if (values_key != 0)
      kept_amg.erase(std::remove_if(kept_amg.begin(),
                                    kept_amg.end(),
                                    [&](const KeptAMG &k) { return k.key == values_key; }),
                     kept_amg.end());
    if (amg_update == AMGUpdate::recompute && prm.kept_factorisations > 0 && amg_key != 0 &&
        amg_key != values_key)
      {
        kept_amg.insert(kept_amg.begin(),
                        KeptAMG{amg_key, std::move(amg), iterations_per_decade_after_build});
        if (kept_amg.size() > prm.kept_factorisations)
          kept_amg.pop_back();
      }
    amg                               = std::move(fresh);
    amg_built                         = true;
    amg_stale                         = false;
    amg_for_this_matrix               = true;
    borrowed                          = false;
    iterations_per_decade_after_build = 0;
    rows_changed_since_made           = 0;
    amg_key                           = values_key;
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
      solve_cholmod(x, b);
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
        const double tolerance = relative_tolerance > 0 ? relative_tolerance : prm.cg_tolerance;
        // A hierarchy made for other values (kept, recomputed on the
        // aggregates of another matrix, recalled or borrowed) gets a budget:
        // three times what the rebuild check of update_amg() tolerates per
        // decade, for every decade from this solve's start to the requested
        // residual, plus 10. CG past it is slower than a fresh hierarchy would
        // be (on the default scene, the recomputation after the first contact
        // set of an initial adaptation took 372 iterations where a fresh build
        // then took 10-50), so it stops there and goes on from its iterate with
        // a fresh one (rebuild_amg()), instead of learning it after the solve.
        // Every rank computes the same budget from global norms.
        unsigned int budget = prm.cg_max_iterations;
        if (amg_stale && iterations_per_decade_after_build > 0)
          {
            Vector       r(b);
            const double start   = matrix->residual(r, x, b);
            const double target  = tolerance * b.l2_norm();
            const double decades = start > target ? std::log10(start / target) : 0.;
            const double allowed = 3 * prm.amg_rebuild_ratio * iterations_per_decade_after_build *
                                     std::max(1., decades) +
                                   10;
            if (allowed < prm.cg_max_iterations) // (no overflow in the conversion)
              budget = static_cast<unsigned int>(std::ceil(allowed));
          }
        SolverControl    control(budget, tolerance * b.l2_norm());
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
            // badly (or indefinitely): once more with a fresh hierarchy, from
            // the better of the start and the last iterate.
            if (!amg_stale)
              throw;
            const bool over_budget =
              budget < prm.cg_max_iterations && control.last_step() >= budget;
            if (verbosity >= 1)
              pcout << "      " << name << ": CG "
                    << (over_budget ? "over its budget of " + std::to_string(budget) + " iterations" :
                                      std::string("failed"))
                    << " with the kept AMG hierarchy, building it afresh" << std::endl;
            iterations += control.last_step();
            Vector       r_last(b), r_start(b);
            const double last_residual  = matrix->residual(r_last, x, b);
            const double start_residual = matrix->residual(r_start, x_start, b);
            if (!(last_residual < start_residual)) // (a NaN too)
              x = x_start;
            rebuild_amg();
            control.set_max_steps(prm.cg_max_iterations);
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


  void mark_neighbours(const TrilinosWrappers::SparseMatrix &A,
                       std::vector<char>                    &rows,
                       const unsigned int                    layers)
  {
    const Epetra_CrsMatrix &M = A.trilinos_matrix();
    const int               n = M.NumMyRows();
    AssertThrow(static_cast<int>(rows.size()) == n, ExcInternalError());
    std::vector<int> layer, next;
    for (int r = 0; r < n; ++r)
      if (rows[r])
        layer.push_back(r);
    for (unsigned int l = 0; l < layers && !layer.empty(); ++l, layer.swap(next))
      {
        next.clear();
        for (const int r : layer)
          {
            int     length;
            double *values;
            int    *columns;
            M.ExtractMyRowView(r, length, values, columns);
            for (int k = 0; k < length; ++k)
              if (const int c = M.ColMap().GID(columns[k]); c >= 0 && c < n && !rows[c])
                {
                  rows[c] = 1;
                  next.push_back(c);
                }
          }
      }
  }
} // namespace ContactStefan
