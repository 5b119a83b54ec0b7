// MechanicalField: generalized plane strain (doc/model.md).
//
// A long body that is free at its ends is neither in plane strain (e_zz = 0,
// held at the ends) nor in plane stress: its cross-sections stay plane and
// move apart uniformly, e_zz = e_b over body b, with no net out-of-plane
// force. With e_b as one more unknown per body the potential energy is
//     Pi(u, e) = 1/2 u.K u + sum_b (e_b g_b.u + 1/2 a_b e_b^2 - e_b F_b) - f.u,
//     g_b,i = int_b lambda_zz tr e(phi_i),   a_b = int_b C_zzzz,
//     F_b   = int_b beta_zz (Theta - Theta_ref)   (+ the reference strains),
// so the in-plane equilibrium gains the load -g_b e_b (sigma_xx and sigma_yy
// carry lambda_zz e_b) and dPi/de_b = int_b sigma_zz = 0 closes the system.
// The strain terms use the stiffness's Gauss rule, the thermal term the
// vertex rule of the thermal load: a body heated uniformly and free to expand
// is stress-free to round-off on any mesh (u = alpha dT x, e_b = alpha dT).
//
// The e_b are condensed out of each linear solve of the contact step exactly
// (the Sherman-Morrison-Woodbury formula): after the solve for the current e,
// the response W_c (K W_c = g_c with the homogeneous constraints of the
// current active set) of each body's unit e_zz gives u(e') = u - sum_c W_c
// (e'_c - e_c), and the forces N_b(e') = 0 are a small symmetric positive
// definite system M de = -N with M_bc = a_b delta_bc - g_b.W_c. The W_c are
// one extra solve per body with the factorisation (or preconditioner) the
// solve just used, redone only when the matrix changes (a new active set, a
// phase change, a new mesh). The contact active set, which reads the
// multipliers from K u - f + g e, stays exact.
#include <deal.II/base/array_view.h>
#include <deal.II/base/mpi.h>

#include <deal.II/lac/full_matrix.h>

#include <contact-stefan/mechanics/mechanical_field.h>

namespace ContactStefan
{
  namespace
  {
    // The sum over all ranks, entry by entry.
    std::vector<double> sum_over_ranks(const std::vector<double> &local, const MPI_Comm comm)
    {
      std::vector<double> global(local.size());
      Utilities::MPI::sum(make_array_view(local), comm, make_array_view(global));
      return global;
    }

    // g_K . x_K: the out-of-plane force of a cell's strain for the nodal
    // values x (ghosted), or its part of g_b . W_c.
    template <class CellIterator, class GhostedVector>
    double coupling_product(const dealii::Vector<double>         &g,
                            const CellIterator                   &cell,
                            const GhostedVector                  &x,
                            std::vector<types::global_dof_index> &dofs)
    {
      dofs.resize(g.size());
      cell->get_dof_indices(dofs);
      double sum = 0;
      for (unsigned int i = 0; i < g.size(); ++i)
        sum += g(i) * x[dofs[i]];
      return sum;
    }
  } // namespace



  template <int dim>
  void MechanicalField<dim>::assemble_out_of_plane_operators(const unsigned int   c,
                                                             const FEValues<dim> &fe_values,
                                                             const FEValuesExtractors::Vector &u)
  {
    const ElasticModuli    &moduli = cell_moduli[c];
    const unsigned int      n      = fe_values.get_fe().n_dofs_per_cell();
    dealii::Vector<double> &g      = cell_ezz_coupling[c];
    g.reinit(n);
    double a = 0;
    for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
      {
        for (unsigned int i = 0; i < n; ++i)
          g(i) +=
            moduli.lambda_zz * trace(fe_values[u].symmetric_gradient(i, q)) * fe_values.JxW(q);
        a += moduli.modulus_zz * fe_values.JxW(q);
      }
    cell_ezz_stiffness[c] = a;
  }



  template <int dim>
  std::vector<double>
  MechanicalField<dim>::local_out_of_plane_forces(const Vector        &u_ghosted,
                                                  std::vector<double> *scale) const
  {
    std::vector<double>                  force(slot_of_body.size(), 0.);
    std::vector<types::global_dof_index> dofs;
    if (scale != nullptr)
      scale->assign(slot_of_body.size(), 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int c    = cell->active_cell_index();
          const unsigned int slot = slot_of_body.at(cell->material_id());
          const double       strain = coupling_product(cell_ezz_coupling[c], cell, u_ghosted, dofs);
          double             thermal = 0;
          if (thermal_stress)
            for (unsigned int v = 0; v < 4; ++v)
              thermal += cell_ezz_thermal[c][v] * cell_theta_excess[c][v];
          const double uniform   = cell_ezz_stiffness[c] * ezz[slot];
          const double reference = c < cell_ezz_reference.size() ? cell_ezz_reference[c] : 0.;
          force[slot] += strain + uniform - thermal - reference;
          if (scale != nullptr)
            (*scale)[slot] +=
              std::abs(strain) + std::abs(uniform) + std::abs(thermal) + std::abs(reference);
        }
    return force;
  }



  template <int dim>
  std::vector<double> MechanicalField<dim>::out_of_plane_forces() const
  {
    const unsigned int n_slots = slot_of_body.size();
    if (!generalized_plane_strain)
      return std::vector<double>(n_slots, 0.);
    std::vector<double> scale;
    std::vector<double> force =
      sum_over_ranks(local_out_of_plane_forces(displacement_ghosted, &scale), mpi_communicator);
    scale = sum_over_ranks(scale, mpi_communicator);
    for (unsigned int b = 0; b < n_slots; ++b)
      force[b] = scale[b] > 0 ? force[b] / scale[b] : 0.;
    return force;
  }



  template <int dim>
  void MechanicalField<dim>::balance_out_of_plane(const bool new_matrix)
  {
    if (!generalized_plane_strain)
      return;
    TimerOutput::Scope                   t(timer, "contact step: out-of-plane strain");
    const unsigned int                   n_slots = slot_of_body.size();
    std::vector<types::global_dof_index> dofs;
    if (new_matrix || ezz_response.size() != n_slots ||
        ezz_response[0].size() != displacement.size())
      {
        // The inhomogeneities of the constraints alone: distribute() of a
        // zero vector. W = distribute(solution) - them satisfies the
        // homogeneous constraints.
        Vector inhomogeneity(owned, mpi_communicator);
        constraints.distribute(inhomogeneity);
        ezz_response.resize(n_slots);
        for (unsigned int b = 0; b < n_slots; ++b)
          {
            Vector rhs(owned, mpi_communicator);
            for (const auto &cell : dof_handler.active_cell_iterators())
              if (cell->is_locally_owned() && slot_of_body.at(cell->material_id()) == b)
                {
                  const auto &g = cell_ezz_coupling[cell->active_cell_index()];
                  dofs.resize(g.size());
                  cell->get_dof_indices(dofs);
                  // Without the matrix argument: no inhomogeneity part.
                  constraints.distribute_local_to_global(g, dofs, rhs);
                }
            rhs.compress(VectorOperation::add);
            if (ezz_response[b].size() != displacement.size())
              ezz_response[b].reinit(owned, mpi_communicator);
            linear_solver.solve(ezz_response[b], rhs, linear_prm.cg_tolerance);
            constraints.distribute(ezz_response[b]);
            ezz_response[b] -= inhomogeneity;
          }
      }
    // M_bc = a_b delta_bc - g_b.W_c and the forces N_b of the solution for
    // the current e.
    FullMatrix<double>  M(n_slots, n_slots);
    std::vector<double> local_a(n_slots, 0.);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        local_a[slot_of_body.at(cell->material_id())] +=
          cell_ezz_stiffness[cell->active_cell_index()];
    const std::vector<double> a = sum_over_ranks(local_a, mpi_communicator);
    for (unsigned int c = 0; c < n_slots; ++c)
      {
        Vector w(owned, relevant, mpi_communicator);
        w = ezz_response[c];
        std::vector<double> gw(n_slots, 0.);
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            gw[slot_of_body.at(cell->material_id())] +=
              coupling_product(cell_ezz_coupling[cell->active_cell_index()], cell, w, dofs);
        gw = sum_over_ranks(gw, mpi_communicator);
        for (unsigned int b = 0; b < n_slots; ++b)
          M(b, c) = (b == c ? a[b] : 0.) - gw[b];
      }
    const std::vector<double> force =
      sum_over_ranks(local_out_of_plane_forces(displacement_ghosted), mpi_communicator);
    for (unsigned int b = 0; b < n_slots; ++b)
      AssertThrow(M(b, b) > 0 && std::isfinite(M(b, b)),
                  ExcMessage("generalized plane strain: the out-of-plane stiffness of body " +
                             std::to_string(prm.body_ids[b]) +
                             " is not positive (is the body held against rigid motion?)"));
    M.gauss_jordan();
    dealii::Vector<double> minus_force(n_slots), de(n_slots);
    for (unsigned int b = 0; b < n_slots; ++b)
      minus_force(b) = -force[b];
    M.vmult(de, minus_force);
    for (unsigned int c = 0; c < n_slots; ++c)
      {
        ezz[c] += de(c);
        displacement.add(-de(c), ezz_response[c]);
      }
    displacement_ghosted = displacement;
  }



  template <int dim>
  std::vector<double> MechanicalField<dim>::restart_state() const
  {
    std::vector<double> state = ezz;
    state.insert(state.end(), old_ezz.begin(), old_ezz.end());
    return state;
  }



  template <int dim>
  void MechanicalField<dim>::set_restart_state(const std::vector<double> &state)
  {
    AssertThrow(state.size() == 2 * ezz.size(),
                ExcMessage("the checkpoint's out-of-plane strains do not match the bodies"));
    std::copy(state.begin(), state.begin() + ezz.size(), ezz.begin());
    std::copy(state.begin() + ezz.size(), state.end(), old_ezz.begin());
  }



  template void
  MechanicalField<2>::assemble_out_of_plane_operators(const unsigned int,
                                                      const FEValues<2> &,
                                                      const FEValuesExtractors::Vector &);
  template std::vector<double>
  MechanicalField<2>::local_out_of_plane_forces(const Vector &, std::vector<double> *) const;
  template std::vector<double> MechanicalField<2>::out_of_plane_forces() const;
  template void                MechanicalField<2>::balance_out_of_plane(const bool);
  template std::vector<double> MechanicalField<2>::restart_state() const;
  template void                MechanicalField<2>::set_restart_state(const std::vector<double> &);
} // namespace ContactStefan
