// The CHOLMOD path of LinearSolver: set-up, numeric factorisation, the row
// modifications of a factor when an active set changes a few rows, recall of
// kept factors and the solve (doc/algorithms.md §4).
#include <contact-stefan/linear_algebra/cholmod_factor.h>
#include <contact-stefan/linear_algebra/crs_rows.h>

#include <algorithm>
#include <stdexcept>

#include <Epetra_CrsMatrix.h>

namespace ContactStefan
{
  void LinearSolver::Cholmod::analyse(const bool               nested,
                                      const std::string       &name,
                                      const std::vector<char> &last)
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
    const int  n      = static_cast<int>(A->ncol);
    const auto marked =
      std::count_if(last.begin(), last.end(), [](const char c) { return c != 0; });
    front_last = !nested && static_cast<int>(last.size()) == n && marked > 0 && marked < n;
    if (front_last)
      {
        // The rows expected to change after all others: CAMD's constraint
        // sets 0 (the rest) and 1 (them), each ordered by approximate minimum
        // degree. A row replaced later then has its path to the root of the
        // elimination tree among them: the columns to update are those of
        // the front's band and the separators next to it, not most of the
        // factor (AMD's deep trees) or a path of nested dissection's
        // separators across the whole domain.
        std::vector<int> member(n), permutation(n);
        for (int i = 0; i < n; ++i)
          member[i] = last[i] != 0;
        if (cholmod_camd(A, nullptr, 0, member.data(), permutation.data(), &common))
          {
            common.nmethods           = 1;
            common.method[0].ordering = CHOLMOD_GIVEN;
            L = cholmod_analyze_p(A, permutation.data(), nullptr, 0, &common);
          }
        front_last = L != nullptr;
      }
    if (L == nullptr)
      {
        common.nmethods = nested ? 1 : 0;
        if (nested)
          common.method[0].ordering = CHOLMOD_METIS;
        L = cholmod_analyze(A, &common);
      }
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
    modified_since      = 0;
    const auto *perm    = static_cast<const int *>(L->Perm);
    factor_index.resize(n);
    for (int i = 0; i < n; ++i)
      factor_index[perm[i]] = i;
  }



  std::vector<int> LinearSolver::Cholmod::rows_to_replace(const std::vector<double> &old)
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



  double LinearSolver::Cholmod::replacement_work(const cholmod_factor *F, const std::vector<int> &rows, const double budget) const
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



  bool LinearSolver::Cholmod::replace_rows(cholmod_factor *F, const std::vector<int> &rows)
  {
    const int     n   = static_cast<int>(A->ncol);
    const double *now = static_cast<const double *>(A->x);
    if (row_pattern == nullptr)
      {
        row_pattern = cholmod_allocate_sparse(n, 1, n, false, true, 0, CHOLMOD_PATTERN, &common);
        row_values  = cholmod_allocate_sparse(n, 1, n, false, true, 0, CHOLMOD_REAL, &common);
        if (row_pattern == nullptr || row_values == nullptr)
          {
            if (row_pattern != nullptr)
              cholmod_free_sparse(&row_pattern, &common);
            if (row_values != nullptr)
              cholmod_free_sparse(&row_values, &common);
            return false;
          }
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
        cholmod->analyse(false, name, volatile_rows ? volatile_rows() : std::vector<char>());
      }
    else
      {
        // New values on the analysed pattern: a gather through the map built
        // with the pattern (no index lookups, no sorting).
        auto         *value  = static_cast<double *>(cholmod->A->x);
        const int    *target = cholmod->position_of_entry.data();
        std::size_t   entry  = 0;
        const CrsRows row_of(M);
        for (int r = 0; r < n; ++r)
          {
            int     length;
            double *values;
            int    *columns;
            row_of(r, length, values, columns);
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
    // (Until it succeeds, the factor names no values: a failure must not
    // leave it recallable or keepable under its old key.)
    cholmod->key = 0;
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
    ++statistics.cholmod_factorisations;
  }



  // A new ordering of the same pattern (nested dissection, or the rows in
  // `last` last) and A's values factorised on it. The kept factors are of the
  // old ordering and go with it: a set that recurs is factorised again (so the
  // factorisations counted depend on when the ordering changed, and can
  // differ from those of the Amesos path on several ranks).
  void LinearSolver::reorder_cholmod(const bool               nested,
                                     const std::vector<char> &last,
                                     const std::uint64_t      key)
  {
    try
      {
        cholmod->analyse(nested, name, last);
      }
    catch (...)
      {
        // (Nothing usable is left: the next update() starts afresh.)
        cholmod.reset();
        throw;
      }
    cholmod_numeric();
    cholmod->key = key;
    ++statistics.reorderings;
  }



  // The CHOLMOD path of update(): keep the current factor (if it has a key) and
  // factorise into the storage of the least recently used one once 'Kept
  // factorisations' are kept: all share the one symbolic analysis. Where
  // only a few rows changed against the current or a kept factor, that
  // factor's rows are replaced in place instead (Solver/Row update limit).
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
            // Where the caller names the rows that change next (a front that
            // has left the band ordered last at the last analysis), order
            // them last afresh: an analysis by CAMD costs about what AMD's
            // does, a few factorisations' worth less than nested dissection.
            // Not once such an ordering has served no modification (the rows
            // named were not those that changed: nested dissection below is
            // the remedy, for the rest of this pattern's life), nor when the
            // caller names no row or every row (nothing to order last).
            // (Only changes of fewer than a tenth of the rows count, as below:
            // a change of most rows is expensive on any ordering.)
            const bool local = 10 * rows.size() < cholmod->A->ncol;
            if (local && cholmod->front_last && cholmod->modified_since == 0)
              cholmod->front_last_failed = true;
            std::vector<char> last;
            if (local && volatile_rows && !cholmod->front_last_failed &&
                !cholmod->nested_dissection)
              last = volatile_rows();
            const auto named =
              std::count_if(last.begin(), last.end(), [](const char c) { return c != 0; });
            if (named > 0 && named < static_cast<long>(cholmod->A->ncol))
              {
                reorder_cholmod(false, last, key);
                return;
              }
            // A factorisation that row modifications could not replace:
            // AMD's elimination trees are deep, so each modified row costs
            // a path through most of the factor; nested dissection's are
            // shallow (the Stefan strip's column of 41 nodes: 2.3 times a
            // factorisation's flops with AMD, 0.22 with METIS). Reorder once
            // the factorisations so lost have cost what a nested-dissection
            // analysis costs (renting against buying). Only changes of fewer
            // than a tenth of the rows count: a new time step changes all.
            if (!cholmod->nested_dissection && prm.reordering_cost > 0 &&
                10 * rows.size() < cholmod->A->ncol)
              {
                cholmod->rejected_flops += cholmod->factorisation_flops;
                if (cholmod->rejected_flops >=
                    prm.reordering_cost * static_cast<double>(cholmod->n_values()))
                  {
                    reorder_cholmod(true, {}, key);
                    return;
                  }
              }
          }
      }
    // A modification is made in place of its base, which is given up: a copy
    // of the base, to keep it as well, cost about what the modification does
    // (the Stefan strip at nx = 400 took 15 % longer with the copies, although
    // they saved 93 of 277 factorisations by recall). Where the base is a kept
    // factor, the current one takes its place among the kept.
    if (base == -1 || base >= 0)
      {
        Cholmod::Factor base_factor;
        if (base == -1)
          base_factor = Cholmod::Factor{cholmod->L, std::move(cholmod->values), cholmod->unchecked};
        else
          {
            base_factor = std::move(kept[base].second);
            kept.erase(kept.begin() + base);
            if (prm.kept_factorisations > 0 && cholmod->key != 0)
              kept.insert(
                kept.begin(),
                {cholmod->key,
                 Cholmod::Factor{cholmod->L, std::move(cholmod->values), cholmod->unchecked}});
            else
              cholmod_free_factor(&cholmod->L, &cholmod->common);
          }
        cholmod->L         = base_factor.L;
        cholmod->values    = {};
        cholmod->key       = 0;
        cholmod->unchecked = false;
        if (cholmod->replace_rows(cholmod->L, rows))
          {
            const auto *value = static_cast<const double *>(cholmod->A->x);
            cholmod->values.assign(value, value + cholmod->n_values());
            // (No row to replace: the base factors these very values.)
            cholmod->unchecked = !rows.empty() || base_factor.unchecked;
            if (!rows.empty())
              {
                ++cholmod->modified_since;
                ++statistics.row_updates;
                statistics.replaced_rows += rows.size();
              }
          }
        else
          cholmod_numeric();
        cholmod->key = key;
        return;
      }
    // A factorisation afresh. Its storage: the current factor's (nothing is
    // kept), a new one (fewer than 'Kept factorisations' are kept), or the
    // least recently used kept one's; the current factor is kept.
    const bool      keep_current = prm.kept_factorisations > 0 && cholmod->key != 0;
    Cholmod::Factor storage;
    if (!keep_current)
      storage = Cholmod::Factor{cholmod->L, std::move(cholmod->values), cholmod->unchecked};
    else if (kept.size() >= prm.kept_factorisations)
      {
        storage = std::move(kept.back().second);
        kept.pop_back();
      }
    if (storage.L == nullptr)
      {
        // (New storage: a copy of the current factor, for its symbolic
        // analysis.) Copied before the current factor moves to the kept ones,
        // so that a failed copy leaves every factor with one owner.
        storage.L = cholmod_copy_factor(cholmod->L, &cholmod->common);
        if (storage.L == nullptr)
          throw std::runtime_error("cholmod could not copy a factor of the " + name +
                                   " matrix (out of memory?)");
      }
    if (keep_current)
      kept.insert(kept.begin(),
                  {cholmod->key,
                   Cholmod::Factor{cholmod->L, std::move(cholmod->values), cholmod->unchecked}});
    cholmod->L         = storage.L;
    cholmod->values    = {};
    cholmod->key       = 0;
    cholmod->unchecked = false;
    cholmod_numeric();
    cholmod->key = key;
  }



  // The CHOLMOD path of recall().
  bool LinearSolver::recall_cholmod(const std::uint64_t key)
  {
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



  // The CHOLMOD solve of solve().
  void LinearSolver::solve_cholmod(Vector &x, const Vector &b)
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
            const std::uint64_t key = cholmod->key;
            cholmod_numeric();
            cholmod->key = key; // the same values, now factorised
            solve_cholmod(x, b);
            return;
          }
      }
  }
} // namespace ContactStefan
