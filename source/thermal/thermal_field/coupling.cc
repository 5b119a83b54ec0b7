// ThermalField: its side of the thermo-mechanical coupling (doc/coupling.md).
//
// The mechanical field receives the temperature at the vertices of each cell
// and the phase weights or solid fractions of each cell; this field receives
// the thermoelastic work at the vertices. Both travel as per-cell arrays
// indexed by the active cell index of the shared triangulation, so neither
// field touches the other's DoFs.
#include <contact-stefan/thermal/thermal_field.h>

namespace ContactStefan
{
  // The absolute reference temperature at the vertices of each cell (the
  // heating coefficient) and the coupling strength gamma / rho c of each body
  // and phase; both refused where they make no sense, before any work.
  template <int dim>
  void ThermalField<dim>::setup_coupling()
  {
    cell_heating.assign(heating ? triangulation.n_active_cells() : 0, dealii::Vector<double>());
    cell_absolute_reference.assign(heating ? triangulation.n_active_cells() : 0,
                                   {{0., 0., 0., 0.}});
    max_coupling_strength = 0;
    if (!heating)
      return;
    const double                         offset = prm.coupling.absolute_offset();
    std::vector<types::global_dof_index> cell_dofs(fe.n_dofs_per_cell());
    std::string                          bad_reference, bad_strength;
    double                               strength = 0;
    // Each body's own Theta_0 where bodies meet (two_sided_vertices()).
    std::vector<bool> shared = two_sided_vertices(triangulation, prm.interface_pairs);
    if (!jumps_at(functions.reference_temperature(), triangulation, shared))
      shared.assign(shared.size(), false); // (a conductance node: node_point())
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int c = cell->active_cell_index();
          cell_heating[c].reinit(fe.n_dofs_per_cell());
          cell->get_dof_indices(cell_dofs);
          double theta_max = 0;
          for (unsigned int v = 0; v < 4; ++v)
            {
              const double theta0 = functions.reference_temperature().value(
                shared[cell->vertex_index(v)] ? point_of_side<dim>(cell, v) :
                                                node_point(cell_dofs[v], cell->vertex(v)));
              cell_absolute_reference[c][v] = theta0 + offset;
              theta_max                     = std::max(theta_max, theta0 + offset);
              if (!(theta0 + offset > 0) && bad_reference.empty())
                bad_reference = "the absolute reference temperature Theta_0 + " + number(offset) +
                                " = " + number(theta0 + offset) + " at (" +
                                number(cell->vertex(v)[0]) + ", " + number(cell->vertex(v)[1]) +
                                ") is not > 0 (see Coupling/Temperature scale)";
            }
          const Material &m = materials[cell->material_id()];
          for (unsigned int p = 0; p < m.phase_moduli.size(); ++p)
            {
              const double gamma = theta_max * m.phase_moduli[p].free_expansion_capacity(
                                                 prm.physics.generalized_plane_strain);
              const double ratio = gamma / m.enthalpy_law.heat_capacity(p);
              strength           = std::max(strength, ratio);
              // Without the thermal stress nothing feeds back: no instability.
              if (prm.thermal_stress_active() && !(ratio < 1) && bad_strength.empty())
                bad_strength =
                  "parameter 'Materials/Body " + std::to_string(cell->material_id()) +
                  "/Thermal expansion': in phase " + std::to_string(p) +
                  " the heating term adds gamma = Theta_0 beta:C^-1:beta = " + number(gamma) +
                  " to rho c = " + number(m.enthalpy_law.heat_capacity(p)) +
                  " (gamma/rho c >= 1): the staggered and the fixed-point coupled "
                  "steps both diverge (doc/coupling.md)";
            }
        }
    functions.check_finite_values(mpi_communicator);
    throw_collectively<InputError>(bad_reference.empty() ? "" :
                                                           "parameter 'Coupling/Reference "
                                                           "temperature': " +
                                                             bad_reference,
                                   mpi_communicator);
    throw_collectively<InputError>(bad_strength, mpi_communicator);
    max_coupling_strength = Utilities::MPI::max(strength, mpi_communicator);
  }



  template <int dim>
  void ThermalField<dim>::cell_temperatures(CellVertexValues &theta) const
  {
    cell_values(temperature_ghosted, theta);
  }



  template <int dim>
  void ThermalField<dim>::cell_values(const Vector &nodal, CellVertexValues &values) const
  {
    values.assign(triangulation.n_active_cells(), {{0., 0., 0., 0.}});
    // A vector of the ghosted layout (every ghosted vector of this field is
    // made on `relevant`; on one rank an owned one is the same) is read by
    // local entry (index_local_entries()), any other through its map.
    if (nodal.trilinos_vector().MyLength() == static_cast<int>(relevant_entry.size()))
      {
        const double *const entries = nodal.trilinos_vector()[0];
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            {
              const unsigned int c = cell->active_cell_index();
              for (unsigned int v = 0; v < 4; ++v)
                values[c][v] = entries[relevant_entry[cell_nodes[c][v]]];
            }
        return;
      }
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < 4; ++v)
            values[cell->active_cell_index()][v] = nodal[dofs[v]];
        }
  }



  template <int dim>
  void ThermalField<dim>::set_thermoelastic_work(const CellVertexValues &work)
  {
    if (!heating)
      return;
    TimerOutput::Scope                   t(timer, "coupling: thermoelastic heating");
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    coupling_heat = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int c = cell->active_cell_index();
          for (unsigned int v = 0; v < 4; ++v)
            cell_heating[c](v) = cell_absolute_reference[c][v] * work[c][v];
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(cell_heating[c], dofs, coupling_heat);
        }
    coupling_heat.compress(VectorOperation::add);
  }



  template <int dim>
  double ThermalField<dim>::thermoelastic_heat() const
  {
    if (!heating)
      return 0;
    double sum = 0;
    for (const auto dof : owned)
      sum -= coupling_heat[dof];
    return Utilities::MPI::sum(sum, mpi_communicator);
  }



  template <int dim>
  void ThermalField<dim>::phase_weights(const typename DoFHandler<dim>::active_cell_iterator &cell,
                                        const Vector                                         &h,
                                        std::vector<double> &weights) const
  {
    // Average over the cell's nodes of the share w_p of each phase p of this
    // body's material at the node (a node shared with another body has a mixed
    // law: its fraction through each of this body's transition temperatures).
    const EnthalpyLaw                   &body_law = laws[law_of_body.at(cell->material_id())];
    const unsigned int                   n        = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index> dofs(n);
    cell->get_dof_indices(dofs);
    weights.assign(body_law.n_transitions() + 1, 0.);
    for (unsigned int i = 0; i < n; ++i)
      {
        const EnthalpyLaw &nodal = law(dofs[i]);
        double             below = 1; // share not yet through transition j
        for (unsigned int j = 0; j < body_law.n_transitions(); ++j)
          {
            const double through =
              nodal.fraction_through_temperature(body_law.transition_temperature(j), h[dofs[i]]);
            weights[j] += (below - through) / n;
            below = through;
          }
        weights.back() += below / n;
      }
  }



  template <int dim>
  void ThermalField<dim>::cell_phase_weights(std::vector<std::vector<double>> &weights) const
  {
    weights.assign(triangulation.n_active_cells(), std::vector<double>());
    Vector h_old(owned, relevant, mpi_communicator);
    h_old = old_enthalpy;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        phase_weights(cell, h_old, weights[cell->active_cell_index()]);
  }



  template <int dim>
  void ThermalField<dim>::cell_solid_fractions(CellVertexValues &solid,
                                               CellVertexValues *crossing) const
  {
    solid.assign(triangulation.n_active_cells(), {{1., 1., 1., 1.}});
    if (crossing)
      crossing->assign(triangulation.n_active_cells(), {{1., 1., 1., 1.}});
    Vector h(owned, relevant, mpi_communicator), h_old(owned, relevant, mpi_communicator);
    h     = enthalpy;
    h_old = old_enthalpy;
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const EnthalpyLaw &body_law = laws[law_of_body.at(cell->material_id())];
          if (body_law.n_transitions() == 0)
            continue;
          const double melting  = body_law.transition_temperature(body_law.n_transitions() - 1);
          const auto  &material = prm.materials.at(cell->material_id());
          cell->get_dof_indices(dofs);
          for (unsigned int v = 0; v < 4; ++v)
            {
              const EnthalpyLaw &nodal = law(dofs[v]);
              const double       now   = h[dofs[v]];
              solid[cell->active_cell_index()][v] =
                1. - nodal.fraction_through_temperature(melting, now);
              if (!crossing)
                continue;
              // H* where the solid fraction is the threshold (the node's
              // plateau at the melting temperature, a point without one),
              // and when within the step h (linear in time) passed it: the
              // birth threshold when h fell (freezing), the melting threshold
              // when it rose (only a rise can melt a solid point).
              const double before = h_old[dofs[v]];
              const double threshold =
                now > before ? material.melting_solid_fraction : material.birth_solid_fraction;
              const auto [lower, upper] = nodal.enthalpy_range(melting);
              const double target       = lower + (1. - threshold) * (upper - lower);
              double       s            = 1.;
              if (before != now)
                s = std::min(1., std::max(0., (before - target) / (before - now)));
              (*crossing)[cell->active_cell_index()][v] = s;
            }
        }
  }



  template void   ThermalField<2>::setup_coupling();
  template void   ThermalField<2>::cell_temperatures(CellVertexValues &) const;
  template void   ThermalField<2>::cell_values(const Vector &, CellVertexValues &) const;
  template void   ThermalField<2>::set_thermoelastic_work(const CellVertexValues &);
  template double ThermalField<2>::thermoelastic_heat() const;
  template void   ThermalField<2>::phase_weights(const DoFHandler<2>::active_cell_iterator &,
                                               const Vector &,
                                               std::vector<double> &) const;
  template void   ThermalField<2>::cell_phase_weights(std::vector<std::vector<double>> &) const;
  template void ThermalField<2>::cell_solid_fractions(CellVertexValues &, CellVertexValues *) const;
} // namespace ContactStefan
