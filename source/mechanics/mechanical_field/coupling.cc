// MechanicalField: its side of the thermo-mechanical coupling (doc/coupling.md).
//
// The thermal field hands over the temperature at the vertices of each cell and
// the phase weights of each cell; this field hands back the thermoelastic work
// at the vertices. Both travel as per-cell arrays indexed by the active cell
// index of the shared triangulation, so neither field touches the other's DoFs.
//
// The thermal-stress load and the heating term use one operator per cell,
//     B_K(i, v) = w_v beta_K : e(phi_i)(x_v),
// the trapezoidal (vertex) rule with the weights w_v of the lumped mass:
//     thermal load    f_i = sum_v B_K(i, v) (Theta_v - Theta_0,v),
//     heating of v    G_v = Theta_0,v^abs sum_i B_K(i, v) (u - u_old)_i.
// With a constant Theta_0 the heating operator is Theta_0 B^T: the discrete
// counterpart of the energy identity between the two coupling terms, and a
// uniform strain rate heats every node in proportion to its lumped mass (which
// makes doc/benchmarks.md T2 and T3 exact on any mesh).
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <contact-stefan/core/q1_kernels.h>
#include <contact-stefan/interfaces/body_interface.h>
#include <contact-stefan/mechanics/mechanical_field.h>

#include <limits>

namespace ContactStefan
{
  namespace
  {
    // f_i = sum_v B_K(i, v) d_v: the thermal load of the vertex values d.
    template <class Operator, class Result>
    void apply_thermal_operator(const Operator &B, const std::array<double, 4> &d, Result &f)
    {
      for (unsigned int i = 0; i < B.size(); ++i)
        {
          double sum = 0;
          for (unsigned int v = 0; v < 4; ++v)
            sum += B[i][v] * d[v];
          f[i] = sum;
        }
    }
  } // namespace



  template <int dim>
  unsigned int
  MechanicalField<dim>::set_phase_weights(const std::vector<std::vector<double>> &weights)
  {
    TimerOutput::Scope         t(timer, "coupling: phase-dependent stiffness");
    const hp::QCollection<dim> gauss(QGauss<dim>(2));
    const hp::QCollection<dim> vertex_rule(QTrapezoid<dim>{});
    hp::FEValues<dim>          gauss_values(fe, gauss, update_gradients | update_JxW_values);
    hp::FEValues<dim>          vertex_values(
      fe, vertex_rule, update_gradients | update_JxW_values | update_quadrature_points);
    unsigned int changed = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int  c      = cell->active_cell_index();
          const ElasticModuli moduli = materials[cell->material_id()].moduli(weights[c]);
          // Exact comparison: a cell whose nodes stayed off the plateaus has
          // bitwise the same weights (0 or 1) and is left alone.
          if (moduli == cell_moduli[c])
            continue;
          cell_moduli[c] = moduli;
          assemble_cell_operators(cell, gauss_values, vertex_values);
          if (history)
            {
              references_changed.resize(triangulation.n_active_cells(), false);
              references_changed[c] = true;
            }
          ++changed;
        }
    changed = Utilities::MPI::sum(changed, mpi_communicator);
    if (changed > 0)
      {
        ++stiffness_version;
        update_stiffness_diagonal();
        update_condition_stiffness();
      }
    return changed;
  }



  template <int dim>
  void MechanicalField<dim>::set_cell_temperatures(const CellVertexValues &theta)
  {
    if (!thermal_stress)
      return;
    TimerOutput::Scope t(timer, "coupling: thermal stress load");
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int      c = cell->active_cell_index();
          auto                   &f      = cell_thermal_load[c];
          const ThermalOperator  &B      = cell_thermal_operator[c];
          auto &excess = cell_theta_excess[c];
          for (unsigned int v = 0; v < 4; ++v)
            excess[v] = theta[c][v] - cell_reference[c][v];
          apply_thermal_operator(B, excess, f);
          // The load of the reference strains (solidification.cc).
          if (history && cell_reference_load[c].size() == B.size())
            for (unsigned int i = 0; i < B.size(); ++i)
              f[i] += cell_reference_load[c][i];
        }
  }



  template <int dim>
  void MechanicalField<dim>::thermal_load_change(const CellVertexValues &theta,
                                                 const CellVertexValues &theta_before,
                                                 Vector                 &change) const
  {
    // (One MPI rank, as the block correction: the sums go to a plain vector
    // of all DoFs, which deal.II's constraints fill without a look-up per entry.)
    AssertThrow(Utilities::MPI::n_mpi_processes(mpi_communicator) == 1, ExcNotImplemented());
    dealii::Vector<double>               sum(dof_handler.n_dofs());
    std::vector<types::global_dof_index> dofs;
    dealii::Vector<double>               f;
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        const unsigned int     c = cell->active_cell_index();
        const ThermalOperator &B = cell_thermal_operator[c];
        if (f.size() != B.size())
          f.reinit(B.size(), true);
        std::array<double, 4> d;
        for (unsigned int v = 0; v < 4; ++v)
          d[v] = theta[c][v] - theta_before[c][v];
        apply_thermal_operator(B, d, f);
        dofs.resize(B.size());
        cell->get_dof_indices(dofs);
        // Without the matrix argument: the change of a load has no
        // inhomogeneity part.
        constraints.distribute_local_to_global(f, dofs, sum);
      }
    change.reinit(owned, mpi_communicator);
    std::copy(sum.begin(), sum.end(), change.trilinos_vector()[0]);
  }



  template <int dim>
  void MechanicalField<dim>::thermoelastic_work(CellVertexValues &work) const
  {
    TimerOutput::Scope t(timer, "coupling: thermoelastic work");
    work.assign(triangulation.n_active_cells(), {{0., 0., 0., 0.}});
    // The change of u over the step, with ghost entries (one vector
    // operation instead of two look-ups per cell DoF), read by local entry.
    scratch_owned = displacement;
    scratch_owned -= old_displacement;
    scratch_ghosted        = scratch_owned;
    const double *const du = scratch_ghosted.trilinos_vector()[0];
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int     c     = cell->active_cell_index();
          const ThermalOperator &B     = cell_thermal_operator[c];
          const auto            &entry = cell_entry[c];
          for (unsigned int i = 0; i < B.size(); ++i)
            {
              const double d = du[entry[i]];
              for (unsigned int v = 0; v < 4; ++v)
                work[c][v] += B[i][v] * d;
            }
          // Generalized plane strain: the out-of-plane strain rate heats by the
          // transpose of the thermal part of the out-of-plane force.
          if (generalized_plane_strain)
            {
              const unsigned int slot = slot_of_body.at(cell->material_id());
              for (unsigned int v = 0; v < 4; ++v)
                work[c][v] += cell_ezz_thermal[c][v] * (ezz[slot] - old_ezz[slot]);
            }
        }
  }



  template <int dim>
  std::pair<SymmetricTensor<2, dim>, double>
  MechanicalField<dim>::stress(const typename DoFHandler<dim>::active_cell_iterator &cell,
                               const unsigned int                                    vertex,
                               const SymmetricTensor<2, dim>                        &strain) const
  {
    const unsigned int c = cell->active_cell_index();
    // The elastic strain: e less the reference strain at the vertex (the part
    // of the cell's reference strains the element holds, solidification.cc;
    // zero without a history or a reference load).
    SymmetricTensor<2, dim> elastic = strain;
    if (history && cell_reference_load[c].size() > 0)
      elastic -= cell_vertex_reference_strain[c][vertex];
    return point_stress(cell, vertex, elastic);
  }



  template <int dim>
  std::pair<SymmetricTensor<2, dim>, double>
  MechanicalField<dim>::point_stress(const typename DoFHandler<dim>::active_cell_iterator &cell,
                                     const unsigned int                                    corner,
                                     const SymmetricTensor<2, dim> &elastic) const
  {
    const unsigned int      c        = cell->active_cell_index();
    const ElasticModuli    &moduli   = cell_moduli[c];
    const double            excess   = thermal_stress ? cell_theta_excess[c][corner] : 0.;
    SymmetricTensor<2, dim> sigma    = moduli.C * elastic - excess * moduli.beta;
    double                  sigma_zz = moduli.lambda_zz * trace(elastic) - moduli.beta_zz * excess;
    if (generalized_plane_strain)
      {
        // The body's e_zz less the point's reference e_zz (out_of_plane.cc).
        const double e_zz =
          ezz[slot_of_body.at(cell->material_id())] - corner_reference(c, corner).strain[3];
        sigma += moduli.lambda_zz * e_zz * unit_symmetric_tensor<dim>();
        sigma_zz += moduli.modulus_zz * e_zz;
      }
    return {sigma, sigma_zz};
  }



  template <int dim>
  void MechanicalField<dim>::cell_vertex_displacement(
    const typename DoFHandler<dim>::active_cell_iterator &cell,
    std::array<std::array<double, 4>, dim>               &u) const
  {
    const FiniteElement<dim> &cell_fe = cell->get_fe();
    const unsigned int        first   = slot_of_body.at(cell->material_id()) * dim;
    AssertDimension(cell_fe.n_dofs_per_cell(), 4 * dim);
    const double *const values = displacement_ghosted.trilinos_vector()[0];
    const auto         &entry  = cell_entry[cell->active_cell_index()];
    for (unsigned int i = 0; i < 4 * dim; ++i)
      {
        // (component, index within FE_Q(1)) = (component, vertex).
        const auto [component, vertex] = cell_fe.system_to_component_index(i);
        u[component - first][vertex]   = values[entry[i]];
      }
  }



  // The vertex rule in closed form (q1_kernels.h): at vertex v the strain of
  // the bilinear interpolant and the weight |det J(v)|/4, the same numbers as
  // FEValues with QTrapezoid and MappingQ1 give (tests/unit_q1_kernels.cc),
  // without a mapping evaluation per cell.
  template <int dim>
  void MechanicalField<dim>::for_each_vertex_stress(
    const std::function<void(const Point<dim> &,
                             double,
                             const SymmetricTensor<2, dim> &,
                             double,
                             const SymmetricTensor<2, dim> &,
                             const ElasticModuli &,
                             const SymmetricTensor<2, dim> &)> &visit) const
  {
    assert_two_dimensional<dim>();
    Point<2>                               x[4];
    std::array<std::array<double, 4>, dim> u;
    const std::vector<bool> shared = two_sided_vertices(triangulation, prm.interface_pairs);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_vertices(cell, x);
          cell_vertex_displacement(cell, u);
          const std::array<double, 4> weight = q1_lumped_mass(x);
          for (unsigned int v = 0; v < 4; ++v)
            {
              const SymmetricTensor<2, dim> strain = q1_strain(x, u, v % 2, v / 2);
              const auto [sigma, szz]              = stress(cell, v, strain);
              const unsigned int c      = cell->active_cell_index();
              const double       excess = thermal_stress ? cell_theta_excess[c][v] : 0.;
              visit(shared[cell->vertex_index(v)] ? point_of_side<dim>(cell, v) : x[v],
                    weight[v],
                    sigma,
                    szz,
                    -excess * cell_moduli[c].beta,
                    cell_moduli[c],
                    strain);
            }
        }
  }



  template <int dim>
  typename MechanicalField<dim>::ElasticStatistics MechanicalField<dim>::elastic_statistics() const
  {
    TimerOutput::Scope t(timer, "statistics: elastic energy");
    assert_two_dimensional<dim>();
    // The energy of the material points, the cell corners (solidification.md):
    // the point of corner q has the quadrant's 2 x 2 Gauss weight, the strain
    // of the element at its Gauss point (where the stiffness takes it) and
    // vertex q's thermal strain and reference e_zz (where the thermal load
    // takes them). Its elastic strain is that of w = u - u_ref, u_ref the
    // displacement of the cell's reference strains (zero without a history;
    // solidification.cc), so a cell born stress-free holds no energy.
    //
    // Until 2026-11-29 the energy was taken by the vertex rule with the strain
    // at the vertices, where Q1's bending (parasitic shear) modes are largest:
    // it over-weighted them (the contact block at N = 32 0.53 % above the
    // energy's limit, now 0.14 %; doc/coupling.md section 6). A mixed form,
    // the quadratic part by the Gauss rule and the thermal terms by the vertex
    // rule (the discrete potential's own), can come out negative where the
    // element cannot follow a thermal strain; this one is a sum of squares.
    //
    // In generalized plane strain the energy is that of the 3D stress (sigma,
    // sigma_zz): with lambda = lambda_zz and M = C_zzzz the in-plane strain is
    // (C - lambda^2/M I x I)^-1 (sigma - lambda/M sigma_zz I), e_zz = (sigma_zz -
    // lambda tr e)/M, and the energy 1/2 (sigma : e + sigma_zz e_zz).
    ElasticStatistics                      result;
    const ElasticModuli                   *last_moduli = nullptr;
    SymmetricTensor<4, dim>                compliance;
    const bool                             with_zz = generalized_plane_strain;
    const SymmetricTensor<2, dim>          I       = unit_symmetric_tensor<dim>();
    Point<2>                               x[4];
    std::array<std::array<double, 4>, dim> u, w;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int c = cell->active_cell_index();
          cell_vertices(cell, x);
          cell_vertex_displacement(cell, u);
          w                  = u;
          const bool shifted = history && c < cell_reference_displacement.size() &&
                               cell_reference_displacement[c].size() == 4 * dim;
          if (shifted)
            {
              const FiniteElement<dim> &cell_fe = cell->get_fe();
              const unsigned int        first   = slot_of_body.at(cell->material_id()) * dim;
              for (unsigned int i = 0; i < 4 * dim; ++i)
                {
                  const auto [component, vertex] = cell_fe.system_to_component_index(i);
                  w[component - first][vertex] -= cell_reference_displacement[c][i];
                }
            }
          const ElasticModuli &moduli = cell_moduli[c];
          if (last_moduli == nullptr || !(moduli == *last_moduli))
            {
              compliance  = with_zz ? invert(moduli.C - moduli.lambda_zz * moduli.lambda_zz /
                                                         moduli.modulus_zz * outer_product(I, I)) :
                                      invert(moduli.C);
              last_moduli = &moduli;
            }
          const std::array<double, 4> weight = q1_gauss_weights(x);
          for (unsigned int q = 0; q < 4; ++q)
            {
              const double                  xi = q1_gauss_point[q % 2], eta = q1_gauss_point[q / 2];
              const SymmetricTensor<2, dim> e_w = q1_strain(x, w, xi, eta);
              const auto [sigma, sigma_zz]      = point_stress(cell, q, e_w);
              if (with_zz)
                {
                  const double                  ratio = moduli.lambda_zz / moduli.modulus_zz;
                  const SymmetricTensor<2, dim> e     = compliance * (sigma - ratio * sigma_zz * I);
                  const double e_zz = (sigma_zz - moduli.lambda_zz * trace(e)) / moduli.modulus_zz;
                  result.energy += 0.5 * (sigma * e + sigma_zz * e_zz) * weight[q];
                }
              else
                result.energy += 0.5 * sigma * (compliance * sigma) * weight[q];
              // The small-strain check: e(u) at the Gauss points.
              result.max_strain =
                std::max(result.max_strain, (shifted ? q1_strain(x, u, xi, eta) : e_w).norm());
            }
        }
    result.energy     = Utilities::MPI::sum(result.energy, mpi_communicator);
    result.max_strain = Utilities::MPI::max(result.max_strain, mpi_communicator);
    return result;
  }



  // The work of the contact forces on the bodies over the last step: each
  // condition pushes its sides apart with lambda n, so the work is
  // -sum_p lambda_p (jump_p(u) - jump_p(u_old)) over the obstacle and interface
  // nodes (collective). A closing contact does negative work on the bodies.
  template <int dim>
  double MechanicalField<dim>::contact_work() const
  {
    Vector u_old(owned, relevant, mpi_communicator);
    u_old      = old_displacement;
    double sum = 0;
    for (const auto &c : normal_conditions)
      if (c.kind != NormalCondition::Kind::roller && owned.is_element(c.dofs_k[0]))
        {
          double old_jump = 0;
          for (unsigned int d = 0; d < dim; ++d)
            {
              old_jump +=
                c.normal[d] * (u_old[c.dofs_k[d]] - (c.has_partner ? u_old[c.dofs_l[d]] : 0.));
              for (const auto &[dofs_m, w] : c.masters)
                old_jump -= c.normal[d] * w * u_old[dofs_m[d]];
            }
          sum -= contact_pressure(c) * c.weight * (normal_displacement_jump(c) - old_jump);
        }
    return Utilities::MPI::sum(sum, mpi_communicator);
  }



  template <int dim>
  void MechanicalField<dim>::check_pressure_windows() const
  {
    std::vector<unsigned int> nodes(pressure_windows.size(), 0);
    for (const auto &c : normal_conditions)
      if (c.carries_pressure() && owned.is_element(c.dofs_k[0]))
        for (std::size_t w = 0; w < pressure_windows.size(); ++w)
          nodes[w] += pressure_windows[w].contains(c.position);
    Utilities::MPI::sum(nodes, mpi_communicator, nodes);
    for (std::size_t w = 0; w < pressure_windows.size(); ++w)
      if (nodes[w] == 0)
        throw InputError("Output/Contact pressure windows",
                         "'" + pressure_windows[w].name +
                           "' holds no node of an obstacle boundary or contact interface of "
                           "the mesh (widen it or refine the mesh)");
  }



  // The window sums from the multipliers themselves: the nodal pressure
  // vector holds one value per DoF, and where an interface meets an obstacle
  // both conditions share a DoF. A sum below the round-off of the nodes'
  // residuals (64 eps times their stiffness times the largest displacement)
  // is 0: an open stretch reports 0, not the sign of round-off.
  template <int dim>
  void MechanicalField<dim>::store_window_sums(const std::vector<Decision> &decisions,
                                               ContactStepReport           &report) const
  {
    report.window_sums.clear();
    if (pressure_windows.empty())
      return;
    const std::size_t   n_groups = contact_groups.size();
    const double        u_max    = displacement.linfty_norm();
    std::vector<double> sums(3 * n_groups * pressure_windows.size(), 0.);
    // (The decisions are those of the nodes that carry a pressure.)
    for (const auto &dec : decisions)
      {
        const std::size_t group =
          std::lower_bound(contact_groups.begin(), contact_groups.end(), dec.c->group) -
          contact_groups.begin();
        AssertThrow(group < n_groups && contact_groups[group] == dec.c->group, ExcInternalError());
        for (std::size_t w = 0; w < pressure_windows.size(); ++w)
          if (pressure_windows[w].contains(dec.c->position))
            {
              double *const at = &sums[3 * (w * n_groups + group)];
              at[0] += dec.lambda;
              at[1] += dec.c->weight;
              at[2] += round_off_factor * std::numeric_limits<double>::epsilon() *
                       dec.c->stiffness * u_max;
            }
      }
    Utilities::MPI::sum(sums, mpi_communicator, sums);
    for (std::size_t w = 0; w < pressure_windows.size(); ++w)
      {
        report.window_sums.emplace_back(pressure_windows[w].name,
                                        std::map<std::string, std::pair<double, double>>());
        for (std::size_t g = 0; g < n_groups; ++g)
          if (const double *const at = &sums[3 * (w * n_groups + g)]; at[1] > 0)
            report.window_sums.back().second[contact_groups[g]] = {std::abs(at[0]) > at[2] ? at[0] :
                                                                                             0.,
                                                                   at[1]};
      }
  }



  // Ghosted copies of the last contact step's nodal pressure, gap and active
  // flags, read at the interface vertices of the owned cells (whose DoFs
  // another rank may own). A mortar slave node's state is keyed by its node
  // number and handed to every rank (collective): the heat it exchanges
  // reaches master DoFs that any rank may own.
  template <int dim>
  void MechanicalField<dim>::interface_contact_states(InterfaceContactStates &states) const
  {
    states.clear();
    Vector p(owned, relevant, mpi_communicator), g(owned, relevant, mpi_communicator),
      active(owned, relevant, mpi_communicator);
    p      = pressure;
    g      = gap;
    active = interface_active;
    // (body k, body l, node, closed) and (gap, pressure) of the owned mortar nodes.
    std::vector<std::array<unsigned int, 4>> mortar_keys;
    std::vector<std::array<double, 2>>       mortar_values;
    for (const auto &c : normal_conditions)
      if (c.kind == NormalCondition::Kind::interface && !c.mortar)
        {
          InterfaceContactState &s = states[{c.body_k, c.body_l, c.vertex}];
          s.closed                 = c.tied || active[c.dofs_k[0]] > 0.5;
          s.gap                    = c.tied ? 0. : g[c.dofs_k[0]];
          s.pressure               = c.tied ? 0. : p[c.dofs_k[0]];
        }
      else if (c.kind == NormalCondition::Kind::interface && owned.is_element(c.dofs_k[0]))
        {
          mortar_keys.push_back(
            {{c.body_k, c.body_l, c.mortar_node, active[c.dofs_k[0]] > 0.5 ? 1u : 0u}});
          mortar_values.push_back({{g[c.dofs_k[0]], p[c.dofs_k[0]]}});
        }
    if (mortar_summary.empty())
      return;
    const auto keys   = Utilities::MPI::all_gather(mpi_communicator, mortar_keys);
    const auto values = Utilities::MPI::all_gather(mpi_communicator, mortar_values);
    for (unsigned int r = 0; r < keys.size(); ++r)
      for (unsigned int i = 0; i < keys[r].size(); ++i)
        {
          const auto            &key = keys[r][i];
          InterfaceContactState &s   = states[{key[0], key[1], key[2]}];
          s.closed                   = key[3] == 1;
          s.gap                      = values[r][i][0];
          s.pressure                 = values[r][i][1];
        }
  }



  template unsigned int
  MechanicalField<2>::set_phase_weights(const std::vector<std::vector<double>> &weights);
  template void MechanicalField<2>::set_cell_temperatures(const CellVertexValues &theta);
  template void MechanicalField<2>::thermal_load_change(const CellVertexValues &theta,
                                                        const CellVertexValues &theta_before,
                                                        Vector                 &change) const;
  template void MechanicalField<2>::thermoelastic_work(CellVertexValues &work) const;
  template std::pair<SymmetricTensor<2, 2>, double>
                MechanicalField<2>::stress(const typename DoFHandler<2>::active_cell_iterator &cell,
                             const unsigned int                                  vertex,
                             const SymmetricTensor<2, 2>                        &strain) const;
  template void MechanicalField<2>::cell_vertex_displacement(
    const typename DoFHandler<2>::active_cell_iterator &cell,
    std::array<std::array<double, 4>, 2>               &u) const;
  template void MechanicalField<2>::for_each_vertex_stress(
    const std::function<void(const Point<2> &,
                             double,
                             const SymmetricTensor<2, 2> &,
                             double,
                             const SymmetricTensor<2, 2> &,
                             const ElasticModuli &,
                             const SymmetricTensor<2, 2> &)> &visit) const;
  template typename MechanicalField<2>::ElasticStatistics
                  MechanicalField<2>::elastic_statistics() const;
  template double MechanicalField<2>::contact_work() const;
  template void   MechanicalField<2>::check_pressure_windows() const;
  template void   MechanicalField<2>::store_window_sums(const std::vector<Decision> &,
                                                      ContactStepReport &) const;
  template void   MechanicalField<2>::interface_contact_states(InterfaceContactStates &) const;
} // namespace ContactStefan
