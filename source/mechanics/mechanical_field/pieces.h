// Small pieces shared by the mechanical field's member files
// (source/mechanics/mechanical_field/): not part of the public headers.
#ifndef contact_stefan_mechanical_field_pieces_h
#define contact_stefan_mechanical_field_pieces_h

#include <deal.II/base/geometry_info.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/lac/affine_constraints.h>

#include <contact-stefan/interfaces/contact.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
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

    // A contact row whose entry u_j is itself constrained in terms of the
    // row's target (a roller u_x = a u_y on a slanted face at a node whose
    // contact row targets u_y and names u_x) would close a cycle that
    // AffineConstraints::close() never leaves. Such lines are substituted into
    // the row and the row is solved for its target again. False if the
    // target's coefficient then vanishes: the condition cannot be imposed on
    // that component.
    inline bool break_cycles(Contact::ConstraintRow          &row,
                             const AffineConstraints<double> &constraints)
    {
      double                          self          = 0;
      double                          inhomogeneity = row.inhomogeneity;
      std::map<std::uint64_t, double> entries;
      for (const auto &[j, a] : row.entries)
        {
          const auto *line  = constraints.get_constraint_entries(j);
          const bool  names = line && std::any_of(line->begin(), line->end(), [&](const auto &e) {
                               return e.first == row.target;
                             });
          if (!names)
            {
              entries[j] += a;
              continue;
            }
          inhomogeneity += a * constraints.get_inhomogeneity(j);
          for (const auto &[k, b] : *line)
            (k == row.target ? self : entries[k]) += a * b;
        }
      if (self == 0)
        return true;
      if (std::abs(1 - self) < 1e-10)
        return false;
      row.entries.clear();
      for (const auto &[k, b] : entries)
        if (b != 0)
          row.entries.emplace_back(k, b / (1 - self));
      row.inhomogeneity = inhomogeneity / (1 - self);
      return true;
    }
  } // namespace MechanicalFieldPieces
} // namespace ContactStefan

#endif
