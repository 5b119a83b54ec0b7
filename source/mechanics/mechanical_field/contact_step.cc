// The contact step: linear elasticity with frictionless Signorini conditions on
// rigid obstacles and between bodies, solved by the primal-dual active-set method.
//
// For a guess of the active set every active node is the linear constraint
// n.(u_k - u_l) = g (n.u_k = g at an obstacle; at a mortar slave node the master
// side is a weighted sum of nodes), written in AffineConstraints by solving for
// the displacement component with the larger |n_c|, on top of the hanging-node,
// Dirichlet, tied and roller constraints (where that component is taken, the
// other, then the partner's). The constrained system is assembled from cached
// cell matrices and solved. The compressive normal force of each node is read
// off the residual, lambda = -n.(K u - f)_k, and the node is active next
// iteration if lambda + c d > 0, d = n.(u_k - u_l) - g, c the complementarity
// constant times the node's normal stiffness, until the set does not change;
// warm-started from the previous step's set. If a set recurs, c is divided by
// ten, which makes the update follow the multipliers more and breaks the cycle.
#include <deal.II/base/function_parser.h>

#include <deal.II/lac/solver_cg.h>
#include <deal.II/lac/solver_control.h>
#include <deal.II/lac/trilinos_precondition.h>
#include <deal.II/lac/trilinos_solver.h>

#include <contact-stefan/mechanics/mechanical_field.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include "pieces.h"

namespace ContactStefan
{
  namespace
  {
    // Whether a and b store the same entries in the same order (same maps,
    // same row offsets and local column indices, optimised storage).
    bool same_storage(const TrilinosWrappers::SparseMatrix &a_,
                      const TrilinosWrappers::SparseMatrix &b_)
    {
      auto   &a         = const_cast<Epetra_CrsMatrix &>(a_.trilinos_matrix());
      auto   &b         = const_cast<Epetra_CrsMatrix &>(b_.trilinos_matrix());
      int    *offsets_a = nullptr, *indices_a = nullptr, *offsets_b = nullptr, *indices_b = nullptr;
      double *values_a = nullptr, *values_b = nullptr;
      const int n = a.NumMyRows();
      return a.StorageOptimized() && b.StorageOptimized() && n == b.NumMyRows() &&
             a.NumMyNonzeros() == b.NumMyNonzeros() && a.RowMap().SameAs(b.RowMap()) &&
             a.ColMap().SameAs(b.ColMap()) &&
             a.ExtractCrsDataPointers(offsets_a, indices_a, values_a) == 0 &&
             b.ExtractCrsDataPointers(offsets_b, indices_b, values_b) == 0 &&
             std::equal(offsets_a, offsets_a + n + 1, offsets_b) &&
             std::equal(indices_a, indices_a + a.NumMyNonzeros(), indices_b);
    }

    // to = from for two matrices on the same sparsity pattern: with the same
    // storage (same_storage()) a copy of the value array, otherwise an
    // entry-wise sum into the zeroed matrix. Not copy_from(): it may replace
    // the Epetra matrix that a preconditioner or direct solver still refers to.
    void copy_matrix_values(const TrilinosWrappers::SparseMatrix &from,
                            TrilinosWrappers::SparseMatrix       &to,
                            const bool                            storage_matches)
    {
      to = 0;
      if (storage_matches)
        {
          const auto &a = from.trilinos_matrix();
          auto       &b = const_cast<Epetra_CrsMatrix &>(to.trilinos_matrix());
          std::copy(a[0], a[0] + a.NumMyNonzeros(), b[0]);
        }
      else
        to.add(1., from);
    }
  } // namespace



  // The gap g of every obstacle and interface node at the current time.
  template <int dim>
  void MechanicalField<dim>::update_condition_gaps()
  {
    for (const auto &[pair, law] : prm.interface_pairs)
      functions.interface_gap(pair.first, pair.second).set_time(time);
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      if (bc.type == Parameters::MechanicalBoundary::Type::obstacle)
        functions.obstacle_gap(id).set_time(time);
    for (auto &c : normal_conditions)
      if (c.kind != NormalCondition::Kind::roller)
        c.gap =
          (c.kind == NormalCondition::Kind::obstacle ? functions.obstacle_gap(c.boundary_id) :
                                                       functions.interface_gap(c.body_k, c.body_l))
            .value(Point<dim>(c.position)) +
          c.mortar_gap;
  }



  // n.(u_k - u_l), n.u_k, or n.(u_k - sum_m w_m u_m) at a mortar slave node.
  template <int dim>
  double MechanicalField<dim>::normal_displacement_jump(const NormalCondition &c) const
  {
    double jump = 0;
    for (unsigned int d = 0; d < dim; ++d)
      {
        jump += c.normal[d] * (displacement_ghosted[c.dofs_k[d]] -
                               (c.has_partner ? displacement_ghosted[c.dofs_l[d]] : 0.));
        for (const auto &[dofs_m, w] : c.masters)
          jump -= c.normal[d] * w * displacement_ghosted[dofs_m[d]];
      }
    return jump;
  }



  template <int dim>
  void MechanicalField<dim>::build_contact_constraints(unsigned int &n_skipped)
  {
    constraints.clear();
    constraints.reinit(relevant);
    constraints.merge(fixed_constraints);
    n_skipped = 0;
    placed_per_group.clear();
    imposed_conditions.clear();
    for (const auto &c : normal_conditions)
      {
        const bool is_interface = c.kind == NormalCondition::Kind::interface;
        if (c.kind == NormalCondition::Kind::roller || (is_interface && c.tied))
          continue;
        const Vector &active = active_flags_ghosted(c);
        if (active[c.dofs_k[0]] < 0.5)
          continue;
        // Candidates: side k's components by decreasing |n_c|, then the partner's.
        std::vector<std::pair<unsigned int, bool>> candidates;
        const unsigned int major = std::abs(c.normal[1]) > std::abs(c.normal[0]) ? 1 : 0;
        for (const bool partner : {false, true})
          if (!partner || c.has_partner)
            for (const unsigned int comp : {major, 1 - major})
              candidates.emplace_back(comp, partner);
        bool placed = false;
        for (const auto &[comp, partner] : candidates)
          {
            const auto target = partner ? c.dofs_l[comp] : c.dofs_k[comp];
            if (c.normal[comp] == 0 || constraints.is_constrained(target))
              continue;
            auto row =
              c.mortar ?
                Contact::mortar_constraint(c.dofs_k, c.masters, c.normal, c.gap, comp) :
                Contact::normal_constraint(
                  c.dofs_k, c.has_partner ? &c.dofs_l : nullptr, c.normal, c.gap, comp, partner);
            if (!MechanicalFieldPieces::break_cycles(row, constraints)) // (a slanted roller)
              continue;
            constraints.add_line(row.target);
            for (const auto &[dof, coefficient] : row.entries)
              constraints.add_entry(row.target, dof, coefficient);
            constraints.set_inhomogeneity(row.target, row.inhomogeneity);
            placed = true;
            break;
          }
        n_skipped += !placed;
        if (placed)
          imposed_conditions.insert({c.dofs_k[0], static_cast<int>(c.kind)});
        if (placed && owned.is_element(c.dofs_k[0]))
          ++placed_per_group[c.group];
      }
    // A rank may see a constrained DoF (e.g. the parent of a hanging node) without
    // a cell at which it could build that DoF's contact condition: exchange the
    // constraint lines of locally relevant DoFs (deal.II: before close()).
    if (Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
      constraints.make_consistent_in_parallel(owned, relevant, mpi_communicator);
    constraints.close();
  }



  // The bodies must be held against rigid motion by the current constraints
  // (prescribed displacements, rollers, ties and the active contact set), or
  // the stiffness matrix is singular. The rigid modes are, per body, translation
  // in x, in y and rotation about the body's centre (scaled to unit size); a
  // constraint line u_i = sum_j a_ij u_j + b_i has, for mode r, the homogeneous
  // residual r_i - sum_j a_ij r_j (entries of any body: a closed contact or a tie
  // to a held body holds the other one). The assembly is held iff these residual
  // vectors span all 3 n_bodies modes, i.e. iff their Gram matrix is positive
  // definite; a failing pivot names the body and the motion.
  template <int dim>
  void MechanicalField<dim>::check_rigid_body_modes() const
  {
    const unsigned int  n_modes = 3 * prm.body_ids.size();
    std::vector<double> gram(n_modes * n_modes, 0.);
    const auto          mode = [&](const DofInfo &d, const unsigned int m) {
      if (m / 3 != d.slot)
        return 0.;
      const auto &c = body_frame[d.slot];
      if (m % 3 < 2)
        return d.component == m % 3 ? 1. : 0.;
      return d.component == 0 ? -(d.position[1] - c.first[1]) / c.second :
                                         (d.position[0] - c.first[0]) / c.second;
    };
    std::vector<double> r(n_modes);
    for (const auto &[dof, info] : dof_info)
      if (owned.is_element(dof) && constraints.is_constrained(dof))
        {
          for (unsigned int m = 0; m < n_modes; ++m)
            r[m] = mode(info, m);
          for (const auto &[j, a] : *constraints.get_constraint_entries(dof))
            if (const auto other = dof_info.find(j); other != dof_info.end())
              for (unsigned int m = 0; m < n_modes; ++m)
                r[m] -= a * mode(other->second, m);
          for (unsigned int a = 0; a < n_modes; ++a)
            if (r[a] != 0)
              for (unsigned int b = 0; b < n_modes; ++b)
                gram[a * n_modes + b] += r[a] * r[b];
        }
    Utilities::MPI::sum(gram, mpi_communicator, gram);
    const char *names[3] = {"translation in x", "translation in y", "rotation"};
    // Cholesky; a pivot at or below the tolerance is a free (combination of) mode(s).
    std::vector<double> L(n_modes * n_modes, 0.);
    for (unsigned int i = 0; i < n_modes; ++i)
      for (unsigned int j = 0; j <= i; ++j)
        {
          double sum = gram[i * n_modes + j];
          for (unsigned int k = 0; k < j; ++k)
            sum -= L[i * n_modes + k] * L[j * n_modes + k];
          if (i == j)
            {
              if (sum <= contact_prm.rigid_mode_tolerance)
                throw std::runtime_error(
                  "body " + std::to_string(prm.body_ids[i / 3]) + " is not held against " +
                  names[i % 3] + " at t = " + number(time) +
                  " (the elasticity system would be singular): with the current contact set "
                  "nothing holds it; give it displacement, roller or tied conditions in that "
                  "direction");
              L[i * n_modes + i] = std::sqrt(sum);
            }
          else
            L[i * n_modes + j] = sum / L[j * n_modes + j];
        }
  }



  // The system with the current constraints: K and the right-hand side, or the
  // right-hand side alone (K unchanged: same stiffness, same constraint
  // pattern; the inhomogeneities still go in through the cell matrices).
  //
  // K is the bulk matrix (the cells away from the contact boundaries, which no
  // active set changes) plus the cells near a contact condition, condensed
  // with the current constraints: a contact iteration touches a few hundred
  // cells instead of all. The right-hand side always comes from the
  // vector-only condensation, so that every solve of an active set sees the
  // same vector to the last bit, whether its matrix was re-assembled or not;
  // a cell without load, thermal stress or constrained DoF adds nothing and is
  // skipped.
  template <int dim>
  void MechanicalField<dim>::assemble_system(const bool with_matrix)
  {
    TimerOutput::Scope                   t(timer,
                         with_matrix ? "contact step: assemble" :
                                                         "contact step: assemble right-hand side");
    std::vector<types::global_dof_index> dofs;
    if (with_matrix)
      {
        const std::uint64_t signature = Fingerprint::combine(
          Fingerprint::constraints(fixed_constraints, owned, false, mpi_communicator),
          stiffness_version);
        if (!have_bulk || signature != bulk_signature)
          assemble_bulk_matrix(signature);
        // The copy zeroes system_matrix first: that also clears the entries of
        // other ranks' rows kept since the last compress().
        copy_matrix_values(bulk_matrix, system_matrix, bulk_storage_matches);
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned() && cell_near_contact[cell->active_cell_index()])
            {
              dofs.resize(cell->get_fe().n_dofs_per_cell());
              cell->get_dof_indices(dofs);
              constraints.distribute_local_to_global(cell_stiffness[cell->active_cell_index()],
                                                     dofs,
                                                     system_matrix);
            }
        system_matrix.compress(VectorOperation::add);
      }
    assemble_right_hand_side();
  }



  template <int dim>
  void MechanicalField<dim>::assemble_bulk_matrix(const std::uint64_t signature)
  {
    // have_bulk is false after each new sparsity pattern (setup_dofs()).
    if (!have_bulk)
      {
        bulk_matrix.reinit(system_matrix);
        bulk_storage_matches = same_storage(bulk_matrix, system_matrix);
      }
    bulk_matrix = 0;
    cell_fixed_constrained.assign(triangulation.n_active_cells(), false);
    std::vector<types::global_dof_index> dofs;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int index = cell->active_cell_index();
          dofs.resize(cell->get_fe().n_dofs_per_cell());
          cell->get_dof_indices(dofs);
          for (const auto dof : dofs)
            if (fixed_constraints.is_constrained(dof))
              cell_fixed_constrained[index] = true;
          if (!cell_near_contact[index])
            fixed_constraints.distribute_local_to_global(cell_stiffness[index], dofs, bulk_matrix);
        }
    bulk_matrix.compress(VectorOperation::add);
    bulk_signature = signature;
    have_bulk      = true;
  }



  template <int dim>
  void MechanicalField<dim>::solve_linear_system(const bool factorise, const bool settled)
  {
    if (factorise)
      {
        // Only the constraints changed since the AMG hierarchy was built
        // (same stiffness): LinearSolver::update keeps its aggregates.
        TimerOutput::Scope t(timer, "contact step: factorise");
        if (preconditioner_stiffness_version == stiffness_version)
          linear_solver.update(system_matrix);
        else
          linear_solver.initialize(system_matrix);
        preconditioner_stiffness_version = stiffness_version;
      }
    TimerOutput::Scope t(timer, "contact step: linear solve");
    if (guess_pending)
      {
        // An initial guess (the block correction of the coupling) that already
        // solves the system to the CG tolerance on its free rows stands: no
        // solve, also on the direct path (a constrained row holds what the
        // condensation put there, not the value distribute() gives the guess).
        guess_pending = false;
        Vector residual(owned, mpi_communicator);
        system_matrix.residual(residual, displacement, system_rhs);
        constraints.set_zero(residual);
        if (residual.l2_norm() <= linear_prm.cg_tolerance * system_rhs.l2_norm())
          {
            ++guesses_accepted;
            constraints.distribute(displacement);
            displacement_ghosted = displacement;
            balance_out_of_plane(factorise);
            return;
          }
      }
    linear_solver.solve(displacement,
                        system_rhs,
                        settled ? linear_prm.cg_tolerance : contact_prm.cg_contact_set_tolerance);
    constraints.distribute(displacement);
    displacement_ghosted = displacement;
    balance_out_of_plane(factorise);
  }



  template <int dim>
  std::uint64_t MechanicalField<dim>::constraints_hash(const bool with_inhomogeneities) const
  {
    return Fingerprint::constraints(constraints, owned, with_inhomogeneities, mpi_communicator);
  }



  template <int dim>
  std::uint64_t MechanicalField<dim>::gaps_hash() const
  {
    std::uint64_t local = 0;
    for (const auto &c : normal_conditions)
      if (owned.is_element(c.dofs_k[0]))
        local += Fingerprint::mix(Fingerprint::mix(3 * c.dofs_k[0] + static_cast<int>(c.kind)) +
                                  Fingerprint::bits(c.gap));
    return Utilities::MPI::sum(local, mpi_communicator);
  }



  // The loads of every cell (body and surface loads, thermal stress), bit for
  // bit. The multiplier of a contact condition is the residual of its
  // constrained row, K u - f there, so the loads of constrained rows matter
  // as much as those of free rows: two blocks pressed together by thermal
  // expansion have the same condensed right-hand side at every temperature
  // (the loads of the two interface rows cancel on the row they are tied
  // into), but not the same contact pressure.
  template <int dim>
  std::uint64_t MechanicalField<dim>::loads_hash() const
  {
    const bool    loaded = functions.mechanical_load_present();
    std::uint64_t local  = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int index = cell->active_cell_index();
          std::uint64_t      h     = Fingerprint::mix(index + 1);
          if (loaded)
            for (const double f : cell_load[index])
              h = Fingerprint::mix(h + Fingerprint::bits(f));
          if (thermal_stress)
            for (const double f : cell_thermal_load[index])
              h = Fingerprint::mix(h ^ Fingerprint::bits(f));
          local += h;
        }
    // (The same e_zz on every rank: added once, on the first.)
    if (generalized_plane_strain && Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      for (const double e : ezz)
        local = Fingerprint::mix(local + Fingerprint::bits(e));
    return Utilities::MPI::sum(local, mpi_communicator);
  }



  // All the data a converged contact solve depends on besides the matrix:
  // inhomogeneities (prescribed displacements, gaps of active conditions),
  // the gaps of every condition and the loads of every row.
  template <int dim>
  std::uint64_t MechanicalField<dim>::contact_data_hash() const
  {
    return Fingerprint::combine(Fingerprint::combine(constraints_hash(true), gaps_hash()),
                                loads_hash());
  }



  // result = K u (- f), unconstrained (hanging nodes condensed): the nodal
  // contact forces on the contact nodes and the reactions on Dirichlet nodes.
  template <int dim>
  void MechanicalField<dim>::apply_stiffness(const Vector &u_ghosted,
                                             Vector       &result,
                                             const bool    with_load) const
  {
    result            = 0;
    const bool loaded = with_load && functions.mechanical_load_present();
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const unsigned int                   n = cell->get_fe().n_dofs_per_cell();
          std::vector<types::global_dof_index> dofs(n);
          cell->get_dof_indices(dofs);
          dealii::Vector<double> u(n), r(n);
          for (unsigned int i = 0; i < n; ++i)
            u(i) = u_ghosted[dofs[i]];
          cell_stiffness[cell->active_cell_index()].vmult(r, u);
          if (loaded)
            r -= cell_load[cell->active_cell_index()];
          if (with_load && thermal_stress)
            for (unsigned int i = 0; i < n; ++i)
              r(i) -= cell_thermal_load[cell->active_cell_index()][i];
          if (with_load && generalized_plane_strain)
            r.add(ezz[slot_of_body.at(cell->material_id())],
                  cell_ezz_coupling[cell->active_cell_index()]);
          hanging_node_constraints.distribute_local_to_global(r, dofs, result);
        }
    result.compress(VectorOperation::add);
  }



  template <int dim>
  Vector &MechanicalField<dim>::active_flags(const NormalCondition &c)
  {
    return c.kind == NormalCondition::Kind::interface ? interface_active : obstacle_active;
  }



  template <int dim>
  const Vector &MechanicalField<dim>::active_flags_ghosted(const NormalCondition &c) const
  {
    return c.kind == NormalCondition::Kind::interface ? interface_active_ghosted :
                                                        obstacle_active_ghosted;
  }



  template <int dim>
  bool MechanicalField<dim>::is_active(const NormalCondition &c) const
  {
    return (c.kind == NormalCondition::Kind::interface ? interface_active :
                                                         obstacle_active)[c.dofs_k[0]] > 0.5;
  }



  template <int dim>
  double MechanicalField<dim>::contact_pressure(const NormalCondition &c) const
  {
    return pressure[c.dofs_k[0]];
  }



  template <int dim>
  double MechanicalField<dim>::contact_gap(const NormalCondition &c) const
  {
    return gap[c.dofs_k[0]];
  }



  // For every owned obstacle/interface condition (not tied): the compressive
  // normal force lambda, the gap violation d = n.(u_k - u_l) - g and the scaled
  // complementarity constant. scale: the largest |lambda| + c |d| on this rank.
  //
  // lambda comes from the residual K u - f at the DoFs of the node (pair),
  // which holds the reactions of every constraint acting there: the contact
  // condition, and a roller, a prescribed component or another active contact
  // condition at the same vertex. Contact::constraint_multiplier separates
  // them (the residual is a combination of the constraints' gradients), so a
  // node where an interface meets a roller face reports the contact force
  // alone, not the roller's reaction with it.
  template <int dim>
  std::vector<typename MechanicalField<dim>::Decision>
  MechanicalField<dim>::contact_decisions(const Vector &residual,
                                          double       &local_scale,
                                          double       &max_penetration) const
  {
    Vector r(owned, relevant, mpi_communicator);
    r = residual;
    // The active contact conditions at each DoF they involve.
    std::unordered_map<types::global_dof_index, std::vector<const NormalCondition *>> active_at;
    for (const auto &c : normal_conditions)
      if (c.carries_pressure() && active_flags_ghosted(c)[c.dofs_k[0]] > 0.5)
        for (unsigned int d = 0; d < dim; ++d)
          {
            active_at[c.dofs_k[d]].push_back(&c);
            if (c.has_partner)
              active_at[c.dofs_l[d]].push_back(&c);
          }

    std::vector<Decision> decisions;
    local_scale = 0, max_penetration = 0;
    for (const auto &c : normal_conditions)
      if (c.carries_pressure() && owned.is_element(c.dofs_k[0]))
        {
          // The DoFs that the constraints at this vertex tie together: those of
          // the node (pair), closed under the fixed lines (a tie joins the two
          // sides; a roller the two components) and the other active contact
          // conditions (their partners), so that every reaction acting here is
          // seen in full. A few rounds reach all of them (at most both sides'
          // two components at one vertex).
          std::vector<types::global_dof_index> D(c.dofs_k.begin(), c.dofs_k.end());
          if (c.has_partner)
            D.insert(D.end(), c.dofs_l.begin(), c.dofs_l.end());
          const auto add = [&](const types::global_dof_index dof) {
            if (std::find(D.begin(), D.end(), dof) == D.end())
              D.push_back(dof);
          };
          // Three rounds: node -> its constraints' DoFs -> their partners; all
          // at one vertex, so nothing new can appear after that.
          for (unsigned int round = 0; round < 3; ++round)
            for (const auto dof : std::vector<types::global_dof_index>(D))
              {
                if (fixed_constraints.is_constrained(dof) &&
                    !hanging_node_constraints.is_constrained(dof))
                  for (const auto &[j, a] : *fixed_constraints.get_constraint_entries(dof))
                    add(j);
                if (const auto it = named_by.find(dof); it != named_by.end())
                  for (const auto target : it->second)
                    add(target);
                if (const auto it = active_at.find(dof); it != active_at.end())
                  for (const NormalCondition *o : it->second)
                    for (unsigned int d = 0; d < dim; ++d)
                      {
                        add(o->dofs_k[d]);
                        if (o->has_partner)
                          add(o->dofs_l[d]);
                      }
              }
          const auto index = [&](const types::global_dof_index dof) {
            return std::find(D.begin(), D.end(), dof) - D.begin();
          };
          const auto gradient = [&](const NormalCondition &o) {
            std::vector<double> g(D.size(), 0.);
            for (unsigned int d = 0; d < dim; ++d)
              {
                if (const auto i = index(o.dofs_k[d]); i < long(D.size()))
                  g[i] += o.normal[d];
                if (const auto i = index(o.dofs_l[d]); o.has_partner && i < long(D.size()))
                  g[i] -= o.normal[d];
              }
            return g;
          };
          // The other constraints on D: fixed lines (rollers, prescribed
          // components; hanging-node lines are not reactions) and the other
          // active contact conditions at this vertex.
          std::vector<std::vector<double>>  others;
          std::set<const NormalCondition *> seen{&c};
          for (const auto dof : D)
            {
              if (fixed_constraints.is_constrained(dof) &&
                  !hanging_node_constraints.is_constrained(dof))
                {
                  std::vector<double> g(D.size(), 0.);
                  g[index(dof)] = 1;
                  for (const auto &[j, a] : *fixed_constraints.get_constraint_entries(dof))
                    if (const auto i = index(j); i < long(D.size()))
                      g[i] -= a;
                  others.push_back(g);
                }
              if (const auto it = active_at.find(dof); it != active_at.end())
                for (const NormalCondition *o : it->second)
                  if (seen.insert(o).second)
                    others.push_back(gradient(*o));
            }
          std::vector<double> r_D(D.size());
          for (unsigned int i = 0; i < D.size(); ++i)
            r_D[i] = r[D[i]];
          double lambda = -Contact::constraint_multiplier(gradient(c), others, r_D);
          // Not determined by the constraints at this vertex (its direction lies in
          // the span of the others): the residual's normal component on side k.
          if (std::isnan(lambda))
            {
              lambda = 0;
              for (unsigned int d = 0; d < dim; ++d)
                lambda -= c.normal[d] * r[c.dofs_k[d]];
            }
          const double d = normal_displacement_jump(c) - c.gap;
          const double c_eff =
            contact_prm.complementarity_constant * complementarity_scale * c.stiffness;
          decisions.push_back({&c, lambda, d, c_eff});
          local_scale     = std::max(local_scale, std::abs(lambda) + c_eff * std::abs(d));
          max_penetration = std::max(max_penetration, d);
        }
    return decisions;
  }



  // Nodal pressures and gaps for output, and the forces per group.
  template <int dim>
  void MechanicalField<dim>::store_contact_output(const std::vector<Decision> &decisions,
                                                  ContactStepReport           &report)
  {
    pressure = 0;
    gap      = 0;
    std::map<std::string, double> forces, lengths;
    double                        max_pressure = 0, min_active_pressure = HUGE_VAL;
    for (const auto &dec : decisions)
      {
        pressure[dec.c->dofs_k[0]] = dec.lambda / dec.c->weight;
        gap[dec.c->dofs_k[0]]      = -dec.d;
        forces[dec.c->group] += dec.lambda;
        max_pressure = std::max(max_pressure, dec.lambda / dec.c->weight);
        if (is_active(*dec.c))
          {
            min_active_pressure = std::min(min_active_pressure, dec.lambda / dec.c->weight);
            lengths[dec.c->group] += dec.c->weight;
          }
      }
    pressure.compress(VectorOperation::insert);
    gap.compress(VectorOperation::insert);
    for (const auto &group : contact_groups)
      {
        report.forces[group]          = Utilities::MPI::sum(forces[group], mpi_communicator);
        report.contact_lengths[group] = Utilities::MPI::sum(lengths[group], mpi_communicator);
      }
    report.max_pressure        = Utilities::MPI::max(max_pressure, mpi_communicator);
    report.min_active_pressure = Utilities::MPI::min(min_active_pressure, mpi_communicator);
    if (report.min_active_pressure == HUGE_VAL)
      report.min_active_pressure = 0;
    store_window_sums(decisions, report);
  }



  // Reuse if stationary: the same matrix, loads (of free and constrained rows),
  // inhomogeneities and gaps as the last converged solve, from its converged
  // active set, give its solution, multipliers and set again; nothing is
  // solved. Returns whether the last solve's report (with no work counted) is
  // the answer.
  template <int dim>
  bool MechanicalField<dim>::reuse_if_stationary(ContactStepReport &report)
  {
    if (contact_data_hash() != solved_signature)
      return false;
    report            = last_report;
    report.reused     = true;
    report.iterations = report.changes = report.c_reductions = report.factorisations = 0;
    report.linear = linear_solver.take_statistics();
    return true;
  }



  // Update the active set: every owned condition is active in the next
  // iteration if lambda + c d > tolerance (Contact::is_active). Counts the
  // changes and the active nodes into the report and returns the change
  // together with an order-independent hash of the new set (the same on
  // every rank) and this rank's smallest multiplier of a node that was active.
  template <int dim>
  typename MechanicalField<dim>::SetUpdate
  MechanicalField<dim>::update_active_set(const std::vector<Decision> &decisions,
                                          const double                 tolerance,
                                          ContactStepReport           &report)
  {
    unsigned int  local_changes = 0, local_active = 0;
    std::uint64_t local_hash       = 0;
    double        local_min_lambda = HUGE_VAL;
    for (const auto &dec : decisions)
      {
        Vector    &active     = active_flags(*dec.c);
        const bool was_active = active[dec.c->dofs_k[0]] > 0.5;
        const bool now_active = Contact::is_active(dec.lambda, dec.d, dec.c_eff, tolerance);
        if (was_active)
          local_min_lambda = std::min(local_min_lambda, dec.lambda);
        if (now_active != was_active)
          {
            active[dec.c->dofs_k[0]] = now_active ? 1. : 0.;
            ++local_changes;
          }
        if (now_active)
          {
            ++local_active;
            // Order-independent hash of the set: sum of mixed node keys.
            std::uint64_t key =
              dec.c->dofs_k[0] * 2 + (dec.c->kind == NormalCondition::Kind::interface);
            key ^= key >> 33;
            key *= 0xff51afd7ed558ccdULL;
            key ^= key >> 33;
            local_hash += key;
          }
      }
    obstacle_active.compress(VectorOperation::insert);
    interface_active.compress(VectorOperation::insert);
    obstacle_active_ghosted    = obstacle_active;
    interface_active_ghosted   = interface_active;
    const unsigned int changes = Utilities::MPI::sum(local_changes, mpi_communicator);
    report.active_nodes        = Utilities::MPI::sum(local_active, mpi_communicator);
    report.changes += changes;
    // For the AMG reuse limit: an upper bound of the rows changed (a set
    // that returns to an earlier one counts twice, and a condition without
    // a free DoF changes no row; both only recompute earlier).
    linear_solver.note_changed_rows(changes);
    const std::uint64_t set_hash = Utilities::MPI::sum(local_hash, mpi_communicator);
    return {changes, set_hash, local_min_lambda};
  }



  // Check the converged set: it is a fixed point, which with a small c might
  // still violate the contact conditions; check them with c at full size (no
  // active node pulling, no inactive node penetrating, to the tolerance). A
  // violation stops the run. Collective.
  template <int dim>
  void MechanicalField<dim>::check_converged_set(const std::vector<Decision> &decisions) const
  {
    double local_violation = 0, local_size = 0;
    for (const auto &dec : decisions)
      {
        const bool   active = is_active(*dec.c);
        const double c_full = dec.c_eff / complementarity_scale;
        local_violation     = std::max(local_violation, active ? -dec.lambda : c_full * dec.d);
        local_size          = std::max(local_size, std::abs(dec.lambda) + c_full * std::abs(dec.d));
      }
    const double violation = Utilities::MPI::max(local_violation, mpi_communicator);
    if (violation > 10 * contact_prm.tolerance * Utilities::MPI::max(local_size, mpi_communicator))
      throw std::runtime_error("the contact step converged to a set that violates the contact "
                               "conditions by " +
                               number(violation) + " (force units) at t = " + number(time) +
                               "; see 'Contact/Complementarity constant'");
  }



  // A set recurred more than 'Contact/Max set repetitions' times (a cycle of
  // the plain method): divide c by ten, so that the update follows the
  // multipliers more than the gaps, at most 'Contact/Max c reductions' times.
  template <int dim>
  void MechanicalField<dim>::reduce_complementarity_constant(ContactStepReport &report)
  {
    if (report.c_reductions == contact_prm.max_c_reductions)
      throw std::runtime_error("the contact active set keeps cycling at t = " + number(time) +
                               " after " + std::to_string(report.c_reductions) +
                               " reductions of the complementarity constant "
                               "('Contact/Max c reductions')");
    complementarity_scale /= 10;
    ++report.c_reductions;
    pcout << "   Contact step: active set recurred at t = " << time
          << "; complementarity constant divided by 10" << std::endl;
  }



  // The contact step at the time of begin_time_step(), warm-started from the
  // current active set. Each iteration: impose the conditions of the current
  // set, assemble (and check the rigid modes) where the matrix changed, reuse
  // the last solution if nothing changed since (reuse_if_stationary), solve,
  // read the multipliers off the residual (contact_decisions), update the
  // active set, and stop when it did not change (check_converged_set); a set
  // that recurs reduces c (doc/contact.md, "The active-set iteration").
  template <int dim>
  ContactStepReport MechanicalField<dim>::solve()
  {
    ContactStepReport report;
    Vector            residual(owned, mpi_communicator);
    complementarity_scale = 1;
    std::map<std::uint64_t, unsigned int> seen_sets; // hash of an active set -> visits
    const bool                            has_contact = !contact_groups.empty();
    // Whether the active set has settled (CG then solves to its full tolerance).
    bool         settled           = false;
    unsigned int tightening_solves = 0;
    for (unsigned int it = 1;; ++it)
      {
        if (it - tightening_solves > contact_prm.max_iterations)
          throw StepNotConverged(
            "the contact step did not converge in 'Contact/Max iterations' = " +
            std::to_string(contact_prm.max_iterations) + " iterations at t = " + number(time));
        unsigned int skipped = 0;
        build_contact_constraints(skipped);
        // The matrix depends on the stiffness and the constraint pattern only:
        // with both unchanged it is neither re-assembled nor re-factorised.
        const std::uint64_t signature =
          Fingerprint::combine(constraints_hash(false), stiffness_version);
        const bool same_matrix = have_matrix && signature == matrix_signature;
        // The rigid-mode check reads the constraints' pattern and coefficients
        // only: the matrix at hand was built with these, after they passed it.
        if (!same_matrix)
          check_rigid_body_modes();
        assemble_system(!same_matrix);
        have_matrix      = true;
        matrix_signature = signature;
        if (it == 1 && have_solution && same_matrix)
          {
            if (reuse_if_stationary(report))
              return report;
          }
        const bool factorise = !(have_factorisation && signature == factorisation_signature);
        solve_linear_system(factorise, settled || !has_contact);
        report.factorisations += factorise;
        have_factorisation      = true;
        factorisation_signature = signature;
        report.iterations       = it - tightening_solves;
        if (!has_contact)
          {
            // No obstacle and no interface: one linear solve, no active set.
            store_contact_output({}, report);
            break;
          }
        apply_stiffness(displacement_ghosted, residual, true);

        double       local_scale, max_penetration;
        const auto   decisions = contact_decisions(residual, local_scale, max_penetration);
        const double tolerance =
          contact_prm.tolerance * Utilities::MPI::max(local_scale, mpi_communicator);
        const SetUpdate update = update_active_set(decisions, tolerance, report);

        if (verbosity >= 1)
          pcout << "      contact " << it << ": " << report.active_nodes << " active, "
                << update.changes << " changes, max penetration "
                << Utilities::MPI::max(max_penetration, mpi_communicator) << ", min active lambda "
                << Utilities::MPI::min(update.local_min_lambda, mpi_communicator)
                << (skipped > 0 ?
                      ", " + std::to_string(skipped) + " conditions without a free DoF" :
                      "")
                << std::endl;

        if (update.changes == 0 && !settled && !linear_solver.is_direct())
          {
            // The set settled on an inexact solve (CG to 'CG tolerance while
            // the contact set changes'): solve on it to the full tolerance,
            // from this iterate, and check it again.
            settled = true;
            ++tightening_solves;
            continue;
          }
        if (update.changes == 0)
          {
            check_converged_set(decisions);
            store_contact_output(decisions, report);
            break;
          }
        if (!settled && !linear_solver.is_direct() && seen_sets.count(update.set_hash) > 0)
          {
            // A set recurs while CG solves inexactly: solve exactly from now
            // on before judging it a cycle (noise of the loose solve can flip
            // nodes at the threshold).
            settled = true;
            seen_sets.clear();
          }
        else if (++seen_sets[update.set_hash] > contact_prm.max_set_repetitions)
          {
            reduce_complementarity_constant(report);
            seen_sets.clear();
          }
      }
    solved_signature = contact_data_hash();
    have_solution    = true;
    report.linear    = linear_solver.take_statistics();
    last_report      = report;
    return report;
  }



  // After the primary state was restored on a new mesh (setup_dofs() first):
  // hanging-node values from their parents; the data of the current time step
  // on the new mesh (loads, prescribed displacements, gaps), so that solve() may
  // follow; then the derived contact state from u: multipliers from the
  // residual, gaps from the displacement jump, and the active set by the same
  // test as an iteration of solve() (so the next solve is warm-started from it,
  // never from interpolated 0/1 flags).
  template <int dim>
  void MechanicalField<dim>::after_transfer()
  {
    hanging_node_constraints.distribute(displacement);
    hanging_node_constraints.distribute(old_displacement);
    displacement_ghosted = displacement;
    assemble_load();
    make_fixed_constraints();
    update_condition_gaps();
    functions.check_finite_values(mpi_communicator);
    Vector residual(owned, mpi_communicator);
    apply_stiffness(displacement_ghosted, residual, true);
    complementarity_scale = 1;
    // Twice: the multipliers at a vertex with several contact conditions are
    // separated with the other active conditions, so the set found in the first
    // pass (from none) is the input of the second.
    std::vector<Decision> decisions;
    for (unsigned int pass = 0; pass < 2; ++pass)
      {
        double local_scale, max_penetration;
        decisions = contact_decisions(residual, local_scale, max_penetration);
        const double tolerance =
          contact_prm.tolerance * Utilities::MPI::max(local_scale, mpi_communicator);
        for (Vector *v : {&obstacle_active, &interface_active})
          *v = 0.;
        for (const auto &dec : decisions)
          active_flags(*dec.c)[dec.c->dofs_k[0]] =
            Contact::is_active(dec.lambda, dec.d, dec.c_eff, tolerance) ? 1. : 0.;
        obstacle_active.compress(VectorOperation::insert);
        interface_active.compress(VectorOperation::insert);
        obstacle_active_ghosted  = obstacle_active;
        interface_active_ghosted = interface_active;
      }
    ContactStepReport report;
    store_contact_output(decisions, report);
  }



  template void   MechanicalField<2>::update_condition_gaps();
  template double MechanicalField<2>::normal_displacement_jump(const NormalCondition &c) const;
  template void   MechanicalField<2>::build_contact_constraints(unsigned int &n_skipped);
  template void   MechanicalField<2>::check_rigid_body_modes() const;
  template void   MechanicalField<2>::assemble_system(const bool with_matrix);
  template bool   MechanicalField<2>::reuse_if_stationary(ContactStepReport &report);
  template MechanicalField<2>::SetUpdate
  MechanicalField<2>::update_active_set(const std::vector<Decision> &decisions,
                                        const double                 tolerance,
                                        ContactStepReport           &report);
  template void
  MechanicalField<2>::check_converged_set(const std::vector<Decision> &decisions) const;
  template void   MechanicalField<2>::reduce_complementarity_constant(ContactStepReport &report);
  template void   MechanicalField<2>::assemble_bulk_matrix(const std::uint64_t signature);
  template void   MechanicalField<2>::solve_linear_system(const bool factorise, const bool settled);
  template std::uint64_t
  MechanicalField<2>::constraints_hash(const bool with_inhomogeneities) const;
  template std::uint64_t MechanicalField<2>::gaps_hash() const;
  template std::uint64_t MechanicalField<2>::loads_hash() const;
  template std::uint64_t MechanicalField<2>::contact_data_hash() const;
  template void          MechanicalField<2>::apply_stiffness(const Vector &u_ghosted,
                                                    Vector       &result,
                                                    const bool    with_load) const;
  template Vector       &MechanicalField<2>::active_flags(const NormalCondition &c);
  template const Vector &MechanicalField<2>::active_flags_ghosted(const NormalCondition &c) const;
  template bool          MechanicalField<2>::is_active(const NormalCondition &c) const;
  template double        MechanicalField<2>::contact_pressure(const NormalCondition &c) const;
  template double        MechanicalField<2>::contact_gap(const NormalCondition &c) const;
  template std::vector<typename MechanicalField<2>::Decision>
                MechanicalField<2>::contact_decisions(const Vector &residual,
                                        double       &local_scale,
                                        double       &max_penetration) const;
  template void MechanicalField<2>::store_contact_output(const std::vector<Decision> &decisions,
                                                         ContactStepReport           &report);
  template ContactStepReport MechanicalField<2>::solve();
  template void              MechanicalField<2>::after_transfer();
} // namespace ContactStefan
