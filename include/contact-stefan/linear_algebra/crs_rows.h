// Row access to an Epetra matrix without a call per row: a deal.II
// TrilinosWrappers::SparseMatrix, once compressed, keeps its rows in
// compressed arrays (Epetra's optimised storage), and the loops that visit
// every row of a matrix at every solve (the enthalpy step's assembly, the
// gather of new values into CHOLMOD's copy) read them directly.
#ifndef contact_stefan_crs_rows_h
#define contact_stefan_crs_rows_h

#include <deal.II/base/exceptions.h>

#include <Epetra_CrsMatrix.h>

namespace ContactStefan
{
  /**
   * Row r of an Epetra matrix (local row and column indices): from its
   * compressed arrays where it keeps them, else through its row view. The
   * view does the same at the cost of a call with checks per row, which in the
   * Stefan strip's assembly was half the time of the loop.
   */
  class CrsRows
  {
  public:
    explicit CrsRows(const Epetra_CrsMatrix &matrix)
      : matrix(matrix)
    {
      if (!matrix.StorageOptimized() ||
          matrix.ExtractCrsDataPointers(offsets, indices, values) != 0)
        offsets = nullptr;
    }

    void operator()(const int r, int &n, double *&row_values, int *&row_indices) const
    {
      if (offsets == nullptr)
        {
          AssertThrow(matrix.ExtractMyRowView(r, n, row_values, row_indices) == 0,
                      dealii::ExcInternalError());
          return;
        }
      n           = offsets[r + 1] - offsets[r];
      row_values  = values + offsets[r];
      row_indices = indices + offsets[r];
    }

  private:
    const Epetra_CrsMatrix &matrix;
    int                    *offsets = nullptr, *indices = nullptr;
    double                 *values = nullptr;
  };
} // namespace ContactStefan

#endif
