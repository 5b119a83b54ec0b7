// Mesh adaptation: which cells to refine and coarsen, and how to keep contact
// interfaces conforming while doing so (doc/adaptivity.md).
//
// CoupledProblem owns the time loop and the state transfer; this file holds the
// pieces that only look at the mesh:
//
//   FeatureCloud             the phase-front and contact points of all ranks,
//                            and which cells lie within a buffer of them (a
//                            pure kernel with unit tests, tests/unit_adaptation.cc)
//   mark_cells()             the indicator-based flags (Kelly jumps of the
//                            temperature and the displacement, fixed fraction or
//                            fixed number), the feature flags on top, the level
//                            limits and the cell cap
//   make_interfaces_conforming()   refine flags propagated across contact
//                            interfaces (both bodies refined alike), coarsening
//                            next to an interface withheld
//   nonconforming_interface_cells()  the cells to refine if the mesh smoothing of
//                            p4est still refined one side only (a repair round)
#ifndef contact_stefan_mesh_adaptation_h
#define contact_stefan_mesh_adaptation_h

#include <deal.II/base/point.h>

#include <deal.II/distributed/tria.h>

#include <deal.II/lac/vector.h>

#include <deal.II/numerics/rtree.h>

#include <contact-stefan/mesh/refinement_parameters.h>

#include <string>
#include <vector>

namespace ContactStefan
{
  /**
   * The points around which cells are refined: centres of cells that carry a
   * phase front, positions of nodes in contact. Every rank holds the points of
   * all ranks, so that a buffer reaches across rank boundaries whatever its
   * width (a ghost layer is one cell wide).
   */
  template <int dim>
  class FeatureCloud
  {
  public:
    /** Collective: gathers the local points of every rank. */
    FeatureCloud(const std::vector<Point<dim>> &local_points, const MPI_Comm comm);
    /** Serial (the unit tests). */
    explicit FeatureCloud(const std::vector<Point<dim>> &all_points);

    bool empty() const
    {
      return points.empty();
    }
    std::size_t size() const
    {
      return points.size();
    }
    /** The distance from p to the nearest point (infinity if there is none). */
    double distance(const Point<dim> &p) const;
    /**
     * Whether a cell with this centre and diameter lies within `buffer` cells
     * of a point: distance <= (buffer + 1/2) diameter. A cell that contains a
     * point is within 0 cells of it (its centre is at most half a diameter
     * away); with buffer k every cell up to k cells away in any direction
     * joins it (k sqrt(2) widths = k diameters), and along the axes a few more
     * (k = 1 on a square mesh: the cells two across, 2 < 1.5 sqrt(2) widths).
     */
    bool within(const Point<dim> &centre, const double diameter, const unsigned int buffer) const;
    /** Whether a point lies within `radius` of p (the bounding box first). */
    bool near(const Point<dim> &p, const double radius) const;

  private:
    void build();

    std::vector<Point<dim>> points;
    RTree<Point<dim>>       tree;
    /**
     * The bounding box of the points: most cells of a mesh are farther from it
     * than any buffer, and are answered without a query of the tree.
     */
    Point<dim> lower, upper;
  };

  /** What mark_cells() was given and what it decided, for the statistics. */
  struct AdaptationReport
  {
    unsigned int feature_cells = 0;     // owned cells within a buffer of a front or contact point
    unsigned int refine        = 0;     // cells flagged for refinement (all ranks)
    unsigned int coarsen       = 0;     // cells flagged for coarsening (all ranks)
    bool         capped        = false; // indicator flags dropped for 'Max cells'
  };

  /**
   * Sets refine/coarsen flags on the locally owned cells. indicator: per
   * active cell (zero on cells that are not owned), already weighted;
   * features: cells near them are refined to max_level and never coarsened.
   */
  template <int dim>
  AdaptationReport mark_cells(parallel::distributed::Triangulation<dim> &triangulation,
                              const Parameters::Refinement              &prm,
                              const dealii::Vector<float>               &indicator,
                              const FeatureCloud<dim>                   &fronts,
                              const FeatureCloud<dim>                   &contacts);

  /**
   * Propagates refine flags across interfaces between bodies (faces whose two
   * cells have different material ids) until both sides of every interface
   * face are flagged alike, clears coarsen flags next to interfaces, and runs
   * the triangulation's own flag smoothing, repeated until nothing changes.
   * Collective. The node-to-node contact pairs of MechanicalField need the
   * same vertices on both sides of an interface.
   */
  template <int dim>
  void make_interfaces_conforming(parallel::distributed::Triangulation<dim> &triangulation);

  /**
   * After a refinement: flags (for refinement) the owned cells at an interface
   * whose neighbour across it is refined, and returns their number over all
   * ranks (0: the mesh is conforming at every interface). p4est's 2:1 balance
   * can refine cells that carried no flag, on one side only.
   */
  template <int dim>
  unsigned int
  flag_nonconforming_interface_cells(parallel::distributed::Triangulation<dim> &triangulation);
} // namespace ContactStefan

#endif
