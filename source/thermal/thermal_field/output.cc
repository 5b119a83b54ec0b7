// ThermalField: the fields it writes (doc/output.md): temperature, enthalpy,
// phase index and liquid fraction at the nodes (with several slots, each cell
// shows its own side of a conductance interface), and the heat flux at the
// cell centres and recovered onto each body's nodes.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <contact-stefan/core/slot_sum.h>
#include <contact-stefan/thermal/thermal_field.h>

namespace ContactStefan
{
  template <int dim>
  void ThermalField<dim>::add_output(DataOut<dim> &data_out) const
  {
    Vector phase_index(owned, mpi_communicator), liquid(owned, mpi_communicator);
    for (const auto dof : owned)
      {
        phase_index[dof] = law(dof).phase_index(enthalpy[dof]);
        liquid[dof]      = law(dof).liquid_fraction(enthalpy[dof]);
      }
    phase_index.compress(VectorOperation::insert);
    liquid.compress(VectorOperation::insert);
    output_phase_index.reinit(owned, relevant, mpi_communicator);
    output_liquid_fraction.reinit(owned, relevant, mpi_communicator);
    output_phase_index     = phase_index;
    output_liquid_fraction = liquid;
    if (n_slots == 1)
      {
        data_out.add_data_vector(dof_handler, temperature_ghosted, "temperature");
        data_out.add_data_vector(dof_handler, enthalpy_ghosted, "enthalpy");
        data_out.add_data_vector(dof_handler, output_phase_index, "phase_index");
        data_out.add_data_vector(dof_handler, output_liquid_fraction, "liquid_fraction");
      }
    else
      {
        // Each cell shows its own slot (the others are FE_Nothing there): the
        // two sides of a conductance interface keep their own values.
        output_slot_sums.clear();
        using Named = std::pair<const Vector *, const char *>;
        for (const auto &[vector, name] : {Named(&temperature_ghosted, "temperature"),
                                           Named(&enthalpy_ghosted, "enthalpy"),
                                           Named(&output_phase_index, "phase_index"),
                                           Named(&output_liquid_fraction, "liquid_fraction")})
          {
            output_slot_sums.push_back(std::make_shared<SlotSum<dim>>(name, n_slots, 1));
            data_out.add_data_vector(dof_handler, *vector, *output_slot_sums.back());
          }
      }

    // The heat flux at the cell centres (cell data; where the gradient of Q1
    // is accurate, doc/output.md) and recovered onto each body's nodes (point
    // data): never averaged across an interface, where its tangential part
    // jumps with the conductivity.
    const std::vector<std::array<double, 2>> flux = cell_centre_heat_flux();
    for (unsigned int d = 0; d < 2; ++d)
      {
        output_heat_flux[d].reinit(flux.size());
        for (unsigned int c = 0; c < flux.size(); ++c)
          output_heat_flux[d](c) = flux[c][d];
      }
    data_out.add_data_vector(output_heat_flux[0], "cell_heat_flux_x", DataOut<dim>::type_cell_data);
    data_out.add_data_vector(output_heat_flux[1], "cell_heat_flux_y", DataOut<dim>::type_cell_data);
    {
      TimerOutput::Scope t(timer, "output: heat flux");
      recover_heat_flux(flux);
    }
    heat_flux_recovery->add_output(data_out, {"heat_flux_x", "heat_flux_y"});
  }



  template <int dim>
  std::vector<std::array<double, 2>> ThermalField<dim>::cell_centre_heat_flux() const
  {
    // -k K grad(Theta) with the lagged phase mixture's conductivity.
    assert_two_dimensional<dim>();
    const QMidpoint<dim>                 centre;
    FEValues<dim>                        values(fe, centre, update_gradients);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    std::vector<std::array<double, 2>>   flux(triangulation.n_active_cells(), {{0., 0.}});
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          values.reinit(typename Triangulation<dim>::cell_iterator(cell));
          cell->get_dof_indices(dofs);
          Tensor<1, dim> gradient;
          for (unsigned int i = 0; i < dofs.size(); ++i)
            gradient += temperature_ghosted[dofs[i]] * values.shape_grad(i, 0);
          const unsigned int   c = cell->active_cell_index();
          const Tensor<1, dim> q = -cell_conductivity_factor[c] *
                                   (materials[cell->material_id()].conductivity_shape * gradient);
          flux[c] = {{q[0], q[1]}};
        }
    return flux;
  }



  template <int dim>
  void ThermalField<dim>::recover_heat_flux(const std::vector<std::array<double, 2>> &flux) const
  {
    if (!heat_flux_recovery)
      heat_flux_recovery =
        std::make_unique<BodyRecovery<dim>>(triangulation, prm.body_ids, mpi_communicator);
    heat_flux_recovery->recover(flux);
  }



  template <int dim>
  void ThermalField<dim>::for_each_recovered_vertex_heat_flux(
    const std::function<
      void(const Point<dim> &, double, const std::array<double, 2> &, const Point<dim> &)> &visit)
    const
  {
    recover_heat_flux(cell_centre_heat_flux());
    heat_flux_recovery->for_each_vertex(visit);
  }



  template void ThermalField<2>::add_output(DataOut<2> &) const;
  template std::vector<std::array<double, 2>> ThermalField<2>::cell_centre_heat_flux() const;
  template void                               ThermalField<2>::for_each_recovered_vertex_heat_flux(
    const std::function<
      void(const Point<2> &, double, const std::array<double, 2> &, const Point<2> &)> &) const;
} // namespace ContactStefan
