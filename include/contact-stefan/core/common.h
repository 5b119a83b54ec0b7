// Small things every part of contact-stefan shares.
#ifndef contact_stefan_common_h
#define contact_stefan_common_h

#include <deal.II/base/index_set.h>
#include <deal.II/base/mpi.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/trilinos_vector.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ContactStefan
{
  using namespace dealii;

  /** The distributed vector of both fields (owned, or owned plus ghosts). */
  using Vector = TrilinosWrappers::MPI::Vector;

  /**
   * Four numbers per locally owned active cell, one per vertex, indexed by the
   * active cell index: how the two fields exchange the coupling data
   * (doc/coupling.md §3). Vertex v is the cell's v-th vertex and FE_Q(1) DoF.
   */
  using CellVertexValues = std::vector<std::array<double, 4>>;

  /**
   * Tolerances at the level of floating-point round-off (not parameters): a
   * quantity computed from terms of size s is exact to round_off_factor * eps * s.
   */
  constexpr double round_off_factor = 64;

  /**
   * A step's iteration that did not converge within its limit (the contact
   * step's active set, the fixed-point coupling, the enthalpy step's
   * relaxation). Thrown alike on every rank: each limit is tested on global
   * counts. Adaptive time steps redo such a step shorter
   * (doc/time_stepping.md); otherwise it ends the run with its message.
   */
  class StepNotConverged : public std::runtime_error
  {
  public:
    using std::runtime_error::runtime_error;
  };

  /**
   * A number for a message: 6 significant digits in any magnitude
   * (std::to_string prints 1e-9 as 0.000000).
   */
  inline std::string number(const double x)
  {
    std::ostringstream s;
    s << std::setprecision(6) << x;
    return s.str();
  }

  /**
   * The larger of a and b, NaN if either is NaN. (std::max(0., NaN) is 0: a NaN
   * error would read as no error.)
   */
  inline double max_with_nan(const double a, const double b)
  {
    return std::isnan(a) || std::isnan(b) ? std::numeric_limits<double>::quiet_NaN() :
                                            std::max(a, b);
  }

  /**
   * The maximum over all ranks, NaN if any rank has a NaN (MPI_MAX on a NaN is
   * implementation-defined).
   */
  inline double global_max_with_nan(const double local, const MPI_Comm mpi_communicator)
  {
    const bool any_nan = Utilities::MPI::max(std::isnan(local) ? 1 : 0, mpi_communicator) == 1;
    return any_nan ? std::numeric_limits<double>::quiet_NaN() :
                     Utilities::MPI::max(local, mpi_communicator);
  }

  // (A vector without ghosts stores its owned entries in order: the loops
  // below read them by local entry, not through the map's hash table, which
  // TrilinosWrappers' element access consults for every index.)

  /** Collective: max_i |a_i - b_i| over the owned entries of all ranks (NaN wins). */
  inline double max_difference(const Vector &a, const Vector &b)
  {
    double local = 0;
    if (!a.has_ghost_elements() && !b.has_ghost_elements())
      {
        AssertDimension(a.locally_owned_size(), b.locally_owned_size());
        const double *const x = a.trilinos_vector()[0], *const y = b.trilinos_vector()[0];
        for (std::size_t i = 0; i < a.locally_owned_size(); ++i)
          local = max_with_nan(local, std::abs(x[i] - y[i]));
      }
    else
      for (const auto i : a.locally_owned_elements())
        local = max_with_nan(local, std::abs(a[i] - b[i]));
    return global_max_with_nan(local, a.get_mpi_communicator());
  }

  /** Collective: max_i |a_i| over the owned entries of all ranks (a may have ghosts). */
  inline double max_abs(const Vector &a)
  {
    double local = 0;
    if (!a.has_ghost_elements())
      {
        const double *const x = a.trilinos_vector()[0];
        for (std::size_t i = 0; i < a.locally_owned_size(); ++i)
          local = max_with_nan(local, std::abs(x[i]));
      }
    else
      for (const auto i : a.locally_owned_elements())
        local = max_with_nan(local, std::abs(a[i]));
    return global_max_with_nan(local, a.get_mpi_communicator());
  }

  /**
   * Collective: throws std::runtime_error on every rank, naming `what`, if any
   * owned entry of v on any rank is not finite.
   */
  inline void check_finite(const Vector &v, const std::string &what)
  {
    unsigned int bad = 0;
    if (!v.has_ghost_elements())
      {
        const double *const x = v.trilinos_vector()[0];
        for (std::size_t i = 0; i < v.locally_owned_size(); ++i)
          bad += !std::isfinite(x[i]);
      }
    else
      for (const auto i : v.locally_owned_elements())
        bad += !std::isfinite(v[i]);
    bad = Utilities::MPI::sum(bad, v.get_mpi_communicator());
    if (bad > 0)
      throw std::runtime_error(what + " is not finite (" + std::to_string(bad) +
                               " entries are NaN or infinite)");
  }

  /**
   * Collective: if `message` is not empty on some rank, every rank throws
   * Exception(the message of the lowest such rank). A check that only some
   * ranks can make (it needs their cells) thus stops all of them alike.
   */
  template <typename Exception>
  void throw_collectively(const std::string &message, const MPI_Comm mpi_communicator)
  {
    const unsigned int none = Utilities::MPI::n_mpi_processes(mpi_communicator);
    const unsigned int first =
      Utilities::MPI::min(message.empty() ? none :
                                            Utilities::MPI::this_mpi_process(mpi_communicator),
                          mpi_communicator);
    if (first != none)
      throw Exception(Utilities::MPI::broadcast(mpi_communicator, message, first));
  }

  // Order-independent 64-bit fingerprints of what a matrix or a solve depends
  // on, so that a field can tell "nothing changed" without keeping copies.
  namespace Fingerprint
  {
    inline std::uint64_t mix(std::uint64_t key)
    {
      key ^= key >> 33;
      key *= 0xff51afd7ed558ccdULL;
      key ^= key >> 33;
      key *= 0xc4ceb9fe1a85ec53ULL;
      key ^= key >> 33;
      return key;
    }
    inline std::uint64_t bits(const double value)
    {
      std::uint64_t b;
      std::memcpy(&b, &value, sizeof b);
      return b;
    }
    /**
     * Two fingerprints (or a fingerprint and a number) into one. Each part is
     * mixed on its own first, so that changes of two parts cannot cancel (a
     * time step one ulp shorter and a version one higher would in a plain sum).
     */
    inline std::uint64_t combine(const std::uint64_t a, const std::uint64_t b)
    {
      return mix(mix(a) ^ (mix(b) + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2)));
    }
    /**
     * The owned constraint lines: pattern and coefficients, with the
     * inhomogeneities if asked. Collective; the same on every rank.
     */
    inline std::uint64_t constraints(const AffineConstraints<double> &constraints,
                                     const IndexSet                  &owned,
                                     const bool                       with_inhomogeneities,
                                     const MPI_Comm                   mpi_communicator)
    {
      std::uint64_t local = 0;
      for (const auto &line : constraints.get_lines())
        if (owned.is_element(line.index))
          {
            std::uint64_t h = mix(line.index + 1);
            for (const auto &[column, value] : line.entries)
              h = mix(h ^ mix(column + 7)) + mix(bits(value));
            if (with_inhomogeneities)
              h = mix(h + bits(line.inhomogeneity));
            local += h;
          }
      return Utilities::MPI::sum(local, mpi_communicator);
    }
    /** The owned entries of a vector, bit for bit. Collective. */
    inline std::uint64_t vector(const Vector &v)
    {
      // The k-th owned element is the k-th local entry (deal.II builds the
      // Epetra map from the index set in its order): no per-entry index
      // look-ups through Trilinos.
      std::uint64_t       local  = 0;
      const double *const values = v.trilinos_vector()[0];
      std::size_t         k      = 0;
      for (const auto i : v.locally_owned_elements())
        local += mix(mix(i + 3) + bits(values[k++]));
      return Utilities::MPI::sum(local, v.get_mpi_communicator());
    }
  } // namespace Fingerprint

  /**
   * The code is two-dimensional (plane strain or plane stress): the contact normals, the
   * rigid-body modes (2 translations, 1 rotation), the Voigt form of C, the
   * muparser variables "x,y,t" and the Gmsh reader's line/surface tags are
   * written for 2D. The classes keep deal.II's dim template parameter for its
   * API, and say so where they are instantiated.
   */
  template <int dim>
  constexpr void assert_two_dimensional()
  {
    static_assert(dim == 2,
                  "contact-stefan is a plane-strain (2D) code: normals, rigid modes, "
                  "the elasticity tensor in Voigt form and the parsed functions of "
                  "x, y, t are two-dimensional");
  }
} // namespace ContactStefan

#endif
