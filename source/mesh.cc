#include <deal.II/base/utilities.h>

#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>

#include <contact-stefan/common.h>
#include <contact-stefan/mesh.h>

#include <fstream>
#include <set>

namespace ContactStefan
{
  // The mesh: a rectangle (optionally in horizontal layers, one body each) or a
  // Gmsh file. Body and boundary ids in the mesh are checked against the
  // parameter file here, before any time step runs.
  template <int dim>
  void make_mesh(const AllParameters &prm, parallel::distributed::Triangulation<dim> &triangulation)
  {
    assert_two_dimensional<dim>();
    const MPI_Comm mpi_communicator = triangulation.get_communicator();
    const auto    &g                = prm.geometry;
    if (g.mesh_type == Parameters::Geometry::MeshType::rectangle)
      {
        GridGenerator::subdivided_hyper_rectangle(
          triangulation, {g.subdivisions[0], g.subdivisions[1]}, g.lower_left, g.upper_right, true);
        for (const auto &cell : triangulation.active_cell_iterators())
          {
            unsigned int layer = 0;
            for (const double y : g.layer_interfaces)
              {
                const double lo = cell->vertex(0)[1], hi = cell->vertex(3)[1];
                const double tolerance = 1e-10 * (hi - lo);
                if (y > lo + tolerance && y < hi - tolerance)
                  throw InputError(
                    "Geometry/Layer interfaces",
                    "y = " + std::to_string(y) +
                      " does not lie on a line of the coarse mesh (see Subdivisions)");
                if (cell->center()[1] > y)
                  ++layer;
              }
            cell->set_material_id(layer);
          }
      }
    else
      {
        GridIn<dim> grid_in;
        grid_in.attach_triangulation(triangulation);
        std::ifstream in(g.mesh_file);
        try
          {
            grid_in.read_msh(in);
          }
        catch (const std::exception &e)
          {
            throw InputError("Geometry/Mesh file",
                             "'" + g.mesh_file + "' is not a readable Gmsh mesh");
          }
      }

    // Every material id must be a body and every thermal boundary must exist.
    std::set<unsigned int> materials, boundaries;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (!cell->is_artificial())
        {
          materials.insert(cell->material_id());
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary())
              boundaries.insert(face->boundary_id());
        }
    materials  = Utilities::MPI::compute_set_union(materials, mpi_communicator);
    boundaries = Utilities::MPI::compute_set_union(boundaries, mpi_communicator);
    for (const unsigned int m : materials)
      if (prm.materials.count(m) == 0)
        throw InputError("Bodies/Body ids",
                         "the mesh has body (material) id " + std::to_string(m) +
                           ", which is not listed");
    for (const unsigned int b : prm.body_ids)
      if (materials.count(b) == 0)
        throw InputError("Bodies/Body ids",
                         "body " + std::to_string(b) + " does not occur in the mesh");
    for (const auto &[id, bc] : prm.thermal_boundaries)
      if (boundaries.count(id) == 0)
        throw InputError("Boundary conditions/Thermal boundaries",
                         "boundary id " + std::to_string(id) + " does not occur in the mesh");
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      if (boundaries.count(id) == 0)
        throw InputError("Boundary conditions/Mechanical boundaries",
                         "boundary id " + std::to_string(id) + " does not occur in the mesh");

    triangulation.refine_global(prm.refinement.initial_global_refinements);
    const auto &r = prm.refinement;
    if (r.prerefinement_radius > 0)
      for (unsigned int step = 0; step < r.prerefinement_steps; ++step)
        {
          for (const auto &cell : triangulation.active_cell_iterators())
            if (cell->is_locally_owned() && cell->center().distance(r.prerefinement_center) <
                                              r.prerefinement_radius + 0.5 * cell->diameter())
              cell->set_refine_flag();
          triangulation.execute_coarsening_and_refinement();
        }
  }



  template void make_mesh<2>(const AllParameters &, parallel::distributed::Triangulation<2> &);
} // namespace ContactStefan
