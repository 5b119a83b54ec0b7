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

#include <contact-stefan/common.h>
#include <contact-stefan/parameters.h>

#include <memory>
#include <string>
#include <vector>

namespace ContactStefan
{
  class LinearSolver
  {
  public:
    // name: which system, for messages ("enthalpy", "elasticity").
    LinearSolver(const Parameters::Solver &parameters,
                 const unsigned int        verbosity,
                 const ConditionalOStream &pcout,
                 const std::string        &name);

    // The near-null space the AMG hierarchy is built for: vectors over the
    // locally owned rows in their order (elasticity: the rigid-body modes; ML's
    // default, the constant, only fits a scalar operator). Empty: the default.
    void set_near_null_space(std::vector<std::vector<double>> modes);
    // Factorise A, or build the AMG hierarchy of A. A must stay alive and
    // unchanged until the next initialize().
    void initialize(const TrilinosWrappers::SparseMatrix &A);
    // A's values changed in place on a few rows (a new active set): the
    // direct solver refactorises, but an AMG hierarchy built for an earlier
    // state of the same matrix object is kept as the preconditioner (its finest
    // level reads A itself, so CG and the smoother see the new values; the
    // coarse levels are those of the earlier state). Returns whether anything
    // was factorised or built.
    bool update(const TrilinosWrappers::SparseMatrix &A);
    // Whether the last initialize()/update() chose the direct solver (the
    // choice of 'automatic' depends on the size of the system).
    bool is_direct() const
    {
      return use_direct;
    }
    // Solve A x = b with the matrix of the last initialize(); CG (warm
    // started from x) reduces the residual to relative_tolerance ||b||
    // ('Solver/CG tolerance' if 0).
    void solve(Vector &x, const Vector &b, const double relative_tolerance = 0);
    // Forget the matrix (its owner is about to reinit or destroy it): a solve()
    // before the next initialize() is then an error, not a use of freed memory.
    void clear();

  private:
    const Parameters::Solver                       &prm;
    const unsigned int                              verbosity;
    const ConditionalOStream                       &pcout;
    const std::string                               name;
    const TrilinosWrappers::SparseMatrix           *matrix     = nullptr;
    bool                                            use_direct = true; // of the last initialize()
    SolverControl                                   direct_control;
    std::unique_ptr<TrilinosWrappers::SolverDirect> direct;
    TrilinosWrappers::PreconditionAMG               amg;
    bool                                            amg_built = false;
    // The near-null space, column after column (ML reads it by pointer while
    // it builds the hierarchy).
    std::vector<double> null_space;
    unsigned int        null_space_dimension = 0;
  };
} // namespace ContactStefan

#endif
