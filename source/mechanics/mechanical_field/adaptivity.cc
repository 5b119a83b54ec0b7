// What the mechanical field tells the mesh adaptation (mesh_adaptation.h):
// where the contact zones are, and the jump indicator of the displacement
// (doc/adaptivity.md).
#include <contact-stefan/core/q1_kernels.h>
#include <contact-stefan/mechanics/mechanical_field.h>

namespace ContactStefan
{
  template <int dim>
  void MechanicalField<dim>::contact_points(std::vector<Point<dim>> &points) const
  {
    points.clear();
    for (const auto &c : normal_conditions)
      if (c.kind != NormalCondition::Kind::roller && owned.is_element(c.dofs_k[0]) && is_active(c))
        {
          points.emplace_back(c.position[0], c.position[1]);
          // Large sliding: also where the master side is pressed, on its mesh.
          if (c.mortar && c.facing != c.position)
            points.emplace_back(c.facing[0], c.facing[1]);
        }
  }



  // Kelly's indicator for the displacement of each body: eta_K^2 = h_K sum over
  // the faces of K inside its body of int |[grad u] n|^2, in closed form
  // (q1_kernels.h). Across a contact interface the two bodies'
  // displacements are independent (the neighbour's slot is FE_Nothing there),
  // and a "jump" would be the whole gradient: those faces are left out.
  template <int dim>
  void MechanicalField<dim>::error_indicator(dealii::Vector<float> &indicator) const
  {
    CellVertexField field;
    field.n_components = dim;
    field.values.assign(4 * dim * triangulation.n_active_cells(), 0.);
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          const auto &element = cell->get_fe();
          dofs.resize(element.n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          // The slot of body b holds the components dim b ... dim b + dim - 1.
          const unsigned int first = dim * cell->active_fe_index();
          for (unsigned int i = 0; i < dofs.size(); ++i)
            {
              const auto [component, vertex] = element.system_to_component_index(i);
              field.values[(cell->active_cell_index() * dim + component - first) * 4 + vertex] =
                displacement_ghosted[dofs[i]];
            }
        }
    q1_jump_indicator(triangulation, field, true, indicator);
  }



  template void MechanicalField<2>::contact_points(std::vector<Point<2>> &) const;
  template void MechanicalField<2>::error_indicator(dealii::Vector<float> &) const;
} // namespace ContactStefan
