// The mesh of a scene: a rectangle (optionally cut into horizontal layers, one
// body each) or a Gmsh file, checked against the parameter file (every body id
// of the mesh is listed, every listed body and boundary occurs), then refined
// globally and geometrically as 'Mesh refinement' asks.
#ifndef contact_stefan_mesh_h
#define contact_stefan_mesh_h

#include <deal.II/distributed/tria.h>

#include <contact-stefan/core/parameters.h>
#include <contact-stefan/mesh/refinement_parameters.h>

namespace ContactStefan
{
  template <int dim>
  /**
   * coarse_only: the coarse mesh alone (checked the same way), on which a
   * checkpoint's refined mesh is loaded.
   */
  void make_mesh(const SceneParameters                     &prm,
                 const Parameters::Refinement              &refinement,
                 parallel::distributed::Triangulation<dim> &triangulation,
                 const bool                                 coarse_only = false);
} // namespace ContactStefan

#endif
