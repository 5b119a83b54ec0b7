// The CHOLMOD path of LinearSolver (linear_solver_cholmod.cc): the matrix in
// CHOLMOD's storage, its factor and the kept factors of earlier values, and
// the row modifications that turn one factor into another's (Solver/Row update
// limit, Solver/Reordering cost). Private to the linear_algebra layer.
#ifndef contact_stefan_cholmod_factor_h
#define contact_stefan_cholmod_factor_h

#include <contact-stefan/linear_algebra/linear_solver.h>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <cholmod.h>

namespace ContactStefan
{
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
    // whether the ordering is nested dissection or puts the caller's
    // volatile rows last (LinearSolver::set_volatile_rows), the flops of the
    // factorisations on this analysis that were too expensive as row
    // modifications (Solver/Reordering cost), and how many factors of this
    // analysis were modified row by row.
    double       factorisation_flops = 0;
    bool         nested_dissection   = false;
    bool         front_last          = false;
    bool         front_last_failed   = false; // an ordering of the named rows served nothing
    double       rejected_flops      = 0;
    unsigned int modified_since      = 0;
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
    // (AMD on our matrices), nested dissection by METIS, or (not nested, some
    // but not all rows marked in `last`, one entry per unknown) CAMD with the
    // marked rows after all others.
    void analyse(const bool nested, const std::string &name, const std::vector<char> &last = {});

    std::size_t n_values() const
    {
      return static_cast<std::size_t>(static_cast<const int *>(A->p)[A->ncol]);
    }

    // The rows (unknowns) whose row and column must be replaced to turn the
    // matrix with values `old` into A: every row whose diagonal changed, and
    // for each other changed entry (i, j) one of i and j (the one with more
    // changed entries). A changed entry of a row that becomes a constraint
    // (its row and column cleared) is covered by that row alone.
    std::vector<int> rows_to_replace(const std::vector<double> &old);

    // Estimated flops of replacing these rows in factor F (a deletion and an
    // addition each, each a rank-one update of the columns on the row's path
    // to the root of the elimination tree, about 4 flops per entry), counted
    // only up to `budget`.
    double replacement_work(const cholmod_factor *F, const std::vector<int> &rows, const double budget) const;

    // Replace the rows in factor F (which factors the values the rows were
    // found against) by those of A: delete them all, then add them back one by
    // one with the entries of A towards the rows already present. Every
    // intermediate matrix is a principal submatrix of A or of the old matrix
    // bordered by the identity, so positive definite when they are. False if
    // CHOLMOD failed or a pivot is not positive (F must then be factorised afresh).
    bool replace_rows(cholmod_factor *F, const std::vector<int> &rows);
  };
} // namespace ContactStefan

#endif
