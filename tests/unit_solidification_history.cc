// Unit test of the solidification history (mechanics/solidification_history.h):
// the update rule of one material point (freezing, re-melting, no change),
// the transfer rules (refining then coarsening gives back the parent bit for
// bit; coarsening keeps the mean of e_ref over a family), the geometry they
// rely on (Gauss point q lies in the quadrant of vertex q on a distorted cell;
// child k of a refined cell has the parent's vertex k), and the class itself
// moving the references with a distributed mesh through a refinement and the
// coarsening back, and through save() and load().
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/distributed/tria.h>

#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>

#include <contact-stefan/mechanics/solidification_history.h>

#include <cstring>
#include <filesystem>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  SymmetricTensor<2, 2> tensor(const double xx, const double yy, const double xy)
  {
    SymmetricTensor<2, 2> e;
    e[0][0] = xx;
    e[1][1] = yy;
    e[0][1] = xy;
    return e;
  }

  bool same_bits(const CellReferences &a, const CellReferences &b)
  {
    return std::memcmp(&a, &b, sizeof(CellReferences)) == 0;
  }

  // A cell's references that differ in every number (cell number n).
  CellReferences distinct(const unsigned int n)
  {
    CellReferences r;
    for (unsigned int k = 0; k < 4; ++k)
      {
        r[k].solid  = (n + k) % 2;
        r[k].born   = (n + k + 1) % 2;
        r[k].theta  = 100 * n + k + 0.125;
        r[k].time   = 0.5 * n + 0.01 * k;
        r[k].strain = {{1e-3 * n + 1e-4 * k, -2e-3 * n, 3e-5 * k + 1e-6 * n}};
      }
    return r;
  }

  void update_rule()
  {
    CornerReference corner;
    corner.solid                 = 0; // liquid at the last update
    corner.theta                 = 7; // its initial Theta_0
    const CornerReference before = corner;
    check(!update_corner(corner, false, tensor(1, 2, 3), -5, 1.5) &&
            std::memcmp(&corner, &before, sizeof(corner)) == 0,
          "a liquid point that stays liquid keeps its reference");
    // Frozen (its node now below the melting temperature): born at the
    // transition temperature, not at its own temperature.
    check(update_corner(corner, true, tensor(1e-3, -2e-3, 5e-4), 0., 2.5) && corner.solid == 1 &&
            corner.born == 1 && corner.theta == 0 && corner.time == 2.5 &&
            corner.strain[0] == 1e-3 && corner.strain[1] == -2e-3 && corner.strain[2] == 5e-4,
          "a freezing point is born at the transition temperature, in its strain, at t");
    const CornerReference frozen = corner;
    check(!update_corner(corner, true, tensor(9, 9, 9), 0., 3.) &&
            std::memcmp(&corner, &frozen, sizeof(corner)) == 0,
          "a solid point that stays solid keeps its birth");
    check(update_corner(corner, false, tensor(4e-3, 0, 0), 0., 4.) && corner.solid == 0 &&
            corner.born == 1 && corner.time == 4. && corner.strain[0] == 4e-3 &&
            corner.strain[1] == 0,
          "a re-molten point starts a new history");
    check(update_corner(corner, true, tensor(5e-3, 1e-3, 0), 0., 5.) && corner.time == 5. &&
            corner.strain[0] == 5e-3 && corner.strain[1] == 1e-3,
          "and is born again when it re-freezes");
  }

  void transfer_rules()
  {
    const CellReferences              parent   = distinct(3);
    const std::vector<CellReferences> children = refine_references(parent, 4);
    bool                              inherit  = true;
    for (unsigned int k = 0; k < 4; ++k)
      for (unsigned int c = 0; c < 4; ++c)
        inherit = inherit && std::memcmp(&children[k][c], &parent[k], sizeof(CornerReference)) == 0;
    check(inherit, "each child takes the state of the parent's corner of its quadrant");
    check(same_bits(coarsen_references(children), parent),
          "refining then coarsening gives back the parent bit for bit");

    std::vector<CellReferences> family = {distinct(1), distinct(2), distinct(5), distinct(8)};
    const CellReferences        merged = coarsen_references(family);
    bool                        vertex = true;
    for (unsigned int k = 0; k < 4; ++k)
      vertex = vertex && merged[k].solid == family[k][k].solid &&
               merged[k].born == family[k][k].born && merged[k].theta == family[k][k].theta &&
               merged[k].time == family[k][k].time;
    check(vertex, "the coarse corner k takes class, Theta_ref and time of child k's corner k");
    bool mean = true;
    for (unsigned int s = 0; s < 3; ++s)
      {
        double fine = 0, coarse = 0;
        for (unsigned int k = 0; k < 4; ++k)
          {
            for (unsigned int c = 0; c < 4; ++c)
              fine += family[k][c].strain[s] / 16;
            coarse += merged[k].strain[s] / 4;
          }
        mean = mean && UnitTest::close(fine, coarse, 1e-14);
      }
    check(mean, "coarsening keeps the mean of e_ref over the family");
  }

  void geometry()
  {
    // A distorted quadrilateral: Gauss point q is nearer vertex q than any
    // other vertex (it lies in the quadrant of vertex q).
    Triangulation<2>            tria;
    const std::vector<Point<2>> vertices = {Point<2>(0, 0),
                                            Point<2>(1.3, 0.2),
                                            Point<2>(-0.1, 0.9),
                                            Point<2>(1.1, 1.4)};
    GridGenerator::general_cell(tria, vertices);
    FE_Q<2>     fe(1);
    FEValues<2> fe_values(fe, QGauss<2>(2), update_quadrature_points);
    fe_values.reinit(tria.begin_active());
    bool quadrants = true;
    for (unsigned int q = 0; q < 4; ++q)
      for (unsigned int v = 0; v < 4; ++v)
        if (v != q)
          quadrants = quadrants && fe_values.quadrature_point(q).distance(vertices[q]) <
                                     fe_values.quadrature_point(q).distance(vertices[v]);
    check(quadrants, "Gauss point q of QGauss(2) lies in the quadrant of vertex q");
    tria.refine_global(1);
    const auto parent = tria.begin(0);
    bool       corner = true;
    for (unsigned int k = 0; k < 4; ++k)
      corner = corner && parent->child(k)->vertex(k).distance(parent->vertex(k)) == 0;
    check(corner, "child k of a refined cell has the parent's vertex k");
  }

  // The history on a distributed mesh: every cell gets distinct references,
  // half the cells are refined, and coarsened back, and the mesh is saved
  // and loaded: every cell ends with its own references, bit for bit.
  void distributed_transfer()
  {
    parallel::distributed::Triangulation<2> tria(MPI_COMM_WORLD);
    GridGenerator::subdivided_hyper_rectangle(tria, {4, 3}, Point<2>(0, 0), Point<2>(2, 1.5));
    SolidificationHistory<2> history(tria);
    history.resize();
    // Each coarse cell's number by its centre (independent of the order).
    const auto number = [](const Point<2> &centre) {
      return static_cast<unsigned int>(std::floor(centre[0] / 0.5)) +
             4 * static_cast<unsigned int>(std::floor(centre[1] / 0.5));
    };
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        history[cell->active_cell_index()] = distinct(number(cell->center()));
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() && number(cell->center()) % 2 == 0)
        cell->set_refine_flag();
    history.prepare_for_coarsening_and_refinement();
    tria.execute_coarsening_and_refinement();
    history.unpack();
    bool refined = true;
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() && cell->level() == 1)
        {
          const CellReferences parent = distinct(number(cell->parent()->center()));
          unsigned int         k      = 0;
          while (cell->parent()->child(k) != cell)
            ++k;
          for (unsigned int c = 0; c < 4; ++c)
            refined = refined && std::memcmp(&history[cell->active_cell_index()][c],
                                             &parent[k],
                                             sizeof(CornerReference)) == 0;
        }
    check(refined, "a refined cell's children carry the parent's corners (distributed)");
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() && cell->level() == 1)
        cell->set_coarsen_flag();
    history.prepare_for_coarsening_and_refinement();
    tria.execute_coarsening_and_refinement();
    history.unpack();
    bool back = tria.n_global_active_cells() == 12;
    if (!back)
      std::printf("  %u cells after coarsening\n", tria.n_global_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() &&
          !same_bits(history[cell->active_cell_index()], distinct(number(cell->center()))))
        {
          back                   = false;
          const CellReferences a = history[cell->active_cell_index()],
                               b = distinct(number(cell->center()));
          for (unsigned int k = 0; k < 4; ++k)
            std::printf("  cell %u corner %u: %g %g %g %g %.17g | %g %g %g %g %.17g\n",
                        number(cell->center()),
                        k,
                        a[k].solid,
                        a[k].born,
                        a[k].theta,
                        a[k].time,
                        a[k].strain[0],
                        b[k].solid,
                        b[k].born,
                        b[k].theta,
                        b[k].time,
                        b[k].strain[0]);
        }
    check(back, "refined and coarsened back: every cell has its references bit for bit");

    const std::string directory = "unit_solidification_history.checkpoint";
    const bool        root      = Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;
    if (root)
      std::filesystem::create_directories(directory);
    MPI_Barrier(MPI_COMM_WORLD);
    history.prepare_for_serialization();
    tria.save(directory + "/mesh");
    parallel::distributed::Triangulation<2> loaded(MPI_COMM_WORLD);
    GridGenerator::subdivided_hyper_rectangle(loaded, {4, 3}, Point<2>(0, 0), Point<2>(2, 1.5));
    loaded.load(directory + "/mesh");
    SolidificationHistory<2> restored(loaded);
    restored.deserialize();
    bool same = true;
    for (const auto &cell : loaded.active_cell_iterators())
      if (cell->is_locally_owned())
        same =
          same && same_bits(restored[cell->active_cell_index()], distinct(number(cell->center())));
    check(same, "saved and loaded with the mesh: the same references bit for bit");
    MPI_Barrier(MPI_COMM_WORLD);
    if (root)
      std::filesystem::remove_all(directory);
  }
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  update_rule();
  transfer_rules();
  geometry();
  distributed_transfer();
  return UnitTest::finish();
}
