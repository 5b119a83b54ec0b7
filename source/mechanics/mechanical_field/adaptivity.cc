// What the fields tell the mesh adaptation (mesh_adaptation.h): where the phase
// fronts and the contact zones are, and the jump indicators of the temperature
// and the displacement (doc/adaptivity.md).
#include <contact-stefan/mechanics/mechanical_field.h>
#include <contact-stefan/core/q1_kernels.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <cmath>

namespace ContactStefan
{
  // A cell carries a front when its nodes are not all in one phase: their
  // phase indices (p on the branch of phase p, j + fraction on plateau j)
  // differ, or one of them is on a plateau.
  template <int dim>
  void ThermalField<dim>::front_points(std::vector<Point<dim>> &points) const
  {
    points.clear();
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
          bool   plateau = false;
          for (const auto dof : dofs)
            {
              const double index = law(dof).phase_index(enthalpy_ghosted[dof]);
              lowest             = std::min(lowest, index);
              highest            = std::max(highest, index);
              plateau            = plateau || index != std::floor(index);
            }
          if (plateau || highest > lowest)
            points.push_back(cell->center());
        }
  }



  // Kelly's jump of grad Theta over every interior face, interfaces included
  // (the temperature is continuous across them), in closed form
  // (q1_kernels.h).
  template <int dim>
  void ThermalField<dim>::error_indicator(dealii::Vector<float> &indicator) const
  {
    CellVertexField                      field;
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    field.values.assign(4 * triangulation.n_active_cells(), 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < 4; ++v)
            field.values[4 * cell->active_cell_index() + v] = temperature_ghosted[dofs[v]];
        }
    q1_jump_indicator(triangulation, field, false, indicator);
  }



  template <int dim>
  void MechanicalField<dim>::contact_points(std::vector<Point<dim>> &points) const
  {
    points.clear();
    for (const auto &c : normal_conditions)
      if (c.kind != NormalCondition::Kind::roller && owned.is_element(c.dofs_k[0]) && is_active(c))
        points.emplace_back(c.position[0], c.position[1]);
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



  template void ThermalField<2>::front_points(std::vector<Point<2>> &) const;
  template void ThermalField<2>::error_indicator(dealii::Vector<float> &) const;
  template void MechanicalField<2>::contact_points(std::vector<Point<2>> &) const;
  template void MechanicalField<2>::error_indicator(dealii::Vector<float> &) const;
} // namespace ContactStefan
