// Unit test of the pieces of mesh adaptation that only look at the mesh
// (mesh_adaptation.h): the buffer of cells around feature points, the marking
// (features refined to the maximum level and never coarsened, level limits,
// the cell cap) and the conformity of refinement across a contact interface.
#include <deal.II/base/mpi.h>

#include <deal.II/grid/grid_generator.h>

#include <contact-stefan/mesh/mesh_adaptation.h>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  // [0,1]^2 in 4 x 4 cells, refined once (8 x 8, h = 1/8); body 1 above y = 1/2.
  void make_two_bodies(parallel::distributed::Triangulation<2> &tria)
  {
    GridGenerator::subdivided_hyper_cube(tria, 4, 0, 1);
    for (const auto &cell : tria.active_cell_iterators())
      cell->set_material_id(cell->center()[1] > 0.5 ? 1 : 0);
    tria.refine_global(1);
  }

  unsigned int count_flags(parallel::distributed::Triangulation<2> &tria, const bool refine)
  {
    unsigned int n = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        n += (refine ? bool(cell->refine_flag_set()) : cell->coarsen_flag_set()) ? 1 : 0;
    return n;
  }
} // namespace

int main(int argc, char *argv[])
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);

  // --- FeatureCloud: the buffer in cell widths ---------------------------------
  {
    const double          h = 0.1, d = h * std::sqrt(2.);
    const FeatureCloud<2> cloud(std::vector<Point<2>>{Point<2>(0.05, 0.05)});
    const FeatureCloud<2> none(std::vector<Point<2>>{});
    check(cloud.within(Point<2>(0.05, 0.05), d, 0), "a cell contains its own centre");
    check(!cloud.within(Point<2>(0.15, 0.05), d, 0), "buffer 0: the edge neighbour is out");
    check(cloud.within(Point<2>(0.15, 0.05), d, 1), "buffer 1: the edge neighbour is in");
    check(cloud.within(Point<2>(0.15, 0.15), d, 1), "buffer 1: the corner neighbour is in");
    check(cloud.within(Point<2>(0.25, 0.05), d, 1),
          "buffer 1: two cells away along an axis is in (2 h < 1.5 sqrt(2) h)");
    check(!cloud.within(Point<2>(0.25, 0.15), d, 1), "buffer 1: (2, 1) cells away is out");
    check(!cloud.within(Point<2>(0.35, 0.05), d, 1), "buffer 1: three cells away is out");
    check(cloud.within(Point<2>(0.25, 0.25), d, 2), "buffer 2: two cells diagonally is in");
    const FeatureCloud<2> corner(std::vector<Point<2>>{Point<2>(0.1, 0.1)});
    check(corner.within(Point<2>(0.05, 0.05), d, 0), "a node at a cell's corner is in that cell");
    check(!none.within(Point<2>(0, 0), 1e9, 100), "no points: no cell is near");
    check(std::isinf(none.distance(Point<2>(0, 0))), "no points: infinite distance");
    // Near a corner of the points' bounding box, the distance decides, not the box:
    // (1.3, 0.3) is 0.424 from (1, 0).
    const FeatureCloud<2> pair(std::vector<Point<2>>{Point<2>(0, 0), Point<2>(1, 0)});
    check(!pair.within(Point<2>(1.3, 0.3), 0.8, 0), "0.424 away, radius 0.40: out");
    check(pair.within(Point<2>(1.3, 0.3), 0.9, 0), "0.424 away, radius 0.45: in");
    check(pair.within(Point<2>(0.5, 0.3), 1.2, 0), "between the points, 0.583 away, radius 0.6: in");
    check(!pair.within(Point<2>(0.5, -0.7), 1.2, 0), "below the box by more than the radius: out");
    const FeatureCloud<2> many(
      std::vector<Point<2>>{Point<2>(3, 4), Point<2>(-1, 0), Point<2>(0.5, 0.5)});
    check(std::abs(many.distance(Point<2>(0, 0)) - std::sqrt(0.5)) < 1e-15,
          "distance to the nearest of three");
  }

  // --- mark_cells: features, levels, cap --------------------------------------------
  {
    parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
    make_two_bodies(tria);
    Parameters::Refinement prm;
    prm.strategy         = Parameters::Refinement::Strategy::fixed_fraction;
    prm.refine_fraction  = 0.3;
    prm.coarsen_fraction = 0.3;
    prm.min_level        = 0;
    prm.max_level        = 3;
    prm.front_buffer     = 1;
    prm.contact_buffer   = 0;
    prm.max_cells        = 1000000;
    // A smooth indicator that peaks at x = 1: the coarsening goes to the left.
    dealii::Vector<float> indicator(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      indicator(cell->active_cell_index()) = cell->center()[0];
    // A front through the cell at (1/16, 1/16), far from the large indicator.
    const FeatureCloud<2>  fronts(std::vector<Point<2>>{Point<2>(1. / 16, 1. / 16)});
    const FeatureCloud<2>  contacts(std::vector<Point<2>>{});
    const AdaptationReport report        = mark_cells(tria, prm, indicator, fronts, contacts);
    bool                   front_refined = true, front_kept = true;
    for (const auto &cell : tria.active_cell_iterators())
      if (fronts.within(cell->center(), cell->diameter(), 1))
        {
          front_refined = front_refined && cell->refine_flag_set();
          front_kept    = front_kept && !cell->coarsen_flag_set();
        }
    check(report.feature_cells == 6,
          "buffer 1 around the corner cell: itself, 2 edge, 1 corner, 2 two-across neighbours");
    check(front_refined && front_kept, "front cells refined and not coarsened");
    check(count_flags(tria, false) > 0, "cells with a small indicator coarsened elsewhere");

    // The cap: indicator flags go first.
    for (const auto &cell : tria.active_cell_iterators())
      cell->clear_refine_flag(), cell->clear_coarsen_flag();
    prm.max_cells                 = 64 + 3 * 6 + 5;
    const AdaptationReport capped = mark_cells(tria, prm, indicator, fronts, contacts);
    check(capped.capped && capped.refine == 6, "capped: only the 6 feature cells are refined");

    // Level limits: nothing refined beyond max_level, nothing coarsened below min_level.
    for (const auto &cell : tria.active_cell_iterators())
      cell->clear_refine_flag(), cell->clear_coarsen_flag();
    prm.max_cells                  = 1000000;
    prm.max_level                  = 1;
    prm.min_level                  = 1;
    const AdaptationReport limited = mark_cells(tria, prm, indicator, fronts, contacts);
    check(limited.refine == 0 && limited.coarsen == 0,
          "level limits: no flag at level 1 of [1, 1]");
  }

  // --- interfaces: refinement propagated across, coarsening withheld ----------------
  {
    parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
    make_two_bodies(tria);
    // Refine the body-0 cell below the interface at x = 3/16.
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->point_inside(Point<2>(3. / 16, 7. / 16)))
        cell->set_refine_flag();
    make_interfaces_conforming(tria);
    unsigned int above = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->point_inside(Point<2>(3. / 16, 9. / 16)) && cell->refine_flag_set())
        ++above;
    check(above == 1, "the cell across the interface is flagged with it");
    tria.execute_coarsening_and_refinement();
    check(flag_nonconforming_interface_cells(tria) == 0, "conforming after the refinement");

    // Coarsening a family that touches the interface is withheld; elsewhere not.
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->point_inside(Point<2>(1. / 16, 1. / 16)))
        cell->set_refine_flag();
    tria.execute_coarsening_and_refinement(); // a level-2 family far from the interface
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->level() == 2)
        cell->set_coarsen_flag();
    make_interfaces_conforming(tria);
    unsigned int kept_far = 0, kept_near = 0;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->coarsen_flag_set())
        ++(cell->center()[1] < 0.25 ? kept_far : kept_near);
    check(kept_near == 0, "coarsen flags cleared in the families at the interface");
    check(kept_far == 4, "the family far from the interface keeps its coarsen flags");
    for (const auto &cell : tria.active_cell_iterators())
      cell->clear_coarsen_flag();

    // One-sided refinement without propagation is found and repaired.
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->point_inside(Point<2>(13. / 16, 7. / 16)))
        cell->set_refine_flag();
    tria.execute_coarsening_and_refinement();
    check(flag_nonconforming_interface_cells(tria) == 1,
          "a one-sided refinement at the interface: the coarse side is flagged");
    tria.execute_coarsening_and_refinement();
    check(flag_nonconforming_interface_cells(tria) == 0, "conforming after the repair");
  }
  return UnitTest::finish();
}
