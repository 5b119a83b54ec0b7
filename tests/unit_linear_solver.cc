// Unit test of the CHOLMOD path of LinearSolver when an active set changes
// some rows of the matrix: the factor modified row by row ('Solver/Row update
// limit') must solve like a fresh factorisation of the same values, pick the
// kept factor closest to the new values, fall back to a factorisation when
// too many rows change, reorder by nested dissection ('Solver/Reordering
// cost'), order the rows the caller names last ('Solver/Front layers ordered
// last'), and report a matrix that is not positive definite; and that CG on a
// kept AMG hierarchy stops at its budget and builds the hierarchy afresh.
//
// The matrix is the 5-point Laplacian on a 300 x 20 strip plus a small shift;
// "fixing" a node (as the enthalpy step fixes a node on a plateau) clears its
// row and column and puts a value on the diagonal, as AffineConstraints does.
#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>

#include <contact-stefan/linear_algebra/linear_solver.h>

#include <iostream>
#include <set>
#include <sstream>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  // A strip of mx x my nodes, like the Stefan strip's: a "column" is my nodes.
  constexpr unsigned int mx = 300, my = 20, n = mx * my;

  unsigned int node(const unsigned int i, const unsigned int j)
  {
    return j * my + i; // i: along the column, j: along the strip
  }

  // The grid matrix with the nodes in `fixed` cleared (diagonal `fixed_diagonal`)
  // and `extra` added to the diagonal of the nodes in `heavier`.
  void fill(TrilinosWrappers::SparseMatrix &A,
            const std::set<unsigned int>   &fixed,
            const double                    fixed_diagonal,
            const std::set<unsigned int>   &heavier = {},
            const double                    extra   = 0,
            const double                    scale   = 1)
  {
    A = 0;
    for (unsigned int i = 0; i < my; ++i)
      for (unsigned int j = 0; j < mx; ++j)
        {
          const unsigned int r = node(i, j);
          if (fixed.count(r))
            {
              A.set(r, r, fixed_diagonal);
              continue;
            }
          A.set(r, r, scale * (4.1 + (heavier.count(r) ? extra : 0.)));
          const int di[] = {-1, 1, 0, 0}, dj[] = {0, 0, -1, 1};
          for (unsigned int d = 0; d < 4; ++d)
            {
              const int ii = int(i) + di[d], jj = int(j) + dj[d];
              if (ii >= 0 && jj >= 0 && ii < int(my) && jj < int(mx) &&
                  !fixed.count(node(ii, jj)))
                A.set(r, node(ii, jj), -scale);
            }
        }
    A.compress(VectorOperation::insert);
  }

  // The nodes of columns 100-199: the third of the strip that the budget
  // scenarios make heavier.
  std::set<unsigned int> middle_third()
  {
    std::set<unsigned int> nodes;
    for (unsigned int i = 0; i < my; ++i)
      for (unsigned int j = 100; j < 200; ++j)
        nodes.insert(node(i, j));
    return nodes;
  }

  // CG + AMG forced, with `kept` hierarchies kept for recall.
  Parameters::LinearSolvers cg_amg_parameters(const Parameters::LinearSolvers &prm,
                                              const unsigned int               kept)
  {
    Parameters::LinearSolvers cg_prm = prm;
    cg_prm.linear_solver             = Parameters::LinearSolvers::LinearSolverType::cg_amg;
    cg_prm.kept_factorisations       = kept;
    return cg_prm;
  }

  // The largest difference between x and the solution of a fresh
  // factorisation of A's values, relative to the latter's size.
  double difference_to_fresh(const Parameters::LinearSolvers &prm,
                             const TrilinosWrappers::SparseMatrix &A,
                             const ContactStefan::Vector                         &b,
                             const ContactStefan::Vector                         &x)
  {
    Parameters::LinearSolvers fresh_prm = prm;
    fresh_prm.row_update_limit          = 0;
    fresh_prm.kept_factorisations       = 0;
    ConditionalOStream             silent(std::cout, false);
    TrilinosWrappers::SparseMatrix copy;
    copy.copy_from(A);
    LinearSolver fresh(fresh_prm,
                       0,
                       silent,
                       "fresh",
                       Parameters::LinearSolvers::AMGUpdate::recompute,
                       0.02,
                       2);
    fresh.initialize(copy);
    ContactStefan::Vector y(b);
    fresh.solve(y, b);
    ContactStefan::Vector d(x);
    d -= y;
    return d.linfty_norm() / y.linfty_norm();
  }
} // namespace

int main(int argc, char *argv[])
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  ParameterHandler prm_handler;
  Parameters::LinearSolvers::declare(prm_handler);
  Parameters::LinearSolvers prm;
  prm.parse(prm_handler);
  prm.linear_solver      = Parameters::LinearSolvers::LinearSolverType::direct;
  prm.direct_solver_type = "cholmod";

  const IndexSet         all = complete_index_set(n);
  DynamicSparsityPattern pattern(n, n);
  for (unsigned int i = 0; i < my; ++i)
    for (unsigned int j = 0; j < mx; ++j)
      for (int di = -1; di <= 1; ++di)
        for (int dj = -1; dj <= 1; ++dj)
          if (std::abs(di) + std::abs(dj) <= 1 && int(i) + di >= 0 && int(j) + dj >= 0 &&
              int(i) + di < int(my) && int(j) + dj < int(mx))
            pattern.add(node(i, j), node(i + di, j + dj));
  TrilinosWrappers::SparseMatrix A;
  A.reinit(all, all, pattern, MPI_COMM_WORLD);

  ContactStefan::Vector b(all, MPI_COMM_WORLD), x(all, MPI_COMM_WORLD);
  for (unsigned int r = 0; r < n; ++r)
    b[r] = 1. + 0.01 * (r % 7);
  b.compress(VectorOperation::insert);

  const auto column = [](const unsigned int j) {
    std::set<unsigned int> nodes;
    for (unsigned int i = 0; i < my; ++i)
      nodes.insert(node(i, j));
    return nodes;
  };

  // The scenarios: reordering at the first factorisation row modifications
  // could not replace, with modifications up to twice a factorisation's work
  // (so that most changes below are modifications on nested dissection), with
  // 2 kept factorisations and with none; and modifications whatever their
  // cost on CHOLMOD's own ordering (AMD: deep elimination trees, long paths).
  struct Scenario
  {
    std::string  name;
    unsigned int kept;
    double       limit, reordering_cost;
  };
  for (const Scenario &scenario : {Scenario{"reorder at once, 2 kept", 2, 2, 1e-9},
                                   Scenario{"reorder at once, none kept", 0, 2, 1e-9},
                                   Scenario{"always modify, never reorder", 2, 1e9, 0}})
    {
      std::printf("--- %s\n", scenario.name.c_str());
      prm.kept_factorisations = scenario.kept;
      prm.row_update_limit    = scenario.limit;
      prm.reordering_cost     = scenario.reordering_cost;
      const bool         always = scenario.limit > 100;
      ConditionalOStream silent(std::cout, false);
      LinearSolver       solver(prm,
                          0,
                          silent,
                          "test",
                          Parameters::LinearSolvers::AMGUpdate::recompute,
                          0.02,
                          2);
      // The solver's statistics summed over the scenario.
      LinearSolverStatistics total;
      const auto             counts = [&]() {
        total += solver.take_statistics();
        return total;
      };
      const auto print = [&](const std::string &what) {
        const LinearSolverStatistics c = counts();
        std::printf("  %s: %u factorisations, %u modified, %llu rows, %u reorderings\n",
                    what.c_str(),
                    c.cholmod_factorisations,
                    c.row_updates,
                    c.replaced_rows,
                    c.reorderings);
      };
      const auto same_as_fresh = [&](const std::string &what) {
        check(difference_to_fresh(prm, A, b, x) < 1e-12, what + ": solves as a fresh factorisation");
      };
      std::set<unsigned int> none;

      fill(A, none, 1.);
      solver.initialize(A, 1);
      solver.solve(x, b);
      print("initialize");
      check(counts().cholmod_factorisations == 1 && counts().row_updates == 0,
            "initialize factorises");

      // A column of nodes becomes fixed: on AMD's ordering its rows cost
      // more than twice a factorisation, so this factorises and reorders (or,
      // when forced, modifies); on nested dissection the next columns are
      // modifications.
      fill(A, column(5), 2.5);
      solver.update(A, 2);
      solver.solve(x, b);
      print("column 5 fixed");
      check(always ? (counts().row_updates == 1 && counts().replaced_rows == my &&
                      counts().reorderings == 0) :
                     (counts().cholmod_factorisations == 2 && counts().reorderings == 1),
            always ? "column 5: its rows replaced" : "column 5: reordered and factorised");
      same_as_fresh("column 5");

      const auto before_6 = counts();
      fill(A, column(6), 2.5);
      solver.update(A, 3);
      solver.solve(x, b);
      print("column 6 fixed instead");
      // From the current factor (2 columns): a modification gives its base
      // up (no earlier factor without fixed nodes is kept: the one of
      // 'initialize' was modified in place, or dropped by the reordering).
      check(counts().cholmod_factorisations == before_6.cholmod_factorisations &&
              counts().row_updates == before_6.row_updates + 1 &&
              counts().replaced_rows - before_6.replaced_rows == 2 * my,
            "column 6: rows replaced, from the current factor");
      same_as_fresh("column 6");

      // The set of column 5 again: the factor of column 5 was modified in
      // place into column 6's, so nothing is recalled and its rows are
      // replaced again; then column 6 again.
      const auto before_5 = counts();
      fill(A, column(5), 2.5);
      const bool recalled = solver.recall(2);
      if (!recalled)
        solver.update(A, 2);
      solver.solve(x, b);
      check(!recalled && counts().row_updates == before_5.row_updates + 1,
            "column 5 again: not recalled (modified in place), its rows replaced");
      same_as_fresh("column 5 again");
      fill(A, column(6), 2.5);
      if (!solver.recall(3))
        solver.update(A, 3);
      solver.solve(x, b);
      same_as_fresh("column 6 again");

      // Heavier diagonals on some fixed and some free nodes (a capacity change).
      const auto before_heavy = counts();
      fill(A, column(6), 3.5, {node(3, 6), node(2, 21), node(19, 299)}, 0.7);
      solver.update(A, 4);
      solver.solve(x, b);
      print("changed diagonals");
      check(counts().cholmod_factorisations == before_heavy.cholmod_factorisations &&
              counts().replaced_rows - before_heavy.replaced_rows == my + 2,
            "changed diagonals: only those rows replaced");
      same_as_fresh("changed diagonals");

      // The same values under a new key: nothing to replace.
      const auto before_same = counts();
      solver.update(A, 5);
      solver.solve(x, b);
      check(counts().cholmod_factorisations == before_same.cholmod_factorisations &&
              counts().replaced_rows == before_same.replaced_rows,
            "unchanged values: no rows replaced, no factorisation");
      same_as_fresh("unchanged values");

      // Every value changed: a factorisation (unless forced).
      const auto before_all = counts();
      fill(A, none, 1., {}, 0., 2.);
      solver.update(A, 6);
      solver.solve(x, b);
      print("every value changed");
      check(always ? counts().replaced_rows - before_all.replaced_rows == n :
                     counts().cholmod_factorisations == before_all.cholmod_factorisations + 1,
            always ? "every value changed: every row replaced" :
                     "every value changed: factorised afresh");
      same_as_fresh("every value changed");

      // A factorisation afresh keeps the factor it replaces, where factors
      // are kept: the values before it are recalled, with no work.
      fill(A, column(6), 3.5, {node(3, 6), node(2, 21), node(19, 299)}, 0.7);
      const auto before_recall = counts();
      const bool recalled_5    = solver.recall(5);
      if (!recalled_5)
        solver.update(A, 5);
      solver.solve(x, b);
      const bool keeps = scenario.kept > 0 && !always;
      check(recalled_5 == keeps &&
              (!keeps || (counts().cholmod_factorisations == before_recall.cholmod_factorisations &&
                          counts().row_updates == before_recall.row_updates)),
            std::string("the values before a fresh factorisation again: ") +
              (keeps ? "recalled" : "not kept"));
      same_as_fresh("the values before a fresh factorisation again");

      // A front marching 60 columns along the strip and back, a column per
      // update, stays accurate.
      double     worst        = 0;
      const auto before_march = counts();
      for (unsigned int sweep = 0; sweep < 120; ++sweep)
        {
          const unsigned int j = sweep < 60 ? 100 + sweep : 219 - sweep;
          fill(A, column(j), 2., {}, 0., 2.);
          solver.update(A, 100 + sweep);
          solver.solve(x, b);
          worst = std::max(worst, difference_to_fresh(prm, A, b, x));
        }
      print("front marched 120 columns");
      check(always ? counts().cholmod_factorisations == before_march.cholmod_factorisations :
                     counts().row_updates - before_march.row_updates >= 40,
            always ? "a front marching 120 columns: no factorisation" :
                     "a front marching 120 columns: at least 40 modifications");
      check(worst < 1e-11, "... every solve as a fresh factorisation's to 1e-11");

      // A change that makes the matrix indefinite is reported, not solved.
      fill(A, none, 1., {node(5, 10)}, -10., 2.);
      bool reported = false;
      try
        {
          solver.update(A, 7);
        }
      catch (const std::exception &e)
        {
          reported = std::string(e.what()).find("not positive definite") != std::string::npos;
        }
      check(reported, "an indefinite change: 'not positive definite'");
    }
  // The rows about a front ordered last (LinearSolver::set_volatile_rows, as
  // the enthalpy step does with 'Solver/Front layers ordered last'): the
  // columns within 2 of the front's. A front marching 40 columns is then
  // mostly row modifications at the end of the factor, with a new ordering
  // each time it has left the band; without the rows named, on CHOLMOD's own
  // ordering (and no nested dissection), every step factorises.
  prm.kept_factorisations = 2;
  prm.row_update_limit    = 0.5;
  prm.reordering_cost     = 0;
  const auto band         = [&](const unsigned int front) {
    std::vector<char> rows(n, 0);
    for (unsigned int j = front - 2; j <= front + 2; ++j)
      for (unsigned int i = 0; i < my; ++i)
        rows[node(i, j)] = 1;
    return rows;
  };
  // Column 100 fixed, then the front (`front`, which the solver's callback
  // reads) marching to column 140, a column per update. Returns the largest
  // difference of a solve to a fresh factorisation's; the statistics of the
  // first 20 columns go to at_20, the rest stay in the solver.
  const auto march = [&](LinearSolver &solver, unsigned int &front, LinearSolverStatistics &at_20) {
    front = 100;
    fill(A, column(front), 2.);
    solver.initialize(A, 1);
    solver.solve(x, b);
    double worst = difference_to_fresh(prm, A, b, x);
    for (unsigned int step = 1; step <= 40; ++step)
      {
        front = 100 + step;
        fill(A, column(front), 2.);
        solver.update(A, 1 + step);
        solver.solve(x, b);
        worst = std::max(worst, difference_to_fresh(prm, A, b, x));
        if (step == 20)
          at_20 = solver.take_statistics();
      }
    return worst;
  };
  ConditionalOStream silent(std::cout, false);
  for (const bool named : {true, false})
    {
      std::printf("--- front ordered last: %s\n", named ? "rows named" : "rows not named");
      LinearSolver solver(
        prm, 0, silent, "test", Parameters::LinearSolvers::AMGUpdate::recompute, 0.02, 2);
      unsigned int front = 100, asked = 0;
      if (named)
        solver.set_volatile_rows([&]() {
          ++asked;
          return band(front);
        });
      LinearSolverStatistics c;
      const double           worst = march(solver, front, c);
      c += solver.take_statistics();
      std::printf("  %u factorisations, %u modified, %llu rows, %u reorderings, asked %u times\n",
                  c.cholmod_factorisations,
                  c.row_updates,
                  c.replaced_rows,
                  c.reorderings,
                  asked);
      if (named)
        {
          check(c.row_updates >= 30 && c.cholmod_factorisations == 1 + c.reorderings &&
                  c.reorderings >= 1,
                "rows named: mostly modifications, a new ordering as the front leaves its band");
          check(asked == 1 + c.reorderings, "... the rows asked for at every analysis");
        }
      else
        check(c.cholmod_factorisations == 41 && c.row_updates == 0,
              "rows not named: every step factorises (AMD's paths are too long)");
      check(worst < 1e-11, "... every solve as a fresh factorisation's to 1e-11");
    }

  // Rows named that are all the rows, or none (from the start, or from the
  // middle of a march on): CHOLMOD's own ordering, and no reordering for them.
  for (const std::string naming : {"every row", "no row", "no row after 20 columns"})
    {
      LinearSolver solver(
        prm, 0, silent, "test", Parameters::LinearSolvers::AMGUpdate::recompute, 0.02, 2);
      unsigned int front = 100;
      solver.set_volatile_rows([&]() {
        if (naming == "no row after 20 columns" && front < 120)
          return band(front);
        return std::vector<char>(n, naming == "every row" ? 1 : 0);
      });
      LinearSolverStatistics at_20;
      const double                 worst = march(solver, front, at_20);
      const LinearSolverStatistics c = solver.take_statistics();
      std::printf("  %s named: %u reorderings in the first 20 columns, %u after\n",
                  naming.c_str(),
                  at_20.reorderings,
                  c.reorderings);
      check(c.reorderings == 0 && (naming != "no row after 20 columns" || at_20.reorderings >= 1),
            naming + " named: no reordering for it");
      check(worst < 1e-11, "... every solve as a fresh factorisation's to 1e-11");
    }

  // The iterative path's budget for a kept AMG hierarchy ('AMG update' =
  // reuse, no reuse limit): after a change of a few rows CG runs on the kept
  // hierarchy as before; after a change that the kept hierarchy preconditions
  // badly (4000 added to the diagonal of a third of the strip, about a
  // thousand times its own: a large capacity term where the rest has none,
  // as nodes that leave a plateau would get) CG stops at its budget (three
  // times what the rebuild check tolerates per decade), builds the hierarchy
  // afresh and goes on from its iterate. Either way the solution is the direct solver's. The same
  // with 'AMG update' = recompute, whose hierarchy keeps its aggregates and is
  // recomputed for the new values.
  {
    std::ostringstream                 log;
    ConditionalOStream                 logged(log, true);
    const Parameters::LinearSolvers    cg_prm = cg_amg_parameters(prm, 0);
    const std::set<unsigned int>       none;
    const std::set<unsigned int>       heavy = middle_third();
    for (const auto update : {Parameters::LinearSolvers::AMGUpdate::reuse,
                              Parameters::LinearSolvers::AMGUpdate::recompute})
      {
        const std::string what =
          update == Parameters::LinearSolvers::AMGUpdate::reuse ? "kept" : "recomputed";
        LinearSolver solver(cg_prm, 1, logged, "test", update, 0.02, 2);
        fill(A, none, 1.);
        solver.initialize(A, 1);
        x = 0;
        solver.solve(x, b);
        const LinearSolverStatistics first = solver.take_statistics();
        check(first.amg_builds == 1 && first.cg_solves == 1, what + ": one build, one solve");

        fill(A, none, 1., {node(5, 10), node(6, 10)}, 1.);
        solver.update(A, 2);
        solver.solve(x, b);
        const LinearSolverStatistics small = solver.take_statistics();
        check(small.amg_builds == 0 && small.cg_solves == 1,
              what + ": two rows changed: no build");
        check(difference_to_fresh(prm, A, b, x) < 1e-9, "... solves as a direct solve to 1e-9");

        fill(A, none, 1., heavy, 4000.);
        log.str("");
        solver.update(A, 3);
        const LinearSolverStatistics updated = solver.take_statistics();
        solver.solve(x, b);
        const LinearSolverStatistics heavier = solver.take_statistics();
        std::printf("  %s: %u recomputations in the update, %u builds in the solve\n",
                    what.c_str(),
                    updated.amg_recomputations,
                    heavier.amg_builds);
        check(updated.amg_builds == 0 && heavier.amg_builds == 1 && heavier.cg_solves == 1 &&
                log.str().find("over its budget") != std::string::npos,
              what + ": a third of the strip heavier: over the budget, one build within the "
                     "solve");
        check(difference_to_fresh(prm, A, b, x) < 1e-9, "... solves as a direct solve to 1e-9");
      }
  }

  // Hierarchies kept for recall ('AMG update' = recompute, 'Kept
  // factorisations' = 2), as the enthalpy step uses them: the hierarchy of
  // the first values (key 1) is borrowed (as the enthalpy step's loose
  // solves borrow it) for the heavy diagonal above (key 2), which goes over
  // its budget and builds afresh. The first one must then be kept, not
  // dropped: recall(1) finds it without a build, and recall(2) finds the
  // fresh one, current or kept, without a build (before the fix of recall()
  // a recall of the current hierarchy's own values missed it, and the update
  // after it kept two hierarchies of key 2).
  {
    std::ostringstream                 log;
    ConditionalOStream                 logged(log, true);
    const Parameters::LinearSolvers    cg_prm = cg_amg_parameters(prm, 2);
    const std::set<unsigned int>       none;
    const std::set<unsigned int>       heavy = middle_third();
    LinearSolver solver(
      cg_prm, 1, logged, "test", Parameters::LinearSolvers::AMGUpdate::recompute, 0.02, 2);
    fill(A, none, 1.);
    solver.initialize(A, 1);
    x = 0;
    solver.solve(x, b);
    solver.take_statistics();

    fill(A, none, 1., heavy, 4000.);
    log.str("");
    check(solver.borrow_preconditioner(A, 2),
          "kept for recall: the hierarchy of key 1 borrowed for key 2");
    solver.solve(x, b);
    const LinearSolverStatistics borrowed = solver.take_statistics();
    check(borrowed.amg_builds == 1 && log.str().find("over its budget") != std::string::npos,
          "kept for recall: the borrowed solve over its budget, one build within it");
    check(difference_to_fresh(prm, A, b, x) < 1e-9, "... solves as a direct solve to 1e-9");
    check(solver.recall(2),
          "kept for recall: recall(2) right after finds the hierarchy just built");

    // Back and forth between the two values, each recalled without a build
    // and solved within its budget.
    for (const unsigned int key : {1u, 2u, 1u})
      {
        if (key == 1)
          fill(A, none, 1.);
        else
          fill(A, none, 1., heavy, 4000.);
        log.str("");
        const bool recalled = solver.recall(key);
        x = 0;
        solver.solve(x, b);
        const LinearSolverStatistics c = solver.take_statistics();
        std::printf("  kept for recall: recall(%u) %s, %u builds, %u recomputations\n",
                    key,
                    recalled ? "found" : "missed",
                    c.amg_builds,
                    c.amg_recomputations);
        check(recalled && c.amg_builds == 0 && c.amg_recomputations == 0 &&
                log.str().find("over its budget") == std::string::npos,
              "kept for recall: recall(" + std::to_string(key) +
                ") without a build, within the budget");
        check(difference_to_fresh(prm, A, b, x) < 1e-9, "... solves as a direct solve to 1e-9");
      }
    check(!solver.recall(3), "kept for recall: nothing kept under a key never used");
  }
  return UnitTest::finish();
}
