// MechanicalField: set-up of the displacement space, the elasticity operators,
// the loads, the fixed constraints and the nodes that carry a normal condition.
//
// Multibody design (see doc/contact.md): one connected triangulation, the
// temperature on a scalar FE_Q(1) space, the displacement on an hp DoFHandler
// whose element on body b is FE_Q(1)^dim in body b's slot of components and
// FE_Nothing in every other slot (step-46's device). Where two bodies meet, each
// vertex therefore carries one displacement per body, and the contact condition
// between the two is a constraint between DoFs of the same vertex, which every
// MPI rank that sees the vertex can build from its own cells.
#include <deal.II/base/quadrature_lib.h>

#include <deal.II/dofs/dof_tools.h>

#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>

#include <deal.II/hp/fe_values.h>
#include <deal.II/hp/q_collection.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/core/slot_sum.h>
#include <contact-stefan/interfaces/body_interface.h>
#include <contact-stefan/interfaces/contact.h>
#include <contact-stefan/mechanics/mechanical_field.h>

#include <map>
#include <set>
#include <tuple>
#include <unordered_set>

#include "pieces.h"

namespace ContactStefan
{
  using namespace MechanicalFieldPieces;

  namespace
  {
    // Theta_0 at the four corners of a cell, as the temperature field holds
    // it: at a hanging vertex (the midpoint of a coarser neighbour's face) the
    // temperature is constrained to the mean of that face's end values, so the
    // reference there is the mean of the reference at the face's ends, not its
    // value at the midpoint. Otherwise an initial temperature equal to the
    // reference would load every hanging vertex with beta (Theta_0 at the
    // midpoint - the mean): a curved reference is not stress-free at t0 on an
    // adapted mesh (the subduction scene, adapted: a contact force of 2e11
    // N/m and 5 km in contact at t0 without any load). A vertex where bodies
    // meet (two_sided) is evaluated inside the cell, on its own body's side.
    template <int dim>
    std::array<double, 4>
    corner_references(const typename DoFHandler<dim>::active_cell_iterator &cell,
                      const Function<dim>                                  &reference,
                      const std::vector<bool>                              &two_sided)
    {
      const auto at = [&](const unsigned int vertex_index, const Point<dim> &x) {
        return reference.value(
          two_sided[vertex_index] ? x + interface_side_offset * (cell->center() - x) : x);
      };
      std::array<double, 4> values;
      for (unsigned int v = 0; v < 4; ++v)
        values[v] = at(cell->vertex_index(v), cell->vertex(v));
      for (const unsigned int f : cell->face_indices())
        if (!cell->at_boundary(f) && cell->neighbor_is_coarser(f))
          {
            const auto coarse =
              cell->neighbor(f)->face(cell->neighbor_of_coarser_neighbor(f).first);
            const unsigned int a = coarse->vertex_index(0), b = coarse->vertex_index(1);
            for (const unsigned int i : cell->face(f)->vertex_indices())
              if (const unsigned int m = cell->face(f)->vertex_index(i); m != a && m != b)
                values[GeometryInfo<dim>::face_to_cell_vertices(f, i)] =
                  0.5 * (at(a, coarse->vertex(0)) + at(b, coarse->vertex(1)));
          }
      return values;
    }
  } // namespace



  template <int dim>
  MechanicalField<dim>::MechanicalField(
    const SceneContext<dim>                       &context,
    const Parameters::ContactStep                 &contact_prm,
    const Parameters::LinearSolvers               &linear_prm,
    const std::vector<Parameters::SectionLine>    &section_lines,
    const std::vector<Parameters::PressureWindow> &pressure_windows)
    : prm(context.scene)
    , contact_prm(contact_prm)
    , linear_prm(linear_prm)
    , verbosity(context.verbosity)
    , section_lines(section_lines)
    , pressure_windows(pressure_windows)
    , materials(context.materials)
    , functions(context.functions)
    , triangulation(context.triangulation)
    , mpi_communicator(triangulation.get_communicator())
    , timer(context.timer)
    , pcout(context.pcout)
    , dof_handler(triangulation)
    // A contact set changes boundary rows only: the first hierarchy serves
    // every set (Solver/AMG update = automatic).
    , linear_solver(linear_prm,
                    verbosity,
                    pcout,
                    "elasticity",
                    Parameters::LinearSolvers::AMGUpdate::reuse,
                    contact_prm.elasticity_amg_threshold,
                    contact_prm.elasticity_amg_sweeps,
                    contact_prm.elasticity_amg_reuse_limit)
    , coupled(prm.coupling_active())
    , thermal_stress(prm.thermal_stress_active())
    , generalized_plane_strain(prm.physics.generalized_plane_strain)
    , time(prm.time.start_time)
  {
    assert_two_dimensional<dim>();
    // Element b: FE_Q(1)^dim in slot b, FE_Nothing^dim in every other slot.
    const unsigned int n_slots = prm.body_ids.size();
    ezz.assign(n_slots, 0.);
    old_ezz.assign(n_slots, 0.);
    for (unsigned int s = 0; s < n_slots; ++s)
      slot_of_body[prm.body_ids[s]] = s;
    fe = slot_elements<dim>(n_slots, dim);
    // Only a scene with a body that is stress-free at solidification keeps
    // references per material point.
    if (prm.solidification_history_active())
      history = std::make_unique<SolidificationHistory<dim>>(triangulation);
  }



  // Everything that depends on the mesh, rebuilt from scratch.
  template <int dim>
  void MechanicalField<dim>::setup_dofs()
  {
    TimerOutput::Scope t(timer, "setup: mechanical field");
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        cell->set_active_fe_index(slot_of_body.at(cell->material_id()));
    dof_handler.distribute_dofs(fe);
    owned = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
    couple_mortar_interfaces();

    hanging_node_constraints.clear();
    hanging_node_constraints.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, hanging_node_constraints);
    hanging_node_constraints.close();

    for (Vector *v : {&system_rhs,
                      &load,
                      &displacement,
                      &old_displacement,
                      &obstacle_active,
                      &interface_active,
                      &pressure,
                      &gap})
      v->reinit(owned, mpi_communicator);
    for (Vector *v : {&displacement_ghosted,
                      &obstacle_active_ghosted,
                      &interface_active_ghosted,
                      &stiffness_diagonal,
                      &scratch_ghosted})
      v->reinit(owned, relevant, mpi_communicator);
    scratch_owned.reinit(owned, mpi_communicator);
    {
      const Epetra_BlockMap               &map = displacement_ghosted.trilinos_vector().Map();
      std::vector<types::global_dof_index> dofs;
      cell_entry.assign(triangulation.n_active_cells(), {});
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            dofs.resize(cell->get_fe().n_dofs_per_cell());
            AssertThrow(dofs.size() == 4 * dim, ExcInternalError());
            cell->get_dof_indices(dofs);
            for (unsigned int i = 0; i < dofs.size(); ++i)
              {
                const int entry = map.LID(static_cast<TrilinosWrappers::types::int_type>(dofs[i]));
                AssertThrow(entry >= 0, ExcInternalError());
                cell_entry[cell->active_cell_index()][i] = entry;
              }
          }
    }
    cell_load.assign(triangulation.n_active_cells(), dealii::Vector<double>());
    cell_thermal_load.assign(coupled ? triangulation.n_active_cells() : 0, {});
    cell_theta_excess.assign(triangulation.n_active_cells(), {{0., 0., 0., 0.}});
    // Until the thermal field says otherwise, each cell is in phase 0.
    // No thermal load until the thermal field hands over its temperatures (after
    // a mesh change: before after_transfer(), doc/architecture.md).
    cell_moduli.assign(triangulation.n_active_cells(), ElasticModuli());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_moduli[cell->active_cell_index()] =
            materials[cell->material_id()].phase_moduli.front();
        }
    ++stiffness_version;
    have_matrix = have_factorisation = have_solution = have_bulk = false;

    make_body_frames();
    assemble_cell_stiffness();
    find_normal_conditions();
    check_mortar_junctions();
    make_fixed_constraints();
    make_sparsity_pattern();
  }



  // Where each displacement DoF sits, and each body's centre, size and box.
  template <int dim>
  void MechanicalField<dim>::make_body_frames()
  {
    const unsigned int n_slots = prm.body_ids.size();
    dof_info.clear();
    std::vector<Point<dim>> lower(n_slots, Point<dim>(HUGE_VAL, HUGE_VAL)),
      upper(n_slots, Point<dim>(-HUGE_VAL, -HUGE_VAL));
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        {
          const unsigned int slot = slot_of_body.at(cell->material_id());
          const auto         dofs = vertex_dofs<dim>(cell);
          for (const unsigned int v : cell->vertex_indices())
            for (unsigned int d = 0; d < dim; ++d)
              {
                dof_info[dofs[v][d]] = {slot, d, cell->vertex(v)};
                lower[slot][d]       = std::min(lower[slot][d], cell->vertex(v)[d]);
                upper[slot][d]       = std::max(upper[slot][d], cell->vertex(v)[d]);
              }
        }
    body_frame.resize(n_slots);
    body_box.resize(n_slots);
    for (unsigned int s = 0; s < n_slots; ++s)
      {
        Point<dim> lo, hi;
        for (unsigned int d = 0; d < dim; ++d)
          {
            lo[d] = Utilities::MPI::min(lower[s][d], mpi_communicator);
            hi[d] = Utilities::MPI::max(upper[s][d], mpi_communicator);
          }
        body_frame[s] = {0.5 * (lo + hi), 0.5 * lo.distance(hi)};
        body_box[s]   = {lo, hi};
      }
  }



  // The sparsity pattern must hold every system the active-set iteration can
  // produce, with any mixture of active and inactive nodes. Condensing a cell
  // couples its DoFs with every DoF their constraints name, recursively. So
  // each cell's DoFs are closed under "may be constrained in terms of": the
  // entries of the fixed constraints (hanging nodes, prescribed values, ties,
  // rollers) and, for a node with a contact condition, all DoFs of the
  // condition (both bodies, both components); the closure is coupled densely.
  // Then the conditions that cannot be imposed even with every node active are
  // left out (all their components prescribed, e.g. a clamped corner of an
  // obstacle boundary): their residual would be a clamp reaction, not a
  // contact force.
  template <int dim>
  void MechanicalField<dim>::make_sparsity_pattern()
  {
    // Each condition couples the DoFs it names (both sides of an interface).
    // A mortar condition is only ever solved for its slave node: only the
    // slave's DoFs reach the master nodes (so that the closure of a cell
    // stays within a few edges, not the whole interface).
    std::map<types::global_dof_index, std::vector<types::global_dof_index>> condition_dofs;
    for (const auto &c : normal_conditions)
      {
        std::vector<types::global_dof_index> all;
        for (unsigned int d = 0; d < dim; ++d)
          {
            all.push_back(static_cast<types::global_dof_index>(c.dofs_k[d]));
            if (c.has_partner)
              all.push_back(static_cast<types::global_dof_index>(c.dofs_l[d]));
          }
        const std::size_t n_targets = all.size();
        for (const auto &[dofs_m, w] : c.masters)
          for (unsigned int d = 0; d < dim; ++d)
            all.push_back(static_cast<types::global_dof_index>(dofs_m[d]));
        for (std::size_t i = 0; i < n_targets; ++i)
          condition_dofs[all[i]].insert(condition_dofs[all[i]].end(), all.begin(), all.end());
      }
    // The DoFs of conditions that an active set can change (obstacles, and
    // interfaces unless tied): a cell whose closure reaches one is re-assembled
    // in each contact iteration, the others go into the bulk matrix (below,
    // once the contact lines of other ranks are known).
    std::unordered_set<types::global_dof_index> contact_dofs;
    for (const auto &c : normal_conditions)
      if (c.kind == NormalCondition::Kind::obstacle ||
          (c.kind == NormalCondition::Kind::interface && !c.tied))
        for (unsigned int d = 0; d < dim; ++d)
          {
            contact_dofs.insert(c.dofs_k[d]);
            if (c.has_partner)
              contact_dofs.insert(c.dofs_l[d]);
          }
    DynamicSparsityPattern dsp(relevant);
    add_closed_cell_couplings(dsp, condition_dofs);
    settle_imposable_conditions(contact_dofs);

    SparsityTools::distribute_sparsity_pattern(dsp, owned, mpi_communicator, relevant);
    linear_solver.clear();
    system_matrix.reinit(owned, owned, dsp, mpi_communicator);
    set_rigid_body_modes();
  }



  // The couplings of each owned cell: its DoFs closed under every constraint
  // that may ever apply (the fixed ones, and all DoFs of each condition), so
  // that any mixture of active and inactive nodes fits the pattern.
  template <int dim>
  void MechanicalField<dim>::add_closed_cell_couplings(
    DynamicSparsityPattern                                                        &dsp,
    const std::map<types::global_dof_index, std::vector<types::global_dof_index>> &condition_dofs)
    const
  {
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          dofs.resize(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          // Most cells have no constrained or conditioned DoF: their closure is
          // their own DoFs.
          if (std::none_of(dofs.begin(), dofs.end(), [&](const types::global_dof_index dof) {
                return fixed_constraints.is_constrained(dof) || condition_dofs.count(dof) > 0;
              }))
            {
              for (const auto row : dofs)
                if (relevant.is_element(row))
                  dsp.add_entries(row, dofs.begin(), dofs.end(), false);
              continue;
            }
          std::set<types::global_dof_index>    closure(dofs.begin(), dofs.end());
          std::vector<types::global_dof_index> work(dofs.begin(), dofs.end());
          while (!work.empty())
            {
              const auto dof = work.back();
              work.pop_back();
              std::vector<types::global_dof_index> next;
              if (const auto *entries = fixed_constraints.get_constraint_entries(dof))
                for (const auto &entry : *entries)
                  next.push_back(entry.first);
              if (const auto it = condition_dofs.find(dof); it != condition_dofs.end())
                next.insert(next.end(), it->second.begin(), it->second.end());
              for (const auto n : next)
                if (closure.insert(n).second)
                  work.push_back(n);
            }
          const std::vector<types::global_dof_index> columns(closure.begin(), closure.end());
          for (const auto row : columns)
            if (relevant.is_element(row))
              dsp.add_entries(row, columns.begin(), columns.end(), true);
        }
  }



  // With every node active: which conditions can be imposed at all (counted
  // per group, for the check of initialize()), which cells are near a contact
  // DoF (re-assembled in each contact iteration), and the conditions that can
  // never be imposed, left out (their weight goes to a partner at the same
  // vertex where there is one).
  template <int dim>
  void MechanicalField<dim>::settle_imposable_conditions(
    std::unordered_set<types::global_dof_index> &contact_dofs)
  {
    cell_near_contact.assign(triangulation.n_active_cells(), false);
    std::vector<types::global_dof_index> dofs;
    // Every node active: which conditions can be imposed at all.
    for (Vector *v : {&obstacle_active, &interface_active})
      *v = 1.;
    obstacle_active_ghosted  = obstacle_active;
    interface_active_ghosted = interface_active;
    unsigned int skipped     = 0;
    build_contact_constraints(skipped);
    imposable_per_group = placed_per_group;
    // With every node active the constraints also hold the contact lines of
    // conditions that other ranks found (a hanging node of an owned cell can
    // hang on a contact node of another rank's cell): their DoFs count too.
    for (const auto &line : constraints.get_lines())
      if (!fixed_constraints.is_constrained(line.index))
        {
          contact_dofs.insert(line.index);
          for (const auto &entry : line.entries)
            contact_dofs.insert(entry.first);
        }
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          dofs.resize(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          // The fixed constraints are closed: the DoFs their lines name are
          // not constrained by them, so one level of entries is the closure.
          bool near = false;
          for (const auto dof : dofs)
            {
              near = near || contact_dofs.count(dof) > 0;
              if (const auto *entries = fixed_constraints.get_constraint_entries(dof))
                for (const auto &entry : *entries)
                  near = near || contact_dofs.count(entry.first) > 0;
            }
          cell_near_contact[cell->active_cell_index()] = near;
        }
    std::vector<NormalCondition> kept, left_out;
    unsigned int                 dropped = 0;
    for (const auto &c : normal_conditions)
      if (c.kind == NormalCondition::Kind::roller ||
          (c.kind == NormalCondition::Kind::interface && c.tied) ||
          imposed_conditions.count({c.dofs_k[0], static_cast<int>(c.kind)}) == 1)
        kept.push_back(c);
      else
        left_out.push_back(c);
    // Where a tied interface meets an obstacle, the tie takes one side's
    // components and the other side's condition carries the contact of both:
    // it gets their lumped boundary weight, so that its pressure is the force
    // over the whole face length at the vertex. Only a condition with no such
    // partner is really left out.
    for (const auto &c : left_out)
      {
        auto partner = std::find_if(kept.begin(), kept.end(), [&](const NormalCondition &k) {
          return k.kind == c.kind && k.group == c.group && k.position == c.position;
        });
        if (partner != kept.end())
          partner->weight += c.weight;
        else
          dropped += owned.is_element(c.dofs_k[0]);
      }
    normal_conditions.swap(kept);
    update_condition_stiffness();
    n_dropped_conditions = Utilities::MPI::sum(dropped, mpi_communicator);
    for (Vector *v :
         {&obstacle_active, &interface_active, &obstacle_active_ghosted, &interface_active_ghosted})
      *v = 0.;
  }



  template <int dim>
  void MechanicalField<dim>::set_rigid_body_modes()
  {
    // The rigid-body modes of plane elasticity (two translations and the
    // rotation about each body's centre) as the AMG near-null space: with ML's
    // default constant mode CG needs hundreds of iterations.
    std::vector<std::vector<double>> modes(3, std::vector<double>(owned.n_elements(), 0.));
    for (const auto dof : owned)
      {
        const auto        &info  = dof_info.at(dof);
        const unsigned int i     = owned.index_within_set(dof);
        const Point<dim>  &c     = body_frame[info.slot].first;
        modes[info.component][i] = 1;
        const double size        = body_frame[info.slot].second; // scale: O(1) entries
        modes[2][i] =
          (info.component == 0 ? -(info.position[1] - c[1]) : info.position[0] - c[0]) / size;
      }
    linear_solver.set_near_null_space(std::move(modes));
  }



  template <int dim>
  std::string MechanicalField<dim>::describe() const
  {
    unsigned int n_rollers = 0, n_obstacle = 0, n_interface = 0, n_tied = 0;
    for (const auto &c : normal_conditions)
      if (owned.is_element(c.dofs_k[0]))
        {
          (c.kind == NormalCondition::Kind::roller   ? n_rollers :
           c.kind == NormalCondition::Kind::obstacle ? n_obstacle :
                                                       n_interface)++;
          n_tied += c.kind == NormalCondition::Kind::interface && c.tied;
        }
    // The interfaces' kind: each interface has its own ('Contact/Interface k-l/
    // Kind'); without interface nodes, the default.
    const unsigned int all_tied      = Utilities::MPI::sum(n_tied, mpi_communicator);
    const unsigned int all_interface = Utilities::MPI::sum(n_interface, mpi_communicator);
    const std::string  kind =
      all_interface == 0 ?
         (prm.contact.interfaces == Parameters::Contact::Interfaces::tied ? "tied" : "contact") :
       all_tied == all_interface ? "tied" :
       all_tied == 0             ? "contact" :
                                   "contact and tied";
    return "Mechanics: " + std::to_string(dof_handler.n_dofs()) + " displacement DoFs in " +
           std::to_string(prm.body_ids.size()) + " body(ies); " +
           std::to_string(Utilities::MPI::sum(n_obstacle, mpi_communicator)) + " obstacle, " +
           std::to_string(all_interface) + " interface (" + kind + ") and " +
           std::to_string(Utilities::MPI::sum(n_rollers, mpi_communicator)) + " roller nodes" +
           (n_dropped_conditions == 0 ?
              std::string() :
              "\nContact: " + std::to_string(n_dropped_conditions) +
                " obstacle/interface node(s) have every displacement component prescribed and "
                "are left out of the contact conditions");
  }



  // Cold start at t0: nodes whose gap is already closed (g <= 0) start in
  // contact, so that bodies stacked on each other start supported. Then the
  // input checks that need the mesh: every obstacle and interface must have a
  // node with a free displacement component, and every body must be held
  // against rigid motion by its constraints and the initial contact set.
  template <int dim>
  void MechanicalField<dim>::initialize(const double t0)
  {
    time                 = t0;
    displacement         = 0;
    old_displacement     = 0;
    displacement_ghosted = 0;
    std::fill(ezz.begin(), ezz.end(), 0.);
    std::fill(old_ezz.begin(), old_ezz.end(), 0.);
    // The data at t0 (checked for finite values below, before any output).
    assemble_load();
    make_fixed_constraints();
    // Tied groups from the parameters, not from this rank's conditions: every
    // rank must take the same branch below (it holds collective sums).
    std::set<std::string> obstacle_groups, tied_groups;
    for (const auto &[pair, law] : prm.interface_pairs)
      if (law.kind == Parameters::Contact::Interfaces::tied)
        tied_groups.insert("interface " + std::to_string(pair.first) + "-" +
                           std::to_string(pair.second));
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      if (bc.type == Parameters::MechanicalBoundary::Type::obstacle)
        obstacle_groups.insert(boundary_group(id));
    for (const auto &group : contact_groups)
      if (Utilities::MPI::sum(imposable_per_group[group], mpi_communicator) == 0 &&
          (obstacle_groups.count(group) == 1 || tied_groups.count(group) == 0))
        {
          const bool boundary = obstacle_groups.count(group) == 1;
          throw InputError(boundary ? "Boundary conditions/Mechanical " + group :
                                      std::string("Contact/Interfaces"),
                           "no node of this " + std::string(boundary ? "obstacle" : "interface") +
                             " has a free displacement component: prescribed displacements "
                             "take them all");
        }

    update_condition_gaps();
    functions.check_finite_values(mpi_communicator);
    for (Vector *v : {&obstacle_active, &interface_active})
      *v = 0.;
    for (const auto &c : normal_conditions)
      if (c.kind != NormalCondition::Kind::roller && owned.is_element(c.dofs_k[0]))
        active_flags(c)[c.dofs_k[0]] = c.gap <= 0 ? 1. : 0.;
    obstacle_active.compress(VectorOperation::insert);
    interface_active.compress(VectorOperation::insert);
    obstacle_active_ghosted  = obstacle_active;
    interface_active_ghosted = interface_active;
    unsigned int skipped     = 0;
    build_contact_constraints(skipped);
    try
      {
        check_rigid_body_modes();
      }
    catch (const std::exception &e)
      {
        throw InputError("Boundary conditions/Mechanical boundaries", e.what());
      }
    check_section_lines(section_lines);
  }



  template <int dim>
  void MechanicalField<dim>::begin_time_step(const double t, const double /*tau: quasi-static*/)
  {
    time             = t;
    old_displacement = displacement;
    old_ezz          = ezz;
    guess_pending    = false; // (one of a redone attempt's is stale)
    assemble_load();
    make_fixed_constraints();
    update_condition_gaps();
    functions.check_finite_values(mpi_communicator);
  }



  template <int dim>
  std::vector<Vector *> MechanicalField<dim>::primary_state()
  {
    return {&displacement, &old_displacement};
  }



  template <int dim>
  double MechanicalField<dim>::body_height(const unsigned int body) const
  {
    const auto &box = body_box[slot_of_body.at(body)];
    return box.second[1] - box.first[1];
  }



  // The elasticity matrices K_K of all owned cells (assembled once per mesh, and
  // again for a cell whose phase mixture changed), the thermal operators B_K
  // when the scene is coupled, Theta_0 at the vertices, and the diagonal of K,
  // which scales the complementarity constant per node.
  template <int dim>
  void MechanicalField<dim>::assemble_cell_stiffness()
  {
    const hp::QCollection<dim> gauss(QGauss<dim>(2));
    const hp::QCollection<dim> vertex_rule(QTrapezoid<dim>{});
    hp::FEValues<dim>          gauss_values(fe, gauss, update_gradients | update_JxW_values);
    hp::FEValues<dim>          vertex_values(
      fe, vertex_rule, update_gradients | update_JxW_values | update_quadrature_points);
    cell_stiffness.assign(triangulation.n_active_cells(), LocalMatrix());
    cell_thermal_operator.assign(coupled ? triangulation.n_active_cells() : 0, ThermalOperator());
    cell_reference.assign(coupled ? triangulation.n_active_cells() : 0, {{0., 0., 0., 0.}});
    const unsigned int n_ezz_cells = generalized_plane_strain ? triangulation.n_active_cells() : 0;
    cell_ezz_coupling.assign(n_ezz_cells, dealii::Vector<double>());
    cell_ezz_stiffness.assign(n_ezz_cells, 0.);
    cell_ezz_thermal.assign(n_ezz_cells, {{0., 0., 0., 0.}});
    ezz_response.clear();
    // Theta_0 on each side of a place where bodies meet is the side's own (a
    // reference that jumps there, as the subduction zone's and a casting's
    // do): evaluated inside the cell (two_sided_vertices(), if it jumps there,
    // jumps_at(); always at a conductance interface). The temperature there is
    // one value for both sides (perfect contact), or one per side
    // (conductance); either way each body's thermal strain is measured from
    // its own reference (doc/coupling.md §2).
    std::vector<bool> two_sided;
    if (coupled)
      {
        two_sided = two_sided_vertices(triangulation, prm.interface_pairs);
        if (!jumps_at(functions.reference_temperature(), triangulation, two_sided))
          two_sided = two_sided_vertices(triangulation, prm.interface_pairs, true);
      }
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          assemble_cell_operators(cell, gauss_values, vertex_values);
          if (coupled)
            cell_reference[cell->active_cell_index()] =
              corner_references<dim>(cell, functions.reference_temperature(), two_sided);
        }
    functions.check_finite_values(mpi_communicator);
    update_stiffness_diagonal();
  }



  template <int dim>
  void MechanicalField<dim>::assemble_cell_operators(
    const typename DoFHandler<dim>::active_cell_iterator &cell,
    hp::FEValues<dim>                                    &gauss_values,
    hp::FEValues<dim>                                    &vertex_values)
  {
    const unsigned int               c = cell->active_cell_index();
    const FEValuesExtractors::Vector u(slot_of_body.at(cell->material_id()) * dim);
    const unsigned int               n      = cell->get_fe().n_dofs_per_cell();
    const ElasticModuli             &moduli = cell_moduli[c];
    gauss_values.reinit(cell);
    const FEValues<dim> &fe_values = gauss_values.get_present_fe_values();
    LocalMatrix         &K         = cell_stiffness[c];
    K.reinit(n, n);
    // The strains of the shape functions at a quadrature point, once each
    // (the view computes them from the shape gradients on every call).
    std::vector<SymmetricTensor<2, dim>> strain(n);
    for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
      {
        for (unsigned int j = 0; j < n; ++j)
          strain[j] = fe_values[u].symmetric_gradient(j, q);
        for (unsigned int i = 0; i < n; ++i)
          {
            const SymmetricTensor<2, dim> sigma_i = moduli.C * strain[i];
            for (unsigned int j = 0; j < n; ++j)
              K(i, j) += sigma_i * strain[j] * fe_values.JxW(q);
          }
      }
    if (generalized_plane_strain)
      assemble_out_of_plane_operators(c, fe_values, u);
    if (!coupled)
      return;
    // B_K(i, v) = w_v beta_K : e(phi_i)(x_v), the trapezoidal rule: the same
    // vertex weights as the thermal field's lumped mass, so that the heating
    // operator is the transpose of the thermal-stress operator (times Theta_0)
    // and a uniform strain heats every node in proportion to its mass.
    vertex_values.reinit(cell);
    const FEValues<dim> &fv = vertex_values.get_present_fe_values();
    ThermalOperator     &B  = cell_thermal_operator[c];
    AssertThrow(n == B.size(), ExcInternalError());
    for (unsigned int v = 0; v < 4; ++v)
      {
        Assert(fv.quadrature_point(v).distance(cell->vertex(v)) <= 1e-12 * cell->diameter(),
               ExcInternalError());
        for (unsigned int i = 0; i < n; ++i)
          B[i][v] = moduli.beta * fv[u].symmetric_gradient(i, v) * fv.JxW(v);
        // The thermal part of the cell's out-of-plane force by the same rule.
        if (generalized_plane_strain)
          cell_ezz_thermal[c][v] = moduli.beta_zz * fv.JxW(v);
      }
  }



  // The normal diagonal of K at each normal condition: the per-node scale of
  // the complementarity constant (doc/contact.md). Again after a phase change
  // re-assembled cells, so that a soft melt does not get a solid's c.
  template <int dim>
  void MechanicalField<dim>::update_condition_stiffness()
  {
    for (auto &c : normal_conditions)
      c.stiffness = c.normal[0] * c.normal[0] * stiffness_diagonal[c.dofs_k[0]] +
                    c.normal[1] * c.normal[1] * stiffness_diagonal[c.dofs_k[1]];
  }



  template <int dim>
  void MechanicalField<dim>::update_stiffness_diagonal()
  {
    Vector diagonal(owned, mpi_communicator);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const LocalMatrix                   &K = cell_stiffness[cell->active_cell_index()];
          const unsigned int                   n = K.m();
          std::vector<types::global_dof_index> dofs(n);
          cell->get_dof_indices(dofs);
          dealii::Vector<double> d(n);
          for (unsigned int i = 0; i < n; ++i)
            d(i) = K(i, i);
          hanging_node_constraints.distribute_local_to_global(d, dofs, diagonal);
        }
    diagonal.compress(VectorOperation::add);
    stiffness_diagonal = diagonal;

    // Huge moduli (E = 1e308) overflow in the sums of the cell matrices: refuse
    // them here, before any work, naming the body.
    unsigned int bad_slot = prm.body_ids.size();
    for (const auto dof : owned)
      if (!std::isfinite(diagonal[dof]))
        bad_slot = std::min(bad_slot, dof_info.at(dof).slot);
    bad_slot = Utilities::MPI::min(bad_slot, mpi_communicator);
    if (bad_slot < prm.body_ids.size())
      {
        const unsigned int body = prm.body_ids[bad_slot];
        const auto         type = prm.materials.at(body).elasticity;
        using Elasticity        = Parameters::BodyMaterial::Elasticity;
        throw InputError("Materials/Body " + std::to_string(body) + "/" +
                           (type == Elasticity::isotropic ? "Youngs modulus" :
                            type == Elasticity::lame      ? "Lame lambda" :
                                                            "Elasticity tensor"),
                         "the stiffness matrix it gives is not finite (overflow)");
      }
  }



  // Body forces and tractions at the current time: F_K per cell and their
  // condensed sum. Skipped when the scene has none.
  template <int dim>
  void MechanicalField<dim>::assemble_load()
  {
    TimerOutput::Scope t_(timer, "contact step: assemble load");
    load = 0;
    traction_face_load.clear();
    if (!functions.mechanical_load_present())
      return;

    using Type = Parameters::MechanicalBoundary::Type;
    for (const unsigned int id : prm.body_ids)
      functions.body_force(id).set_time(time);
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      if (bc.type == Type::traction)
        functions.mechanical_boundary(id).set_time(time);

    const hp::QCollection<dim>     quadrature(QGauss<dim>(2));
    const hp::QCollection<dim - 1> face_quadrature(QGauss<dim - 1>(2));
    hp::FEValues<dim>              hp_fe_values(fe,
                                   quadrature,
                                   update_values | update_quadrature_points | update_JxW_values);
    hp::FEFaceValues<dim>          hp_face_values(
      fe, face_quadrature, update_values | update_quadrature_points | update_JxW_values);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const FEValuesExtractors::Vector u(slot_of_body.at(cell->material_id()) * dim);
          const unsigned int               n = cell->get_fe().n_dofs_per_cell();
          dealii::Vector<double>          &F = cell_load[cell->active_cell_index()];
          F.reinit(n);
          hp_fe_values.reinit(cell);
          const FEValues<dim> &fe_values = hp_fe_values.get_present_fe_values();
          const auto          &f         = functions.body_force(cell->material_id());
          for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
            {
              Tensor<1, dim> force;
              for (unsigned int d = 0; d < dim; ++d)
                force[d] = f.value(fe_values.quadrature_point(q), d);
              for (unsigned int i = 0; i < n; ++i)
                F(i) += force * fe_values[u].value(i, q) * fe_values.JxW(q);
            }
          for (const unsigned int face : cell->face_indices())
            if (cell->face(face)->at_boundary())
              {
                const auto bc = prm.mechanical_boundaries.find(cell->face(face)->boundary_id());
                if (bc == prm.mechanical_boundaries.end() || bc->second.type != Type::traction)
                  continue;
                hp_face_values.reinit(cell, face);
                const FEFaceValues<dim> &fv = hp_face_values.get_present_fe_values();
                const auto              &tr = functions.mechanical_boundary(bc->first);
                dealii::Vector<double>   face_load(n);
                for (unsigned int q = 0; q < fv.n_quadrature_points; ++q)
                  {
                    Tensor<1, dim> traction;
                    for (unsigned int d = 0; d < dim; ++d)
                      traction[d] = tr.value(fv.quadrature_point(q), d);
                    for (unsigned int i = 0; i < n; ++i)
                      face_load(i) += traction * fv[u].value(i, q) * fv.JxW(q);
                  }
                F += face_load;
                traction_face_load[{cell->active_cell_index(), face}] = face_load;
              }
          std::vector<types::global_dof_index> dofs(n);
          cell->get_dof_indices(dofs);
          hanging_node_constraints.distribute_local_to_global(F, dofs, load);
        }
    load.compress(VectorOperation::add);
  }



  template class MechanicalField<2>;
} // namespace ContactStefan
