// Unit test of the interface geometry (interfaces/body_interface.h), without
// a solve: on the inclined-interface mesh (tests/make_inclined_blocks_msh.cmake,
// 17 degrees from the vertical, 4 x 4 cells per body) the pairing of the two
// sides' cells at every vertex, the normals (the face normal out of body 1),
// the lumped weights (half the adjacent face lengths, summing to the length
// 1/cos 17deg) and no corner; on an L-shaped interface of a 2 x 2 mesh the
// kink vertex is a corner with the bisecting normal and the weight of both
// faces. Where functions are evaluated per body (two_sided_vertices(),
// jumps_at(), point_of_side(); doc/coupling.md §2): on a straight interface
// of a 4 x 4 mesh, the vertices marked for each law, and which data jump.
#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/tria.h>

#include <contact-stefan/interfaces/body_interface.h>

#include <cmath>
#include <fstream>

#include "unit_test_tools.h"

using namespace ContactStefan;
using UnitTest::check;
using UnitTest::close;

namespace
{
  // Both sides' cells name the vertex at the vertex's position.
  bool paired(const BodyInterface<2>::Vertex &v)
  {
    return v.cell_k->vertex_index(v.vertex_k) == v.index &&
           v.cell_l->vertex_index(v.vertex_l) == v.index &&
           v.cell_k->vertex(v.vertex_k).distance(v.position) == 0 &&
           v.cell_l->vertex(v.vertex_l).distance(v.position) == 0 &&
           v.cell_k->material_id() != v.cell_l->material_id();
  }

  void inclined(const std::string &mesh_file)
  {
    std::printf("inclined interface, 17 degrees (%s)\n",
                mesh_file.substr(mesh_file.rfind('/') + 1).c_str());
    Triangulation<2> triangulation;
    GridIn<2>        grid_in(triangulation);
    std::ifstream    in(mesh_file);
    grid_in.read_msh(in);
    std::string problem;
    const auto  interfaces = find_body_interfaces(triangulation, 20., problem);
    check(problem.empty(), "every normal is defined");
    check(interfaces.size() == 1, "one interface");
    const auto &interface = interfaces[0];
    check(interface.body_k == 1 && interface.body_l == 2 && interface.name() == "interface 1-2",
          "between bodies 1 and 2, named 'interface 1-2'");
    check(interface.faces.size() == 4 && interface.vertices.size() == 5,
          "4 face pairs, 5 vertices");
    bool faces_match = true;
    for (const auto &f : interface.faces)
      faces_match = faces_match && f.cell_k->material_id() == 1 && f.cell_l->material_id() == 2 &&
                    f.cell_k->neighbor(f.face_k) == f.cell_l &&
                    f.cell_l->neighbor(f.face_l) == f.cell_k;
    check(faces_match, "each face pair is one face seen from body 1 and from body 2");
    const double angle = 17. * numbers::PI / 180, t = std::tan(angle);
    bool         pairing = true, on_line = true, normals = true, corners = false;
    double       total   = 0;
    for (const auto &v : interface.vertices)
      {
        pairing = pairing && paired(v);
        on_line = on_line && std::abs(v.position[0] - (1 + (v.position[1] - 0.5) * t)) < 1e-11;
        // Out of body 1 (left) into body 2: the line's direction (sin, cos) turned clockwise.
        normals = normals && std::abs(v.normal[0] - std::cos(angle)) < 1e-11 &&
                  std::abs(v.normal[1] + std::sin(angle)) < 1e-11;
        corners = corners || v.corner;
        total += v.weight;
      }
    check(pairing, "at every vertex, a cell of each body that has it");
    check(on_line, "every vertex on the line x = 1 + (y - 0.5) tan 17deg");
    check(normals, "every normal (cos 17deg, -sin 17deg), out of body 1");
    check(!corners, "no corner on a straight interface");
    check(close(total, 1 / std::cos(angle), 1e-11), "the weights sum to the length 1/cos 17deg");
    const double h = 1 / std::cos(angle) / 4;
    bool         weights = true;
    for (const auto &v : interface.vertices)
      {
        const bool end = v.position[1] < 1e-12 || v.position[1] > 1 - 1e-12;
        weights = weights && std::abs(v.weight - (end ? h / 2 : h)) < 1e-11;
      }
    check(weights, "half a face at the two ends, a face's length inside");
  }

  void kinked()
  {
    std::printf("L-shaped interface of a 2 x 2 mesh\n");
    Triangulation<2> triangulation;
    GridGenerator::subdivided_hyper_rectangle(triangulation, {2, 2}, Point<2>(0, 0), Point<2>(2, 2));
    for (const auto &cell : triangulation.active_cell_iterators())
      cell->set_material_id(cell->center()[0] > 1 && cell->center()[1] > 1 ? 1 : 0);
    std::string problem;
    const auto  interfaces = find_body_interfaces(triangulation, 20., problem);
    check(problem.empty() && interfaces.size() == 1, "one interface, every normal defined");
    const auto &interface = interfaces[0];
    check(interface.faces.size() == 2 && interface.vertices.size() == 3,
          "2 face pairs, 3 vertices");
    bool found = false, ends = true;
    for (const auto &v : interface.vertices)
      if (v.position.distance(Point<2>(1, 1)) < 1e-14)
        {
          found = true;
          check(v.corner, "the kink (1, 1) is a corner (the faces are 90 degrees apart)");
          check(close(v.normal[0], std::sqrt(0.5)) && close(v.normal[1], std::sqrt(0.5)),
                "its normal bisects the kink, out of body 0");
          check(close(v.weight, 1.), "its weight is half of each of its two faces");
          check(paired(v), "a cell of each body has it");
        }
      else
        ends = ends && !v.corner && close(v.weight, 0.5) && paired(v);
    check(found, "the kink is a vertex of the interface");
    check(ends, "the two ends: no corner, half a face each, paired");
  }

  void two_sided()
  {
    std::printf("two-sided vertices of a straight interface x = 1 (4 x 4 cells on [0, 2]^2)\n");
    Triangulation<2> triangulation;
    GridGenerator::subdivided_hyper_rectangle(triangulation,
                                              {4, 4},
                                              Point<2>(0, 0),
                                              Point<2>(2, 2));
    for (const auto &cell : triangulation.active_cell_iterators())
      cell->set_material_id(cell->center()[0] > 1 ? 1 : 0);
    Parameters::InterfacePair law;
    law.thermal_contact = Parameters::InterfacePair::ThermalContact::perfect;
    law.discretisation  = Parameters::InterfacePair::Discretisation::nodal;
    std::map<std::pair<unsigned int, unsigned int>, Parameters::InterfacePair> pairs{{{0, 1}, law}};
    const auto marked = [&](const std::vector<bool> &two_sided) {
      unsigned int count   = 0;
      bool         on_line = true;
      for (unsigned int v = 0; v < triangulation.n_vertices(); ++v)
        if (two_sided[v])
          {
            ++count;
            on_line = on_line && triangulation.get_vertices()[v][0] == 1;
          }
      return on_line ? count : 0;
    };
    const auto all = two_sided_vertices(triangulation, pairs);
    check(marked(all) == 5, "perfect contact: the 5 vertices on x = 1, no other");
    check(marked(two_sided_vertices(triangulation, pairs, true)) == 0,
          "perfect contact, conductances only: none");
    pairs.at({0, 1}).thermal_contact = Parameters::InterfacePair::ThermalContact::conductance;
    check(marked(two_sided_vertices(triangulation, pairs, true)) == 5,
          "a conductance interface, conductances only: the 5");

    const auto function = [](const std::function<double(const Point<2> &)> &f) {
      return ScalarFunctionFromFunctionObject<2>(f);
    };
    const auto below       = function([](const Point<2> &x) { return x[0] < 1 ? 300. : 400.; });
    const auto at_or_below = function([](const Point<2> &x) { return x[0] <= 1 ? 300. : 400.; });
    check(jumps_at(below, triangulation, all) && jumps_at(at_or_below, triangulation, all),
          "300 K | 400 K jumps, whichever side the comparison gives x = 1");
    check(!jumps_at(function([](const Point<2> &x) { return 300 + 1e3 * x[0]; }),
                    triangulation,
                    all),
          "300 + 1000 x does not (the offset inside moves it by about 1e-7 K)");
    check(!jumps_at(function([](const Point<2> &x) { return 1e3 * (x[0] - 1); }),
                    triangulation,
                    all),
          "1000 (x - 1), zero on the interface, does not");
    bool own_side = true;
    for (const auto &cell : triangulation.active_cell_iterators())
      for (const unsigned int v : cell->vertex_indices())
        if (all[cell->vertex_index(v)])
          {
            const double expected = cell->material_id() == 0 ? 300 : 400;
            own_side = own_side && below.value(point_of_side<2>(cell, v)) == expected &&
                       at_or_below.value(point_of_side<2>(cell, v)) == expected;
          }
    check(own_side, "point_of_side: each cell evaluates its own body's value at x = 1");
  }
} // namespace

int main(int argc, char **argv)
{
  Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  if (argc != 2)
    {
      std::printf("usage: unit_body_interface INCLINED_17.msh\n");
      return 2;
    }
  inclined(argv[1]);
  kinked();
  two_sided();
  return UnitTest::finish();
}
