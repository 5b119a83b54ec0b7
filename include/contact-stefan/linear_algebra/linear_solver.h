// One linear solver for both fields: initialise with a matrix once, solve with it
// as often as needed. 'Solver/Linear solver' chooses a sparse direct solver
// (Trilinos Amesos: the factorisation is computed in initialize()) or CG
// preconditioned by ML algebraic multigrid (the hierarchy is built in
// initialize()); CG starts from the x it is given.
#ifndef contact_stefan_linear_solver_h
#define contact_stefan_linear_solver_h

#include <deal.II/base/conditional_ostream.h>

#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/common.h>
#include <contact-stefan/linear_algebra/linear_solver_parameters.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Amesos_BaseSolver.h>
#include <Epetra_LinearProblem.h>

namespace ContactStefan
{
  /**
   * What a linear solver did over some span of work, on its iterative path
   * (CG + AMG) and with CHOLMOD: reported per step and summed over the run
   * (checkpointed with it).
   */
  struct LinearSolverStatistics
  {
    unsigned int cg_solves          = 0;
    unsigned int cg_iterations      = 0; // summed over the solves
    unsigned int max_cg_iterations  = 0; // of one solve
    unsigned int amg_builds         = 0; // hierarchies built afresh
    unsigned int amg_recomputations = 0; // recomputed on kept aggregates
    // CHOLMOD: numeric factorisations, factors modified row by row instead
    // (Solver/Row update limit), the rows they replaced, and reorderings by
    // nested dissection (Solver/Reordering cost).
    unsigned int       cholmod_factorisations = 0;
    unsigned int       row_updates            = 0;
    unsigned long long replaced_rows          = 0;
    unsigned int       reorderings            = 0;

    LinearSolverStatistics &operator+=(const LinearSolverStatistics &other)
    {
      cg_solves += other.cg_solves;
      cg_iterations += other.cg_iterations;
      max_cg_iterations = std::max(max_cg_iterations, other.max_cg_iterations);
      amg_builds += other.amg_builds;
      amg_recomputations += other.amg_recomputations;
      cholmod_factorisations += other.cholmod_factorisations;
      row_updates += other.row_updates;
      replaced_rows += other.replaced_rows;
      reorderings += other.reorderings;
      return *this;
    }

    /** For checkpoints (boost serialization). */
    template <class Archive>
    void serialize(Archive &ar, const unsigned int)
    {
      ar &cg_solves &cg_iterations &max_cg_iterations &amg_builds &amg_recomputations
        &cholmod_factorisations &row_updates &replaced_rows &reorderings;
    }
  };

  class LinearSolver
  {
  public:
    /**
     * name: which system, for messages ("enthalpy", "elasticity");
     * automatic_amg_update: what 'Solver/AMG update = automatic' means for it;
     * aggregation_threshold, smoother_sweeps: its ML settings;
     * reuse_limit: with 'AMG update = reuse', the changed rows (as counted by
     * the callers of update()) a hierarchy is kept across before it is
     * recomputed for the current values (0: no limit);
     * direct_limit: 'Linear solver = automatic' solves systems with fewer
     * unknowns directly (by default 'Automatic direct limit').
     */
    LinearSolver(const Parameters::LinearSolvers           &parameters,
                 const unsigned int                         verbosity,
                 const ConditionalOStream                  &pcout,
                 const std::string                         &name,
                 const Parameters::LinearSolvers::AMGUpdate automatic_amg_update,
                 const double                               aggregation_threshold,
                 const unsigned int                         smoother_sweeps,
                 const unsigned int                         reuse_limit = 0,
                 const unsigned int direct_limit = numbers::invalid_unsigned_int);

    /**
     * The near-null space the AMG hierarchy is built for: vectors over the
     * locally owned rows in their order (elasticity: the rigid-body modes; ML's
     * default, the constant, only fits a scalar operator). Empty: the default.
     */
    void set_near_null_space(std::vector<std::vector<double>> modes);
    /**
     * The rows the caller expects to change next (the nodes about a melting
     * front), asked for whenever CHOLMOD orders a matrix: a nonzero entry per
     * locally owned row puts that row after all others in the fill-reducing
     * order (CAMD with two constraint sets), so that replacing it modifies
     * only the end of the factor. Unset, or an answer without such rows or
     * with only such rows: the ordering is CHOLMOD's own.
     */
    void set_volatile_rows(std::function<std::vector<char>()> rows)
    {
      volatile_rows = std::move(rows);
    }
    /**
     * Factorise A, or build the AMG hierarchy of A. A must stay alive; its
     * values may change in place only if update() follows before the next solve().
     */
    void initialize(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key = 0);
    /**
     * A's values changed in place (a new active set, same pattern): the direct
     * solver refactorises numerically on its kept symbolic analysis (the
     * fill-reducing ordering), or with CHOLMOD modifies the factor closest to
     * the new values row by row where few rows changed ('Solver/Row update
     * limit', 'Solver/Reordering cost'); an AMG hierarchy built on the same matrix object
     * is, by 'Solver/AMG update', kept as it is, or keeps its aggregates and
     * recomputes its prolongators, coarse operators and smoothers from the new
     * values (ML's reuse), or is built afresh.
     * The hierarchy is rebuilt from scratch when the last CG solve needed more
     * than 'Solver/AMG rebuild ratio' times (plus 0.5) the iterations per decade of residual
     * reduction of the first solve after the last full build: ML keeps some estimates of the first
     * build (the finest level's largest eigenvalue), which a moving front can outdate.
     * key (optional, nonzero) names the matrix values for recall(): the
     * caller's fingerprint of everything they depend on.
     * With 'AMG update = reuse' and a reuse limit, a hierarchy kept across
     * more changed rows (note_changed_rows()) than the limit since it was made
     * for its values is recomputed for the new ones. A kept hierarchy costs
     * CG extra iterations that grow with the number of changed rows, not with
     * the mesh.
     */
    void update(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key = 0);
    /**
     * The caller changed n rows of the matrix (active-set conditions entering
     * or leaving; an upper bound will do), for the reuse limit.
     */
    void note_changed_rows(const unsigned int n)
    {
      rows_changed_since_made += n;
    }
    /**
     * The matrix object of the last initialize() now holds the values that
     * were named key in an earlier update() or initialize(): if their
     * factorisation (CHOLMOD or Amesos) or AMG hierarchy was kept ('Solver/Kept
     * factorisations'), it becomes the current one and true is returned, as
     * it is when the current AMG hierarchy is the one made for them, whatever
     * 'AMG update' (borrowed since, or built within a solve that borrowed
     * it); otherwise nothing changes (update() must follow). Each kept Amesos
     * solver holds a full factor (KLU on several ranks: a gathered copy on
     * rank 0), so memory grows with the number kept.
     */
    bool recall(const std::uint64_t key);
    /**
     * A's values changed in place, and the solves until the next update(),
     * initialize() or recall() only need a loose tolerance (an active-set
     * iteration whose set still changes): on the iterative path the current
     * AMG hierarchy, made for earlier values, preconditions CG on the new ones
     * without being recomputed, and true is returned. Such solves do not
     * count for the rebuild check; a CG failure, or CG over its budget
     * (solve()), builds a hierarchy afresh for them. On the direct path
     * nothing can be skipped: false, and the caller must update().
     * recall(key) of the hierarchy's own values ends the borrowing.
     */
    bool borrow_preconditioner(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key);
    /**
     * Whether a system of n_unknowns is solved directly ('Solver/Linear
     * solver'; automatic: below the direct_limit given to the constructor,
     * by default 'Automatic direct limit'). The choice
     * initialize() makes, known before it (and after clear()).
     */
    bool direct_for(const types::global_dof_index n_unknowns) const;
    /**
     * Whether the last initialize()/update() chose the direct solver (the
     * choice of 'automatic' depends on the size of the system).
     */
    bool is_direct() const
    {
      return use_direct;
    }
    /**
     * Solve A x = b with the matrix of the last initialize(); CG (warm
     * started from x) reduces the residual to relative_tolerance ||b||
     * ('Solver/CG tolerance' if 0).
     */
    void solve(Vector &x, const Vector &b, const double relative_tolerance = 0);
    /**
     * Forget the matrix (its owner is about to reinit or destroy it): a solve()
     * before the next initialize() is then an error, not a use of freed memory.
     */
    void clear();
    /** What it did since the last call (and start counting anew). */
    LinearSolverStatistics take_statistics();

  private:
    void check_finite_matrix(const TrilinosWrappers::SparseMatrix &A) const;

    const Parameters::LinearSolvers &prm;
    const unsigned int        verbosity;
    const ConditionalOStream &pcout;
    const std::string         name;
    /** 'Solver/AMG update' with automatic resolved for this system. */
    const Parameters::LinearSolvers::AMGUpdate amg_update;
    /** ML's 'aggregation: threshold' for this system. */
    const double                          aggregation_threshold;
    /** ML's 'smoother: sweeps' for this system. */
    const unsigned int smoother_sweeps;
    /**
     * The reuse limit (0: none) and the rows changed since the current
     * hierarchy was built or recomputed for its values.
     */
    const unsigned int reuse_limit;
    const unsigned int direct_limit;
    std::uint64_t      rows_changed_since_made = 0;
    /** Counted since the last take_statistics(). */
    LinearSolverStatistics statistics;
    /** ML's reuse on the current hierarchy for A's new values; true if it worked. */
    bool recompute_amg(TrilinosWrappers::PreconditionAMG &preconditioner);
    const TrilinosWrappers::SparseMatrix *matrix     = nullptr;
    bool                                  use_direct = true; // of the last initialize()
    /**
     * The direct path: Amesos on the matrix object; its symbolic analysis
     * (ordering) is kept by update() while only values change.
     */
    std::unique_ptr<Epetra_LinearProblem> problem;
    std::unique_ptr<Amesos_BaseSolver>    direct;
    /**
     * Earlier Amesos factorisations of the same matrix object for recall():
     * (key, whether it reused a pivot order, solver), most recently used first;
     * and those of the current one.
     */
    struct KeptDirect
    {
      std::uint64_t                      key;
      bool                               refactorised;
      std::unique_ptr<Amesos_BaseSolver> solver;
    };
    std::vector<KeptDirect> kept_direct;
    std::uint64_t           direct_key = 0;
    /** A new Amesos solver on `problem` with its symbolic and numeric factorisation. */
    std::unique_ptr<Amesos_BaseSolver> new_direct_solver() const;
    /**
     * Or SuiteSparse's CHOLMOD (Direct solver type = cholmod, serial): the
     * factor with its symbolic analysis, kept while the pattern is the same.
     */
    struct Cholmod;
    std::shared_ptr<Cholmod> cholmod;
    std::function<std::vector<char>()> volatile_rows;
    /**
     * Copy the matrix's lower triangle into CHOLMOD's column storage; with
     * analyse, set up its pattern and find the ordering and the symbolic
     * factor.
     */
    void cholmod_factorise(const bool analyse);
    /** recall() and solve() on the CHOLMOD path. */
    bool recall_cholmod(const std::uint64_t key);
    void solve_cholmod(Vector &x, const Vector &b);
    /** Factorise the values in CHOLMOD's copy of the matrix afresh (numerically). */
    void cholmod_numeric();
    /**
     * The direct back end of this matrix: 'Solver/Direct solver type', with
     * 'automatic' meaning cholmod on one MPI rank and Amesos_Klu on several.
     */
    std::string direct_type() const;
    /**
     * Whether the current factorisation is a refactorisation (pivots of an
     * earlier one; its solves are checked against 'Solver/Refactorisation
     * backward error') and the matrix's infinity norm then.
     */
    bool                                               refactorised = false;
    double                                             matrix_norm  = 0;
    std::unique_ptr<TrilinosWrappers::PreconditionAMG> amg =
      std::make_unique<TrilinosWrappers::PreconditionAMG>();
    /** Build a hierarchy of A afresh into `preconditioner`. */
    void build_amg(TrilinosWrappers::PreconditionAMG    &preconditioner,
                   const TrilinosWrappers::SparseMatrix &A);
    /**
     * The paths of update() for the matrix of the last initialize():
     * refactorise with CHOLMOD or Amesos (keeping the current factorisation
     * for recall()), or keep or recompute the AMG hierarchy (false: build
     * afresh); keep_and_recompute_amg() is 'AMG update = recompute' with kept
     * hierarchies.
     */
    void refactorise_cholmod(const std::uint64_t key);
    /** Order the pattern afresh (refactorise_cholmod()) and factorise A's values. */
    void reorder_cholmod(const bool nested, const std::vector<char> &last, const std::uint64_t key);
    void refactorise_direct(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key);
    bool update_amg(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key);
    void keep_and_recompute_amg(const TrilinosWrappers::SparseMatrix &A, const std::uint64_t key);
    /**
     * A fresh hierarchy for values_key within a solve; the kept ones stay. If
     * ML fails, nothing has changed.
     */
    void rebuild_amg();
    /**
     * With 'AMG update = recompute', hierarchies of earlier matrix values of
     * the same matrix object for recall(), most recently used first, like the
     * kept factorisations; amg_key names the current one's values.
     */
    struct KeptAMG
    {
      std::uint64_t                                      key;
      std::unique_ptr<TrilinosWrappers::PreconditionAMG> preconditioner;
      double                                             iterations_per_decade_after_build;
    };
    std::vector<KeptAMG> kept_amg;
    std::uint64_t        amg_key   = 0;
    bool                 amg_built = false;
    /**
     * Whether the hierarchy was built on other matrix values (update() kept or
     * recomputed it, or it was recalled or borrowed): CG then has a budget of
     * iterations (solve()), and going over it or failing earns one retry with
     * a fresh build.
     */
    bool amg_stale = false;
    /**
     * Whether the hierarchy was built or recomputed for the current matrix
     * values ('AMG update = reuse' keeps one made for earlier values).
     */
    bool amg_for_this_matrix = true;
    /**
     * Whether the current hierarchy was borrowed (borrow_preconditioner()) for
     * other matrix values than its own (amg_key).
     */
    bool borrowed = false;
    /**
     * The key of the values the matrix holds (of the last initialize(),
     * update(), borrow_preconditioner() or successful recall()): a hierarchy
     * built afresh within a solve (CG failed or over its budget) is made for
     * them.
     */
    std::uint64_t values_key = 0;
    /**
     * CG iterations per decade of residual reduction: of the first solve
     * after the last full AMG build (0: none yet) and of the last solve.
     */
    double iterations_per_decade_after_build = 0, last_iterations_per_decade = 0;
    /**
     * The near-null space, column after column (ML reads it by pointer while
     * it builds the hierarchy).
     */
    std::vector<double> null_space;
    unsigned int        null_space_dimension = 0;
  };

  /**
   * The rows within `layers` neighbours of the rows marked in `rows` (one
   * entry per locally owned row of A, serial: column indices are row
   * indices), by A's sparsity pattern, breadth first; marked in place.
   */
  void mark_neighbours(const TrilinosWrappers::SparseMatrix &A,
                       std::vector<char>                    &rows,
                       const unsigned int                    layers);
} // namespace ContactStefan

#endif
