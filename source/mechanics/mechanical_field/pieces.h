// Small pieces shared by the mechanical field's member files
// (source/mechanics/mechanical_field/): not part of the public headers.
#ifndef contact_stefan_mechanical_field_pieces_h
#define contact_stefan_mechanical_field_pieces_h

#include <deal.II/base/geometry_info.h>

#include <deal.II/dofs/dof_handler.h>

#include <array>
#include <string>
#include <vector>

namespace ContactStefan
{
  namespace MechanicalFieldPieces
  {
    using namespace dealii;

    // The name of the group of nodes of an obstacle (or roller) boundary, as it
    // appears in the output ("interface k-l" for interfaces).
    inline std::string boundary_group(const unsigned int id)
    {
      return "boundary " + std::to_string(id);
    }

    // The DoFs of each vertex of a cell: dofs[v][d] is displacement component d
    // at cell-local vertex v (the cell's element is FE_Q(1)^dim in one slot).
    template <int dim>
    std::array<std::array<types::global_dof_index, dim>, GeometryInfo<dim>::vertices_per_cell>
    vertex_dofs(const typename DoFHandler<dim>::active_cell_iterator &cell)
    {
      const auto                          &fe = cell->get_fe();
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      cell->get_dof_indices(dofs);
      std::array<std::array<types::global_dof_index, dim>, GeometryInfo<dim>::vertices_per_cell>
        result;
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
        {
          const auto [component, vertex]  = fe.system_to_component_index(i);
          result[vertex][component % dim] = dofs[i];
        }
      return result;
    }
  } // namespace MechanicalFieldPieces
} // namespace ContactStefan

#endif
