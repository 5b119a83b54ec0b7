#include <deal.II/lac/solver_cg.h>

#include <contact-stefan/linear_solver.h>

#include <cmath>
#include <stdexcept>

namespace ContactStefan
{
  using LinearSolverType = Parameters::Solver::LinearSolverType;

  LinearSolver::LinearSolver(const Parameters::Solver &parameters,
                             const unsigned int        verbosity,
                             const ConditionalOStream &pcout,
                             const std::string        &name)
    : prm(parameters)
    , verbosity(verbosity)
    , pcout(pcout)
    , name(name)
    , direct_control(1, 0)
  {}



  void LinearSolver::initialize(const TrilinosWrappers::SparseMatrix &A)
  {
    matrix = &A;
    // Nothing non-finite reaches Trilinos, whose error codes name nothing.
    if (!std::isfinite(A.linfty_norm()))
      throw std::runtime_error("the matrix of the " + name +
                               " system is not finite (overflow: are material values or the "
                               "time step extreme?)");
    try
      {
        if (prm.linear_solver == LinearSolverType::direct)
          {
            direct = std::make_unique<TrilinosWrappers::SolverDirect>(
              direct_control,
              TrilinosWrappers::SolverDirect::AdditionalData(verbosity >= 2,
                                                             prm.direct_solver_type));
            direct->initialize(A);
          }
        else
          {
            TrilinosWrappers::PreconditionAMG::AdditionalData data;
            data.elliptic = true;
            amg.initialize(A, data);
          }
      }
    catch (const std::exception &e)
      {
        throw std::runtime_error("the " + name + " system could not be " +
                                 (prm.linear_solver == LinearSolverType::direct ?
                                    "factorised by " + prm.direct_solver_type :
                                    std::string("preconditioned by AMG")) +
                                 " (a singular or badly scaled matrix?): " + one_line(e.what()));
      }
  }



  void LinearSolver::clear()
  {
    matrix = nullptr;
    direct.reset();
    amg.clear();
  }



  void LinearSolver::solve(Vector &x, const Vector &b)
  {
    if (matrix == nullptr)
      throw std::logic_error("LinearSolver::solve() before initialize()");
    // Nothing non-finite reaches Trilinos (whose error codes name nothing).
    check_finite(b, "the right-hand side of the " + name + " system");
    if (prm.linear_solver == LinearSolverType::direct)
      {
        direct->solve(x, b);
      }
    else
      {
        SolverControl    control(prm.cg_max_iterations, prm.cg_tolerance * b.l2_norm());
        SolverCG<Vector> cg(control);
        cg.solve(*matrix, x, b, amg);
        if (verbosity >= 2)
          pcout << "      CG (" << name << "): " << control.last_step() << " iterations"
                << std::endl;
      }
    check_finite(x, "the solution of the " + name + " system (overflow in the data?)");
  }
} // namespace ContactStefan
