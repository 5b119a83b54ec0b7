// Marking and interface conformity of the adaptive mesh (mesh_adaptation.h,
// doc/adaptivity.md).
#include <deal.II/base/mpi.h>

#include <deal.II/distributed/grid_refinement.h>

#include <deal.II/grid/grid_tools.h>

#include <contact-stefan/mesh/mesh_adaptation.h>

#include <limits>

namespace ContactStefan
{
  template <int dim>
  FeatureCloud<dim>::FeatureCloud(const std::vector<Point<dim>> &local_points, const MPI_Comm comm)
  {
    std::vector<double> coordinates;
    for (const auto &p : local_points)
      for (unsigned int d = 0; d < dim; ++d)
        coordinates.push_back(p[d]);
    for (const auto &rank : Utilities::MPI::all_gather(comm, coordinates))
      for (std::size_t i = 0; i + dim <= rank.size(); i += dim)
        {
          Point<dim> p;
          for (unsigned int d = 0; d < dim; ++d)
            p[d] = rank[i + d];
          points.push_back(p);
        }
    build();
  }



  template <int dim>
  FeatureCloud<dim>::FeatureCloud(const std::vector<Point<dim>> &all_points)
    : points(all_points)
  {
    build();
  }



  template <int dim>
  void FeatureCloud<dim>::build()
  {
    tree = pack_rtree(points);
    for (unsigned int d = 0; d < dim; ++d)
      {
        lower[d] = std::numeric_limits<double>::infinity();
        upper[d] = -std::numeric_limits<double>::infinity();
      }
    for (const auto &p : points)
      for (unsigned int d = 0; d < dim; ++d)
        {
          lower[d] = std::min(lower[d], p[d]);
          upper[d] = std::max(upper[d], p[d]);
        }
  }



  template <int dim>
  double FeatureCloud<dim>::distance(const Point<dim> &p) const
  {
    if (points.empty())
      return std::numeric_limits<double>::infinity();
    std::vector<Point<dim>> nearest;
    tree.query(boost::geometry::index::nearest(p, 1), std::back_inserter(nearest));
    return p.distance(nearest.front());
  }



  template <int dim>
  bool FeatureCloud<dim>::within(const Point<dim>  &centre,
                                 const double       diameter,
                                 const unsigned int buffer) const
  {
    // The relative slack only keeps a point exactly on the rim (a node at a
    // cell's corner is half a diameter from its centre) inside.
    return near(centre, (buffer + 0.5) * diameter * (1 + 1e-10));
  }



  template <int dim>
  bool FeatureCloud<dim>::near(const Point<dim> &p, const double radius) const
  {
    for (unsigned int d = 0; d < dim; ++d)
      if (p[d] < lower[d] - radius || p[d] > upper[d] + radius)
        return false;
    return distance(p) <= radius;
  }



  template <int dim>
  AdaptationReport mark_cells(parallel::distributed::Triangulation<dim> &triangulation,
                              const Parameters::Refinement              &prm,
                              const dealii::Vector<float>               &indicator,
                              const FeatureCloud<dim>                   &fronts,
                              const FeatureCloud<dim>                   &contacts)
  {
    const MPI_Comm   comm = triangulation.get_communicator();
    AdaptationReport report;

    // 1. The indicator. A mesh whose indicator vanishes everywhere (a uniform
    // state) is left alone rather than refined by rank order.
    const double largest = Utilities::MPI::max(indicator.linfty_norm(), comm);
    if (largest > 0)
      {
        if (prm.strategy == Parameters::Refinement::Strategy::fixed_fraction)
          parallel::distributed::GridRefinement::refine_and_coarsen_fixed_fraction(
            triangulation, indicator, prm.refine_fraction, prm.coarsen_fraction);
        else
          parallel::distributed::GridRefinement::refine_and_coarsen_fixed_number(
            triangulation, indicator, prm.refine_fraction, prm.coarsen_fraction, prm.max_cells);
      }

    // 2. The level limits, then 3. the features: refined to the maximum level,
    // never coarsened.
    std::vector<bool> feature(triangulation.n_active_cells(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          if (static_cast<unsigned int>(cell->level()) >= prm.max_level)
            cell->clear_refine_flag();
          if (static_cast<unsigned int>(cell->level()) <= prm.min_level)
            cell->clear_coarsen_flag();
          const bool near = fronts.within(cell->center(), cell->diameter(), prm.front_buffer) ||
                            contacts.within(cell->center(), cell->diameter(), prm.contact_buffer);
          if (!near)
            continue;
          feature[cell->active_cell_index()] = true;
          ++report.feature_cells;
          cell->clear_coarsen_flag();
          if (static_cast<unsigned int>(cell->level()) < prm.max_level)
            cell->set_refine_flag();
        }
    report.feature_cells = Utilities::MPI::sum(report.feature_cells, comm);

    // 4. The cap: a refined cell becomes four, a coarsened family of four one
    // (counted as 3/4 per flagged cell, an estimate: the smoothing may keep some
    // families). Indicator flags go first, feature flags only if they alone
    // exceed the cap.
    const auto count = [&]() {
      unsigned int refine = 0, coarsen = 0;
      for (const auto &cell : triangulation.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            // (refine_flag_set() is a RefinementCase: 3 for isotropic)
            refine += cell->refine_flag_set() ? 1 : 0;
            coarsen += cell->coarsen_flag_set() ? 1 : 0;
          }
      report.refine  = Utilities::MPI::sum(refine, comm);
      report.coarsen = Utilities::MPI::sum(coarsen, comm);
      return triangulation.n_global_active_cells() + 3. * report.refine - 0.75 * report.coarsen;
    };
    for (const bool drop_features : {false, true})
      if (count() > prm.max_cells)
        {
          report.capped = true;
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->is_locally_owned() && (drop_features || !feature[cell->active_cell_index()]))
              cell->clear_refine_flag();
        }
    count();
    return report;
  }



  namespace
  {
    // Whether a face of a cell separates two bodies (an interface).
    template <int dim>
    bool across_interface(const typename Triangulation<dim>::active_cell_iterator &cell,
                          const unsigned int                                       face)
    {
      return !cell->face(face)->at_boundary() &&
             cell->neighbor(face)->material_id() != cell->material_id();
    }
  } // namespace



  template <int dim>
  void make_interfaces_conforming(parallel::distributed::Triangulation<dim> &triangulation)
  {
    const MPI_Comm comm = triangulation.get_communicator();
    // Each round adds flags only (refine flags set, coarsen flags cleared), so
    // the loop ends; the bound guards against a smoothing that undoes them.
    for (unsigned int round = 0; round < 100; ++round)
      {
        bool changed = false;
        // The refine flags of the ghost cells, from their owners.
        std::vector<char> ghost_refine(triangulation.n_active_cells(), 0);
        using Iterator = typename parallel::distributed::Triangulation<dim>::active_cell_iterator;
        GridTools::exchange_cell_data_to_ghosts<char, parallel::distributed::Triangulation<dim>>(
          triangulation,
          [](const Iterator &cell) -> std_cxx17::optional<char> {
            return char(cell->refine_flag_set() ? 1 : 0);
          },
          [&](const Iterator &cell, const char &flag) {
            ghost_refine[cell->active_cell_index()] = flag;
          });
        for (const auto &cell : triangulation.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned int face : cell->face_indices())
              if (across_interface<dim>(cell, face))
                {
                  if (cell->coarsen_flag_set())
                    {
                      cell->clear_coarsen_flag();
                      changed = true;
                    }
                  const auto neighbor = cell->neighbor(face);
                  if (neighbor->has_children())
                    continue; // finer already: flag_nonconforming_interface_cells()
                  const bool neighbor_refines = neighbor->is_locally_owned() ?
                                                  neighbor->refine_flag_set() :
                                                  ghost_refine[neighbor->active_cell_index()];
                  if (neighbor_refines && !cell->refine_flag_set() &&
                      neighbor->level() == cell->level())
                    {
                      cell->set_refine_flag();
                      changed = true;
                    }
                }
        changed = triangulation.prepare_coarsening_and_refinement() || changed;
        if (!Utilities::MPI::logical_or(changed, comm))
          return;
      }
    throw std::runtime_error("the refinement flags at the contact interfaces did not settle in "
                             "100 rounds of propagation and mesh smoothing");
  }



  template <int dim>
  unsigned int
  flag_nonconforming_interface_cells(parallel::distributed::Triangulation<dim> &triangulation)
  {
    unsigned int flagged = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int face : cell->face_indices())
          if (across_interface<dim>(cell, face) && cell->neighbor(face)->has_children())
            {
              cell->set_refine_flag();
              ++flagged;
              break;
            }
    return Utilities::MPI::sum(flagged, triangulation.get_communicator());
  }



  template class FeatureCloud<2>;
  template AdaptationReport mark_cells<2>(parallel::distributed::Triangulation<2> &,
                                          const Parameters::Refinement &,
                                          const dealii::Vector<float> &,
                                          const FeatureCloud<2> &,
                                          const FeatureCloud<2> &);
  template void make_interfaces_conforming<2>(parallel::distributed::Triangulation<2> &);
  template unsigned int
  flag_nonconforming_interface_cells<2>(parallel::distributed::Triangulation<2> &);
} // namespace ContactStefan
