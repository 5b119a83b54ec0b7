// Recovered nodal fields that respect the bodies: include/contact-stefan/core/body_recovery.h.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>

#include <deal.II/hp/fe_values.h>

#include <contact-stefan/core/body_recovery.h>
#include <contact-stefan/core/slot_sum.h>

namespace ContactStefan
{
  template <int dim>
  void recover_pair_in_slots(const DoFHandler<dim>                      &dof_handler,
                             const AffineConstraints<double>            &hanging_node_constraints,
                             const std::map<unsigned int, unsigned int> &slot_of_body,
                             const unsigned int                          components_per_slot,
                             const std::vector<std::array<double, 2>>   &cell_values,
                             const IndexSet                             &owned,
                             const MPI_Comm                              mpi_communicator,
                             Vector                                     &nodal)
  {
    // Lumped mass: the vertex rule's weight of each vertex (a quarter of the
    // cell's area on a parallelogram).
    const hp::QCollection<dim> vertex_rule(QTrapezoid<dim>{});
    hp::FEValues<dim> hp_values(dof_handler.get_fe_collection(), vertex_rule, update_JxW_values);
    Vector            weighted(owned, mpi_communicator), mass(owned, mpi_communicator);
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_values.reinit(cell);
          const FEValues<dim> &fv = hp_values.get_present_fe_values();
          const unsigned int   n  = fv.get_fe().n_dofs_per_cell();
          const unsigned int   c0 = slot_of_body.at(cell->material_id()) * components_per_slot;
          dofs.resize(n);
          cell->get_dof_indices(dofs);
          dealii::Vector<double> local_weighted(n), local_mass(n);
          for (unsigned int i = 0; i < n; ++i)
            {
              // FE_Q(1): the index within the base element is the vertex.
              const auto [component, vertex] = fv.get_fe().system_to_component_index(i);
              local_mass(i)                  = fv.JxW(vertex);
              local_weighted(i) =
                fv.JxW(vertex) * cell_values[cell->active_cell_index()][component - c0];
            }
          hanging_node_constraints.distribute_local_to_global(local_weighted, dofs, weighted);
          hanging_node_constraints.distribute_local_to_global(local_mass, dofs, mass);
        }
    weighted.compress(VectorOperation::add);
    mass.compress(VectorOperation::add);
    nodal.reinit(owned, mpi_communicator);
    for (const auto dof : owned)
      if (mass[dof] > 0)
        nodal[dof] = weighted[dof] / mass[dof];
    nodal.compress(VectorOperation::insert);
    hanging_node_constraints.distribute(nodal);
  }



  template <int dim>
  BodyRecovery<dim>::BodyRecovery(const Triangulation<dim>        &triangulation,
                                  const std::vector<unsigned int> &body_ids,
                                  const MPI_Comm                   mpi_communicator)
    : triangulation(triangulation)
    , mpi_communicator(mpi_communicator)
    , dof_handler(triangulation)
  {
    const unsigned int n_slots = body_ids.size();
    for (unsigned int s = 0; s < n_slots; ++s)
      slot_of_body[body_ids[s]] = s;
    fe          = slot_elements<dim>(n_slots, 2);
    mesh_change = triangulation.signals.any_change.connect([this]() { mesh_changed = true; });
  }



  template <int dim>
  BodyRecovery<dim>::~BodyRecovery()
  {
    mesh_change.disconnect();
  }



  template <int dim>
  void BodyRecovery<dim>::recover(const std::vector<std::array<double, 2>> &cell_values)
  {
    if (mesh_changed)
      {
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            cell->set_active_fe_index(slot_of_body.at(cell->material_id()));
        dof_handler.distribute_dofs(fe);
        owned = dof_handler.locally_owned_dofs();
        DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
        hanging_node_constraints.clear();
        hanging_node_constraints.reinit(relevant);
        DoFTools::make_hanging_node_constraints(dof_handler, hanging_node_constraints);
        hanging_node_constraints.close();
        mesh_changed = false;
      }
    Vector nodal;
    recover_pair_in_slots(dof_handler,
                          hanging_node_constraints,
                          slot_of_body,
                          2,
                          cell_values,
                          owned,
                          mpi_communicator,
                          nodal);
    ghosted.reinit(owned, relevant, mpi_communicator);
    ghosted = nodal;
  }



  template <int dim>
  void BodyRecovery<dim>::add_output(DataOut<dim> &data_out, const std::vector<std::string> &names)
  {
    postprocessor = std::make_unique<BodyPair<dim>>(slot_of_body, 2, names);
    data_out.add_data_vector(dof_handler, ghosted, *postprocessor);
  }



  template <int dim>
  void BodyRecovery<dim>::for_each_vertex(
    const std::function<
      void(const Point<dim> &, double, const std::array<double, 2> &, const Point<dim> &)> &visit)
    const
  {
    const hp::QCollection<dim> vertex_rule(QTrapezoid<dim>{});
    hp::FEValues<dim> hp_values(fe, vertex_rule, update_JxW_values | update_quadrature_points);
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          hp_values.reinit(cell);
          const FEValues<dim> &fv      = hp_values.get_present_fe_values();
          const auto          &cell_fe = cell->get_fe();
          const unsigned int   c0      = slot_of_body.at(cell->material_id()) * 2;
          dofs.resize(cell_fe.n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < GeometryInfo<dim>::vertices_per_cell; ++v)
            visit(fv.quadrature_point(v),
                  fv.JxW(v),
                  {{ghosted[dofs[cell_fe.component_to_system_index(c0, v)]],
                    ghosted[dofs[cell_fe.component_to_system_index(c0 + 1, v)]]}},
                  cell->center());
        }
  }



  template void recover_pair_in_slots<2>(const DoFHandler<2> &,
                                         const AffineConstraints<double> &,
                                         const std::map<unsigned int, unsigned int> &,
                                         const unsigned int,
                                         const std::vector<std::array<double, 2>> &,
                                         const IndexSet &,
                                         const MPI_Comm,
                                         Vector &);
  template class BodyRecovery<2>;
} // namespace ContactStefan
