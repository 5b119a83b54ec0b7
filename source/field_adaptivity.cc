// What the fields tell the mesh adaptation (mesh_adaptation.h): where the phase
// fronts and the contact zones are, and the jump indicators of the temperature
// and the displacement (doc/adaptivity.md).
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <deal.II/numerics/error_estimator.h>

#include <contact-stefan/mechanical_field.h>
#include <contact-stefan/thermal_field.h>

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



  template <int dim>
  void ThermalField<dim>::error_indicator(dealii::Vector<float> &indicator) const
  {
    indicator.reinit(triangulation.n_active_cells());
    KellyErrorEstimator<dim>::estimate(dof_handler,
                                       QGauss<dim - 1>(2),
                                       {},
                                       temperature_ghosted,
                                       indicator,
                                       ComponentMask(),
                                       nullptr,
                                       numbers::invalid_unsigned_int,
                                       triangulation.locally_owned_subdomain());
  }



  template <int dim>
  void MechanicalField<dim>::contact_points(std::vector<Point<dim>> &points) const
  {
    points.clear();
    for (const auto &c : normal_conditions)
      if (c.kind != NormalCondition::Kind::roller && owned.is_element(c.dofs_k[0]) && is_active(c))
        points.emplace_back(c.position[0], c.position[1]);
  }



  // Kelly's indicator written out for the displacement of each body: eta_K^2 =
  // h_K sum over the faces of K inside its body of int |[grad u] n|^2. The
  // library's KellyErrorEstimator would also integrate across a contact
  // interface, where the two bodies' displacements are independent (the
  // neighbour's slot is FE_Nothing there) and the "jump" is the whole gradient.
  template <int dim>
  void MechanicalField<dim>::error_indicator(dealii::Vector<float> &indicator) const
  {
    indicator.reinit(triangulation.n_active_cells());
    hp::QCollection<dim - 1> quadrature;
    for (unsigned int i = 0; i < fe.size(); ++i)
      quadrature.push_back(QGauss<dim - 1>(2));
    const UpdateFlags     flags = update_gradients | update_JxW_values | update_normal_vectors;
    hp::FEFaceValues<dim> face_values(fe, quadrature, flags),
      neighbor_face_values(fe, quadrature, flags);
    hp::FESubfaceValues<dim> subface_values(fe, quadrature, flags),
      neighbor_subface_values(fe, quadrature, flags);
    const unsigned int          n_q = quadrature[0].size();
    std::vector<Tensor<2, dim>> mine(n_q), theirs(n_q);
    const auto                  jump =
      [&](const FEValuesBase<dim> &here, const FEValuesBase<dim> &there, const unsigned int slot) {
        const FEValuesExtractors::Vector u(dim * slot);
        here[u].get_function_gradients(displacement_ghosted, mine);
        there[u].get_function_gradients(displacement_ghosted, theirs);
        double integral = 0;
        for (unsigned int q = 0; q < n_q; ++q)
          integral += ((mine[q] - theirs[q]) * here.normal_vector(q)).norm_square() * here.JxW(q);
        return integral;
      };
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int slot = cell->active_fe_index();
          double             sum  = 0;
          for (const unsigned int face : cell->face_indices())
            {
              if (cell->face(face)->at_boundary() ||
                  cell->neighbor(face)->material_id() != cell->material_id())
                continue;
              const auto neighbor = cell->neighbor(face);
              if (neighbor->has_children())
                for (unsigned int sub = 0; sub < cell->face(face)->n_children(); ++sub)
                  {
                    const auto child = cell->neighbor_child_on_subface(face, sub);
                    subface_values.reinit(cell, face, sub);
                    neighbor_face_values.reinit(child, cell->neighbor_of_neighbor(face));
                    sum += jump(subface_values.get_present_fe_values(),
                                neighbor_face_values.get_present_fe_values(),
                                slot);
                  }
              else if (cell->neighbor_is_coarser(face))
                {
                  const auto [their_face, their_sub] = cell->neighbor_of_coarser_neighbor(face);
                  face_values.reinit(cell, face);
                  neighbor_subface_values.reinit(neighbor, their_face, their_sub);
                  sum += jump(face_values.get_present_fe_values(),
                              neighbor_subface_values.get_present_fe_values(),
                              slot);
                }
              else
                {
                  face_values.reinit(cell, face);
                  neighbor_face_values.reinit(neighbor, cell->neighbor_of_neighbor(face));
                  sum += jump(face_values.get_present_fe_values(),
                              neighbor_face_values.get_present_fe_values(),
                              slot);
                }
            }
          indicator(cell->active_cell_index()) = std::sqrt(cell->diameter() * sum);
        }
  }



  template void ThermalField<2>::front_points(std::vector<Point<2>> &) const;
  template void ThermalField<2>::error_indicator(dealii::Vector<float> &) const;
  template void MechanicalField<2>::contact_points(std::vector<Point<2>> &) const;
  template void MechanicalField<2>::error_indicator(dealii::Vector<float> &) const;
} // namespace ContactStefan
