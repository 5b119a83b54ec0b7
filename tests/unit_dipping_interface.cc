// Unit test of the dipping interface (core/dipping_interface.h), the geometry
// behind the function variable interface_distance and the manifold of a bent
// interface (mesh.cc):
// - straight (Interface dip at base = 0): the signed distance is the
//   perpendicular distance to the line through the trench, positive on body
//   0's side, at points all over the section;
// - bent (Interface dip at base = 90): the coarse nodes lie on the curve
//   (dipping_interface_x); x_at is the curve to 1e-6 m at any height, and off
//   the chords between the nodes; a point pushed off the curve along its
//   normal by delta lies delta away, on the side it was pushed to; beyond the
//   foot the nearest point is the foot node;
// - the mesh generator puts every interface vertex of a twice refined mesh on
//   the curve (the manifold), not on the coarse polyline, and the sign agrees
//   with the bodies at every cell centre;
// - bad polylines are refused.
#include <deal.II/base/mpi.h>

#include <deal.II/distributed/tria.h>

#include <contact-stefan/core/dipping_interface.h>
#include <contact-stefan/mesh/mesh.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;
using UnitTest::close;

namespace
{
  Parameters::Geometry subduction_geometry(const double dip_at_base)
  {
    Parameters::Geometry g;
    g.mesh_type             = Parameters::Geometry::MeshType::dipping_interface;
    g.lower_left            = Point<2>(0, -100000);
    g.upper_right           = Point<2>(400000, 0);
    g.interface_top_x       = 100000;
    g.interface_dip         = 30;
    g.interface_dip_at_base = dip_at_base;
    g.subdivisions          = {80, 20};
    return g;
  }
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  std::mt19937                           random(7);
  std::uniform_real_distribution<double> ux(0, 400000), uy(-100000, 0);

  // --- straight -------------------------------------------------------------
  {
    const DippingInterface interface(subduction_geometry(0));
    check(interface.nodes().size() == 21, "straight: 21 nodes for 20 coarse rows");
    const double s = std::sin(30 * M_PI / 180), c = std::cos(30 * M_PI / 180);
    double       worst = 0;
    for (unsigned int i = 0; i < 1000; ++i)
      {
        const Point<2> p(ux(random), uy(random));
        // The line through (1e5, 0) along (cos 30, -sin 30); its normal into
        // body 0 is (-sin 30, -cos 30). Points whose foot on the line lies
        // beyond the segment are compared with the distance to its end.
        const double   along = (p[0] - 1e5) * c - p[1] * s;
        const double   depth = 1e5 / s; // length of the segment
        const double   perpendicular = -(p[0] - 1e5) * s - p[1] * c;
        const Point<2> end   = along < 0 ? Point<2>(1e5, 0) : interface.nodes().front();
        const double   exact = along >= 0 && along <= depth ?
                                 perpendicular :
                                 std::copysign(p.distance(end), perpendicular);
        worst                = std::max(worst, std::abs(interface.signed_distance(p) - exact));
      }
    std::printf("straight: largest difference from the line's distance, relative to the "
                "height: %s\n",
                worst < 1e-10 * 1e5 ? "below 1e-10" : "ABOVE 1e-10");
    check(worst < 1e-10 * 1e5, "straight: the signed distance is the line's");
    check(interface.signed_distance(Point<2>(50000, -10000)) > 0 &&
            interface.signed_distance(Point<2>(300000, -10000)) < 0,
          "straight: positive in body 0 (left), negative in body 1");
  }

  // --- bent ---------------------------------------------------------------
  {
    const Parameters::Geometry g = subduction_geometry(90);
    const DippingInterface     interface(g);
    const auto                &nodes = interface.nodes();
    bool                       on_curve = true;
    for (unsigned int j = 0; j < nodes.size(); ++j)
      on_curve &=
        nodes[j][0] == dipping_interface_x(1e5, 30, 90, 1e5, -nodes[j][1]) &&
        close(nodes[j][1], -1e5 + j * 5000, 1e-15);
    check(on_curve, "bent: the nodes lie on the curve at the coarse rows' heights");
    std::printf("bent: foot at x = %.2f m\n", nodes.front()[0]);
    check(std::abs(interface.x_at(nodes[7][1]) - nodes[7][0]) < 1e-6 &&
            interface.x_at(-1e9) == interface.x_at(-1e5) &&
            interface.x_at(1e9) == interface.x_at(0) && interface.x_at(0) == 1e5,
          "bent: x_at hits the nodes and holds the end nodes' x beyond them");
    // The curve between the nodes: x_at against the integral itself, and its
    // distance from the chords (the polyline of the nodes alone).
    const DippingInterface polyline(nodes);
    double                 table_error = 0, sagitta = 0;
    for (unsigned int i = 0; i <= 1000; ++i)
      {
        const double y = -1e5 + i * 100.;
        table_error =
          std::max(table_error,
                   std::abs(interface.x_at(y) - dipping_interface_x(1e5, 30, 90, 1e5, -y)));
        sagitta =
          std::max(sagitta, std::abs(polyline.signed_distance(Point<2>(interface.x_at(y), y))));
      }
    std::printf("bent: x_at against the integral %s; the curve up to %.1f m off the chords\n",
                table_error < 1e-6 ? "below 1e-6 m" : "ABOVE 1e-6 m",
                sagitta);
    check(table_error < 1e-6, "bent: x_at is the curve to 1e-6 m");
    check(sagitta > 1 && sagitta < 100, "bent: the curve bows off the chords by metres");
    double worst = 0;
    bool   signs = true;
    for (unsigned int j = 1; j < nodes.size(); ++j)
      for (const double delta : {-300., -10., 10., 300.})
        {
          // The curve's point half way up row j and its unit normal into body
          // 0 (to the left of the upward tangent).
          const double       y = 0.5 * (nodes[j][1] + nodes[j - 1][1]);
          const Point<2>     q(interface.x_at(y), y);
          const Tensor<1, 2> d({interface.x_at(y + 1) - interface.x_at(y - 1), 2.});
          const Tensor<1, 2> n({-d[1] / d.norm(), d[0] / d.norm()});
          const Point<2>     p = q + delta * n;
          const double       e = interface.signed_distance(p);
          worst                = std::max(worst, std::abs(std::abs(e) - std::abs(delta)));
          signs &= (e > 0) == (delta > 0);
        }
    std::printf("bent: distance off the curve along its normal: largest error %s\n",
                worst < 1e-4 ? "below 1e-4 m" : "ABOVE 1e-4 m");
    check(worst < 1e-4, "bent: a point pushed off the curve by delta lies |delta| away");
    check(signs, "bent: pushed towards body 0 is positive, towards body 1 negative");
    const Point<2> below(nodes.front()[0] - 3000, -1e5 - 4000);
    check(close(interface.signed_distance(below), 5000, 1e-12),
          "bent: beyond the foot the nearest point is the foot node (3-4-5)");

    // The generator's bodies agree with the sign at every cell centre.
    SceneParameters scene;
    scene.geometry = g;
    scene.body_ids = {0, 1};
    scene.materials[0];
    scene.materials[1];
    Parameters::Refinement refinement{};
    refinement.initial_global_refinements = 2;
    refinement.max_cells                  = 1000000;
    parallel::distributed::Triangulation<2> mesh(MPI_COMM_WORLD);
    make_mesh(scene, refinement, mesh);
    unsigned int disagree = 0, cells = 0, interface_vertices = 0;
    double       off = 0, off_polyline = 0;
    for (const auto &cell : mesh.active_cell_iterators())
      {
        ++cells;
        disagree += (interface.signed_distance(cell->center()) > 0) != (cell->material_id() == 0);
        // The vertices of body 0's faces towards body 1 lie on the curve.
        for (const unsigned int f : cell->face_indices())
          if (cell->material_id() == 0 && !cell->at_boundary(f) &&
              cell->neighbor(f)->material_id() == 1)
            for (unsigned int v = 0; v < 2; ++v)
              {
                ++interface_vertices;
                off = std::max(off, std::abs(interface.signed_distance(cell->face(f)->vertex(v))));
                off_polyline =
                  std::max(off_polyline,
                           std::abs(polyline.signed_distance(cell->face(f)->vertex(v))));
              }
      }
    std::printf("bent: %u cells of a twice refined mesh, %u on the wrong side\n", cells, disagree);
    check(disagree == 0, "bent: the sign agrees with the mesh's bodies at every cell centre");
    std::printf("bent: interface vertices of the refined mesh up to %.1f m off the coarse "
                "polyline\n",
                off_polyline);
    check(interface_vertices == 2 * 80 && off < 1e-9 * 1e5,
          "bent: the interface's vertices (of 80 faces) lie on the curve to 1e-9 of the height");
    check(off_polyline > 1, "bent: refinement leaves the coarse polyline (the manifold)");
  }

  // --- bad polylines ---------------------------------------------------------
  {
    bool refused = false;
    try
      {
        DippingInterface({Point<2>(0, 0)});
      }
    catch (const std::invalid_argument &)
      {
        refused = true;
      }
    check(refused, "one node is refused");
    refused = false;
    try
      {
        DippingInterface({Point<2>(0, 0), Point<2>(1, 0)});
      }
    catch (const std::invalid_argument &)
      {
        refused = true;
      }
    check(refused, "nodes at the same height are refused");
    refused = false;
    try
      {
        DippingInterface(Parameters::Geometry{});
      }
    catch (const std::invalid_argument &)
      {
        refused = true;
      }
    check(refused, "a geometry that is not a dipping interface is refused");
  }
  return UnitTest::finish();
}
