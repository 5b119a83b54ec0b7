// MechanicalField: the right-hand side of the contact step's linear system,
// the cells' loads (body and surface loads, thermal stress, the in-plane
// stress of e_zz) condensed with the current constraints.
//
// It comes from the vector-only condensation (the cell matrices carry the
// inhomogeneities in), so that every solve of an active set sees the same
// vector to the last bit, whether its matrix was re-assembled or not; a cell
// without load, thermal stress or constrained DoF adds nothing and is skipped.
// On one MPI rank a cell none of whose DoFs is constrained (away from the
// contact conditions and the fixed constraints, hanging nodes included) adds
// its load straight into the vector's entries: the same sums in the same
// order as deal.II's condensation, without its per-entry look-ups through the
// vector's map (a third of a linear thermoelastic step's assembly before).
#include <contact-stefan/mechanics/mechanical_field.h>

namespace ContactStefan
{
  template <int dim>
  void MechanicalField<dim>::assemble_right_hand_side()
  {
    system_rhs            = 0;
    const bool    loaded  = functions.mechanical_load_present();
    const bool    serial  = Utilities::MPI::n_mpi_processes(mpi_communicator) == 1;
    double *const entries = system_rhs.trilinos_vector()[0];
    std::vector<types::global_dof_index> dofs;
    dealii::Vector<double>               rhs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int index = cell->active_cell_index();
          const bool         free  = !cell_near_contact[index] && !cell_fixed_constrained[index];
          if (!loaded && !thermal_stress && !generalized_plane_strain && free)
            continue;
          const unsigned int n = cell->get_fe().n_dofs_per_cell();
          if (rhs.size() != n)
            rhs.reinit(n, true);
          if (loaded)
            rhs = cell_load[index];
          else
            rhs = 0;
          if (thermal_stress)
            for (unsigned int i = 0; i < n; ++i)
              rhs[i] += cell_thermal_load[index][i];
          // The in-plane stress of the body's e_zz (out_of_plane.cc).
          if (generalized_plane_strain)
            rhs.add(-ezz[slot_of_body.at(cell->material_id())], cell_ezz_coupling[index]);
          if (serial && free)
            {
              // (One rank: the owned vector's entries are the relevant ones,
              // in cell_entry's layout.)
              const auto &entry = cell_entry[index];
              for (unsigned int i = 0; i < n; ++i)
                entries[entry[i]] += rhs[i];
              continue;
            }
          dofs.resize(n);
          cell->get_dof_indices(dofs);
          constraints.distribute_local_to_global(rhs, dofs, system_rhs, cell_stiffness[index]);
        }
    system_rhs.compress(VectorOperation::add);
  }



  template void MechanicalField<2>::assemble_right_hand_side();
} // namespace ContactStefan
