// MechanicalField: the reference states of the material points of bodies that
// are stress-free at solidification (doc/solidification.md).
//
// The stress of a material point (corner q of a cell: Gauss point q for the
// elastic part, vertex q for the thermal part) is
//     sigma = C_K : (e - e_ref,q) - beta_K (Theta_q - Theta_ref,q),
// so the discrete equilibrium gains, besides the thermal load B_K (Theta -
// Theta_ref), the load of the reference strains with the stiffness's own rule,
//     f_i = sum_q w_q e(phi_i)(x_q) : C_K : e_ref,q.
// A cell whose four points are born together from the displacement u_n thus
// gets f = K_K u_n: the cell is exactly stress-free in the configuration u_n,
// whatever the mesh.
//
// When. The stiffness of a cell is lagged at the phases of the last step's
// end (coupled_problem.cc); births are lagged the same way: before step n+1,
// a point whose node changed class during step n (the enthalpy step's phase
// state, exactly, with Materials/Body N/Phase change/Solid fraction at birth)
// is born at the transition temperature, with the strain of the moment within
// step n at which its enthalpy passed the birth value (u linear in time).
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <contact-stefan/mechanics/mechanical_field.h>

namespace ContactStefan
{
  template <int dim>
  bool MechanicalField<dim>::keeps_history(
    const typename DoFHandler<dim>::active_cell_iterator &cell) const
  {
    return history && prm.materials.at(cell->material_id()).stress_free_at_solidification;
  }



  template <int dim>
  CornerReference MechanicalField<dim>::corner_reference(const unsigned int cell_index,
                                                         const unsigned int v) const
  {
    if (!history)
      return CornerReference();
    return (*history)[cell_index][v];
  }



  template <int dim>
  void MechanicalField<dim>::initialize_references(const CellVertexValues &solid_fraction,
                                                   const double            t0)
  {
    if (!history)
      return;
    history->resize();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int c    = cell->active_cell_index();
          const auto        &body = prm.materials.at(cell->material_id());
          for (unsigned int v = 0; v < 4; ++v)
            {
              CornerReference &corner = (*history)[c][v];
              corner.solid            = solid_fraction[c][v] >= body.birth_solid_fraction ? 1 : 0;
              corner.time             = t0;
              // Solid at the start: the scene's reference (e = 0 at Theta_0).
              // Melt at the start: referenced to the melt, e_ref = 0 at the
              // transition temperature (a melt keeps no memory of Theta_0,
              // and melt and new crust are both stress-free at the front).
              if (keeps_history(cell) && corner.solid == 0)
                {
                  corner.born  = 1;
                  corner.theta = body.transition_temperatures.back();
                }
            }
        }
  }



  template <int dim>
  unsigned int MechanicalField<dim>::update_references(const CellVertexValues &solid_fraction,
                                                       const CellVertexValues &crossing,
                                                       const double            t,
                                                       const double            tau,
                                                       const bool              lagged_displacement)
  {
    if (!history)
      return 0;
    TimerOutput::Scope         timer_scope(timer, "coupling: solidification references");
    const hp::QCollection<dim> gauss(QGauss<dim>(2));
    hp::FEValues<dim>          gauss_values(fe, gauss, update_gradients);
    Vector                     u_before(owned, relevant, mpi_communicator);
    u_before = old_displacement;
    std::vector<SymmetricTensor<2, dim>> strain_before(4), strain_after(4);
    unsigned int                         born = 0;
    references_changed.resize(triangulation.n_active_cells(), false);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && keeps_history(cell))
        {
          const unsigned int c           = cell->active_cell_index();
          const auto        &body        = prm.materials.at(cell->material_id());
          bool               have_strain = false;
          for (unsigned int v = 0; v < 4; ++v)
            {
              CornerReference &corner    = (*history)[c][v];
              // A melt point freezes at the birth threshold, a solid point
              // melts below the melting threshold (a hysteresis when lower).
              const bool solid_now =
                solid_fraction[c][v] >=
                (corner.solid != 0 ? body.melting_solid_fraction : body.birth_solid_fraction);
              if ((corner.solid != 0) == solid_now)
                continue;
              if (!have_strain)
                {
                  // The strains at the step's start and end at the four Gauss
                  // points (Gauss point v lies in the quadrant of vertex v).
                  gauss_values.reinit(cell);
                  const FEValues<dim>             &fv = gauss_values.get_present_fe_values();
                  const FEValuesExtractors::Vector u(slot_of_body.at(cell->material_id()) * dim);
                  fv[u].get_function_symmetric_gradients(u_before, strain_before);
                  fv[u].get_function_symmetric_gradients(displacement_ghosted, strain_after);
                  have_strain = true;
                }
              // Born when the node's enthalpy passed the birth value, a
              // fraction s of the step (linear in time): the strain and the
              // time interpolated to that moment, at which the node was at
              // the transition temperature. (At the step's end the node may
              // already be colder; taking that strain with Theta_ref =
              // Theta_m would count the cooling in between twice.)
              // With the staggered scheme u_n is the equilibrium with the
              // temperature of t_(n-1) (the contact step comes first), so the
              // strain of the moment t_(n-1) + s tau is extrapolated from
              // u_(n-1), u_n: u_n + s (u_n - u_(n-1)).
              const double s = crossing[c][v];
              const SymmetricTensor<2, dim> strain =
                lagged_displacement ? strain_after[v] + s * (strain_after[v] - strain_before[v]) :
                                      (1. - s) * strain_before[v] + s * strain_after[v];
              // The body's e_zz likewise (generalized plane strain; zero otherwise).
              const unsigned int slot   = slot_of_body.at(cell->material_id());
              const double       e_zz   = out_of_plane_strain(slot);
              const double       e_zz_0 = generalized_plane_strain ? old_ezz[slot] : 0.;
              const double       strain_zz =
                lagged_displacement ? e_zz + s * (e_zz - e_zz_0) : (1. - s) * e_zz_0 + s * e_zz;
              born += update_corner(corner,
                                    solid_now,
                                    strain,
                                    body.transition_temperatures.back(),
                                    t - (1. - s) * tau,
                                    strain_zz);
              references_changed[c] = true;
            }
        }
    return Utilities::MPI::sum(born, mpi_communicator);
  }



  template <int dim>
  void MechanicalField<dim>::apply_references(const bool all_cells)
  {
    if (!history)
      return;
    TimerOutput::Scope         timer_scope(timer, "coupling: solidification references");
    // Only the cells whose references (a birth) or moduli (a new phase
    // mixture) changed since the last call, unless asked for all of them (a
    // new mesh, the initial state, a resume): the load and its projection
    // depend on nothing else.
    const bool all = all_cells || cell_reference_load.size() != triangulation.n_active_cells();
    if (all)
      {
        cell_reference_load.assign(triangulation.n_active_cells(), dealii::Vector<double>());
        cell_vertex_reference_strain.assign(triangulation.n_active_cells(), {});
        cell_reference_displacement.assign(triangulation.n_active_cells(),
                                           dealii::Vector<double>());
        if (generalized_plane_strain)
          cell_ezz_reference.assign(triangulation.n_active_cells(), 0.);
      }
    references_changed.resize(triangulation.n_active_cells(), false);
    const hp::QCollection<dim> gauss(QGauss<dim>(2));
    hp::FEValues<dim>          gauss_values(fe, gauss, update_gradients | update_JxW_values);
    const hp::QCollection<dim> vertex_rule(QTrapezoid<dim>{});
    hp::FEValues<dim>          vertex_values(fe, vertex_rule, update_gradients);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned() && keeps_history(cell) &&
          (all || references_changed[cell->active_cell_index()]))
        {
          const unsigned int c  = cell->active_cell_index();
          references_changed[c] = false;
          cell_reference_load[c].reinit(0);
          cell_reference_displacement[c].reinit(0);
          if (generalized_plane_strain)
            cell_ezz_reference[c] = 0;
          bool any_strain = false;
          for (unsigned int v = 0; v < 4; ++v)
            {
              const CornerReference &corner = (*history)[c][v];
              // Theta_ref: the birth temperature of a born point; Theta_0 of
              // the scene at the vertex otherwise (set with the cell operators;
              // at a hanging vertex the mean of the coarse face's ends).
              if (corner.born != 0)
                cell_reference[c][v] = corner.theta;
              any_strain =
                any_strain || corner.reference_strain().norm() != 0 || corner.strain[3] != 0;
            }
          if (!any_strain)
            continue;
          gauss_values.reinit(cell);
          const FEValues<dim>             &fv = gauss_values.get_present_fe_values();
          const FEValuesExtractors::Vector u(slot_of_body.at(cell->material_id()) * dim);
          const unsigned int               n = fv.get_fe().n_dofs_per_cell();
          dealii::Vector<double>          &f = cell_reference_load[c];
          f.reinit(n);
          for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
            {
              const SymmetricTensor<2, dim> stress =
                cell_moduli[c].C * (*history)[c][q].reference_strain();
              for (unsigned int i = 0; i < n; ++i)
                f(i) += fv[u].symmetric_gradient(i, q) * stress * fv.JxW(q);
            }
          // The part of e_ref the element can hold: the strain of u_ref =
          // K_K^+ f (K_K u_ref = f, u_ref free of rigid motion; f is
          // self-equilibrated). Points born at different steps give a
          // reference strain that jumps inside the cell, which a Q1 strain
          // cannot follow; the rest loads nothing (it is orthogonal to every
          // element strain in the C-weighted Gauss product) and would only
          // add a constant, spurious energy and stress at the points. The
          // point values (stress() at the vertices; the elastic energy, with
          // u_ref itself, at the Gauss points) use the projected strain; its
          // mean over the Gauss points is the mean of e_ref (take a constant
          // test strain), so the cell-centre values are the same either way.
          LAPACKFullMatrix<double> K(n, n);
          K = cell_stiffness[c];
          K.compute_inverse_svd_with_kernel(3);
          dealii::Vector<double> u_ref(n);
          K.vmult(u_ref, f);
          cell_reference_displacement[c] = u_ref;
          vertex_values.reinit(cell);
          const FEValues<dim> &fw = vertex_values.get_present_fe_values();
          auto                &e  = cell_vertex_reference_strain[c];
          for (unsigned int v = 0; v < 4; ++v)
            {
              e[v] = SymmetricTensor<2, dim>();
              for (unsigned int i = 0; i < n; ++i)
                e[v] += u_ref(i) * fw[u].symmetric_gradient(i, v);
            }
          // Generalized plane strain: the reference e_zz of each point loads
          // the plane through lambda_zz and adds to the body's out-of-plane
          // force (out_of_plane.cc); the point values read it per corner, it
          // needs no projection (e_zz is not a field of the element).
          if (generalized_plane_strain)
            for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
              {
                const CornerReference &corner = (*history)[c][q];
                const double           e_zz   = corner.strain[3];
                for (unsigned int i = 0; i < n; ++i)
                  f(i) += cell_moduli[c].lambda_zz * e_zz * trace(fv[u].symmetric_gradient(i, q)) *
                          fv.JxW(q);
                cell_ezz_reference[c] +=
                  (cell_moduli[c].lambda_zz * trace(corner.reference_strain()) +
                   cell_moduli[c].modulus_zz * e_zz) *
                  fv.JxW(q);
              }
        }
  }



  template bool
  MechanicalField<2>::keeps_history(const typename DoFHandler<2>::active_cell_iterator &cell) const;
  template CornerReference MechanicalField<2>::corner_reference(const unsigned int,
                                                                const unsigned int) const;
  template void MechanicalField<2>::initialize_references(const CellVertexValues &, const double);
  template unsigned int MechanicalField<2>::update_references(const CellVertexValues &,
                                                              const CellVertexValues &,
                                                              const double,
                                                              const double,
                                                              const bool);
  template void         MechanicalField<2>::apply_references(const bool);
} // namespace ContactStefan
