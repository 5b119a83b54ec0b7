// Heat transfer across conductance interfaces (doc/interface_heat.md): the
// slots that give the two sides of such an interface their own temperature,
// the interface nodes, and the conductance term of the conductivity matrix.
//
// The flux from side k to side l is q = h (Theta_k - Theta_l), lumped on the
// interface's vertices: a vertex of weight w (half the length of its faces)
// adds w h [1 -1; -1 1] to the rows and columns of its two DoFs. The term is
// symmetric with zero row and column sums, so what leaves one side enters
// the other to round-off and A stays an M-matrix (the enthalpy step's
// active-set method keeps its finite termination). h is evaluated at the
// vertices from the state of the last iterate and held fixed within a
// solve(): a secant linearisation that the fixed-point coupling iterates to
// the implicit value.
#include <deal.II/base/mpi.h>

#include <deal.II/fe/fe_nothing.h>
#include <deal.II/fe/fe_system.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/core/slot_sum.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <set>

namespace ContactStefan
{
  // Slots: bodies joined by interfaces in perfect thermal contact form a
  // group (they share nodes); groups that meet -- at a conductance interface,
  // or only at a vertex -- must have different slots. Groups are coloured
  // greedily in the order of their first body, so a casting and its mould
  // take two slots however many bodies each has. A conductance interface
  // inside a group (its bodies also joined through perfect contacts) has no
  // consistent meaning and is refused, and so is one whose bodies share no
  // face (a mistyped pair would act nowhere).
  template <int dim>
  void ThermalField<dim>::setup_slots(const std::vector<BodyInterface<dim>> &interfaces)
  {
    if (conductance_interfaces.empty())
      {
        if (fe_collection.size() == 0)
          fe_collection.push_back(fe);
        return;
      }
    std::vector<std::pair<unsigned int, unsigned int>> local;
    for (const auto &interface : interfaces)
      if (!interface.faces.empty())
        local.emplace_back(interface.body_k, interface.body_l);
    std::set<std::pair<unsigned int, unsigned int>> touching;
    for (const auto &pairs : Utilities::MPI::all_gather(mpi_communicator, local))
      touching.insert(pairs.begin(), pairs.end());

    const auto conductance = [this](const unsigned int k, const unsigned int l) {
      return prm.interface_pair(k, l).thermal_contact ==
             Parameters::InterfacePair::ThermalContact::conductance;
    };
    // (The sides of a mortar interface are meshed apart: they share no face
    // and no node, and need no slots of their own.)
    for (const auto &[pair, law] : prm.interface_pairs)
      if (conductance(pair.first, pair.second) && touching.count(pair) == 0 &&
          law.discretisation != Parameters::InterfacePair::Discretisation::mortar)
        throw InputError("Contact/" + Parameters::InterfacePair::section(pair.first, pair.second) +
                           "/Thermal contact",
                         "bodies " + std::to_string(pair.first) + " and " +
                           std::to_string(pair.second) +
                           " share no face on the mesh, so the conductance would act nowhere");
    std::map<unsigned int, unsigned int> group;
    for (const unsigned int id : prm.body_ids)
      group[id] = id;
    const std::function<unsigned int(unsigned int)> find = [&](const unsigned int id) {
      return group[id] == id ? id : (group[id] = find(group[id]));
    };
    for (const auto &[k, l] : touching)
      if (!conductance(k, l))
        group[find(k)] = find(l);
    for (const auto &[k, l] : touching)
      if (conductance(k, l) && find(k) == find(l))
        throw InputError("Contact/" + Parameters::InterfacePair::section(k, l) + "/Thermal contact",
                         "bodies " + std::to_string(k) + " and " + std::to_string(l) +
                           " are also joined through interfaces in perfect thermal contact, so "
                           "they share a temperature; make those interfaces conductances too, "
                           "or this one perfect");
    // Groups that meet anywhere, at a face or only at a vertex, need different
    // slots: one slot would give them a shared node there, a path for heat
    // around the conductance (a point has no area: it carries none).
    std::vector<std::pair<unsigned int, unsigned int>> meeting;
    {
      std::map<unsigned int, std::set<unsigned int>> bodies_at;
      for (const auto &cell : triangulation.active_cell_iterators())
        if (!cell->is_artificial())
          for (const unsigned int v : cell->vertex_indices())
            bodies_at[cell->vertex_index(v)].insert(cell->material_id());
      std::set<std::pair<unsigned int, unsigned int>> local_meeting;
      for (const auto &[vertex, bodies] : bodies_at)
        for (const unsigned int a : bodies)
          for (const unsigned int b : bodies)
            if (a < b)
              local_meeting.emplace(a, b);
      std::set<std::pair<unsigned int, unsigned int>> all;
      for (const auto &pairs :
           Utilities::MPI::all_gather(mpi_communicator,
                                      std::vector<std::pair<unsigned int, unsigned int>>(
                                        local_meeting.begin(), local_meeting.end())))
        all.insert(pairs.begin(), pairs.end());
      meeting.assign(all.begin(), all.end());
    }
    std::map<unsigned int, unsigned int> colour; // of each group
    for (const unsigned int id : prm.body_ids)
      {
        const unsigned int g = find(id);
        if (colour.count(g))
          continue;
        std::set<unsigned int> used;
        for (const auto &[k, l] : meeting)
          if (find(k) != find(l) && (find(k) == g || find(l) == g))
            {
              const unsigned int other = find(k) == g ? find(l) : find(k);
              if (colour.count(other))
                used.insert(colour[other]);
            }
        unsigned int c = 0;
        while (used.count(c))
          ++c;
        colour[g] = c;
      }
    unsigned int slots = 1;
    for (const unsigned int id : prm.body_ids)
      {
        slot_of_body[id] = colour[find(id)];
        slots            = std::max(slots, slot_of_body[id] + 1);
      }
    if (fe_collection.size() == 0)
      {
        n_slots = slots;
        if (n_slots == 1)
          fe_collection.push_back(fe);
        else
          fe_collection = slot_elements<dim>(n_slots, 1);
      }
    if (slots != n_slots)
      throw std::logic_error("the thermal slots changed with the mesh");
    if (n_slots > 1)
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          cell->set_active_fe_index(slot_of_body.at(cell->material_id()));
  }



  // One node per vertex of a conductance interface on the owned cells, with
  // the DoFs of its two sides (the cells the interface names: vertex v of a
  // cell is its v-th DoF).
  template <int dim>
  void ThermalField<dim>::setup_conductance_nodes(const std::vector<BodyInterface<dim>> &interfaces)
  {
    conductance_nodes.clear();
    interface_point.clear();
    // The contact step's state belongs to the old mesh's vertices: until the
    // next contact step, the interface's Gap stands in.
    interface_contact.clear();
    have_interface_contact = false;
    if (conductance_interfaces.empty())
      return;
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    const auto dof_at = [&](const typename Triangulation<dim>::active_cell_iterator &c,
                            const unsigned int                                       v) {
      const typename DoFHandler<dim>::active_cell_iterator cell(&triangulation,
                                                                c->level(),
                                                                c->index(),
                                                                &dof_handler);
      cell->get_dof_indices(dofs);
      return dofs[v];
    };
    for (const auto &interface : interfaces)
      for (unsigned int i = 0; i < conductance_interfaces.size(); ++i)
        if (!conductance_interfaces[i].mortar &&
            conductance_interfaces[i].body_k == interface.body_k &&
            conductance_interfaces[i].body_l == interface.body_l)
          for (const auto &vertex : interface.vertices)
            {
              ConductanceNode node;
              node.interface = i;
              node.vertex    = vertex.index;
              node.position  = vertex.position;
              node.centre_k  = vertex.cell_k->center();
              node.centre_l  = vertex.cell_l->center();
              node.dof_k     = dof_at(vertex.cell_k, vertex.vertex_k);
              node.dof_l     = dof_at(vertex.cell_l, vertex.vertex_l);
              node.weight    = vertex.weight;
              node.owned_k   = owned.is_element(node.dof_k);
              node.owned_l   = owned.is_element(node.dof_l);
              if (node.dof_k == node.dof_l || hanging_node_constraints.is_constrained(node.dof_k) ||
                  hanging_node_constraints.is_constrained(node.dof_l))
                throw std::logic_error("a conductance interface node has no two free sides");
              conductance_nodes.push_back(node);
            }
    interface_point.clear();
    for (const auto &node : conductance_nodes)
      for (const auto &[dof, centre] :
           {std::pair(node.dof_k, node.centre_k), std::pair(node.dof_l, node.centre_l)})
        {
          interface_point.emplace(dof,
                                  node.position + interface_side_offset * (centre - node.position));
        }
    interface_point.insert(mortar_interface_points.begin(), mortar_interface_points.end());
  }



  template <int dim>
  void ThermalField<dim>::add_conductance_sparsity(DynamicSparsityPattern &dsp) const
  {
    for (const auto &node : conductance_nodes)
      {
        dsp.add(node.dof_k, node.dof_l);
        dsp.add(node.dof_l, node.dof_k);
      }
    for (const auto &node : mortar_conductance_nodes)
      for (const auto &[master, w] : node.masters)
        {
          dsp.add(node.dof, master);
          dsp.add(master, node.dof);
        }
  }



  template <int dim>
  bool ThermalField<dim>::conductance_depends_on_contact() const
  {
    for (const auto &c : conductance_interfaces)
      if (c.law->depends_on_contact())
        return true;
    return false;
  }



  // The gap, pressure and closed flag at an interface node: the contact
  // step's (keyed by vertex, or by slave node on a mortar interface), or the
  // interface's Gap function with pressure 0 where the contact step has none
  // -- before the first contact step on a mesh, and at a node whose contact
  // condition was left out because all its displacement components are
  // prescribed (it cannot open or close).
  template <int dim>
  void ThermalField<dim>::contact_state(const ConductanceInterface &interface,
                                        const unsigned int          key,
                                        const Point<dim>           &position,
                                        ConductanceState           &state) const
  {
    if (have_interface_contact)
      {
        const auto it = interface_contact.find({interface.body_k, interface.body_l, key});
        if (it != interface_contact.end())
          {
            state.gap      = it->second.gap;
            state.pressure = it->second.pressure;
            state.closed   = it->second.closed;
            return;
          }
      }
    Function<dim> &gap = functions.interface_gap(interface.body_k, interface.body_l);
    gap.set_time(time);
    state.gap      = gap.value(position);
    state.pressure = 0;
    state.closed   = state.gap <= 0;
  }



  // h at every node from the present state: the contact step's gap and
  // pressure (or the interface's Gap where there is no mechanics), the
  // temperatures of the two sides (the last iterate), their liquid fractions
  // at the previous time level (lagged like a phase-dependent conductivity:
  // the phase at a wall node is not a smooth function of h, and a fixed
  // point on it need not converge), the position and the time. A law that
  // cannot be evaluated (a negative or non-finite expression) stops the run
  // on every rank with its reason. Returns the largest change of h relative
  // to the larger of the old and new largest h.
  template <int dim>
  double ThermalField<dim>::update_conductances()
  {
    if (conductance_interfaces.empty())
      return 0;
    bool        changed = false;
    double      change = 0, largest = 0;
    std::string problem;
    Vector      h_old(owned, relevant, mpi_communicator);
    h_old = old_enthalpy;
    try
      {
        for (auto &node : conductance_nodes)
          {
            const ConductanceInterface &interface = conductance_interfaces[node.interface];
            ConductanceState            state;
            contact_state(interface, node.vertex, node.position, state);
            state.temperature = {
              {temperature_ghosted[node.dof_k], temperature_ghosted[node.dof_l]}};
            state.liquid_fraction    = {{law(node.dof_k).liquid_fraction(h_old[node.dof_k]),
                                         law(node.dof_l).liquid_fraction(h_old[node.dof_l])}};
            state.position           = {{node.position[0], node.position[1]}};
            state.time               = time;
            const ConductanceTerms h = interface.law->evaluate(state);
            changed                  = changed || h.total() != node.h.total();
            change                   = std::max(change, std::abs(h.total() - node.h.total()));
            largest                  = std::max({largest, h.total(), node.h.total()});
            node.h                   = h;
          }
        // Mortar nodes: every rank evaluates every node from the same data.
        for (auto &node : mortar_conductance_nodes)
          {
            const ConductanceInterface &interface = conductance_interfaces[node.interface];
            ConductanceState            state     = mortar_conductance_state(node, h_old);
            contact_state(interface, node.node, node.position, state);
            const ConductanceTerms h = interface.law->evaluate(state);
            changed                  = changed || h.total() != node.h.total();
            change                   = std::max(change, std::abs(h.total() - node.h.total()));
            largest                  = std::max({largest, h.total(), node.h.total()});
            node.h                   = h;
          }
      }
    catch (const std::exception &error)
      {
        problem = error.what();
      }
    throw_collectively<std::runtime_error>(problem, mpi_communicator);
    if (Utilities::MPI::max(changed ? 1u : 0u, mpi_communicator) > 0)
      ++conductivity_version;
    change  = Utilities::MPI::max(change, mpi_communicator);
    largest = Utilities::MPI::max(largest, mpi_communicator);
    return largest > 0 ? change / largest : 0.;
  }



  // Each rank writes the rows it owns (the node is on an owned cell of the
  // owner of either DoF), so no entry travels between ranks and the interface
  // needs no hanging-node condensation (its vertices are never hanging: the
  // interface is conforming).
  template <int dim>
  void ThermalField<dim>::add_conductance_matrix(TrilinosWrappers::SparseMatrix &matrix) const
  {
    for (const auto &node : conductance_nodes)
      {
        const double wh = node.weight * node.h.total();
        if (node.owned_k)
          {
            matrix.add(node.dof_k, node.dof_k, wh);
            matrix.add(node.dof_k, node.dof_l, -wh);
          }
        if (node.owned_l)
          {
            matrix.add(node.dof_l, node.dof_l, wh);
            matrix.add(node.dof_l, node.dof_k, -wh);
          }
      }
    // A mortar slave node j and its masters m: h_j W_jm [1 -1; -1 1] per pair.
    for (const auto &node : mortar_conductance_nodes)
      for (const auto &[master, w] : node.masters)
        {
          const double wh = w * node.h.total();
          if (owned.is_element(node.dof))
            {
              matrix.add(node.dof, node.dof, wh);
              matrix.add(node.dof, master, -wh);
            }
          if (owned.is_element(master))
            {
              matrix.add(master, master, wh);
              matrix.add(master, node.dof, -wh);
            }
        }
  }



  template <int dim>
  void ThermalField<dim>::add_conductance_product(const Vector &theta, Vector &result) const
  {
    for (const auto &node : conductance_nodes)
      {
        const double q = node.weight * node.h.total() * (theta[node.dof_k] - theta[node.dof_l]);
        if (node.owned_k)
          result[node.dof_k] += q;
        if (node.owned_l)
          result[node.dof_l] -= q;
      }
    for (const auto &node : mortar_conductance_nodes)
      for (const auto &[master, w] : node.masters)
        {
          const double q = w * node.h.total() * (theta[node.dof] - theta[master]);
          if (owned.is_element(node.dof))
            result[node.dof] += q;
          if (owned.is_element(master))
            result[master] -= q;
        }
  }



  // Per interface: sum over its nodes of w h (Theta_k - Theta_l), by term;
  // the mean h over the interface's length.
  template <int dim>
  std::vector<InterfaceHeat> ThermalField<dim>::interface_heat() const
  {
    const unsigned int  n = conductance_interfaces.size();
    std::vector<double> sums(7 * n, 0.);
    for (const auto &node : conductance_nodes)
      if (node.owned_k)
        {
          double      *s  = &sums[7 * node.interface];
          const double dT = temperature_ghosted[node.dof_k] - temperature_ghosted[node.dof_l];
          const double w  = node.weight;
          s[0] += w * node.h.constant * dT;
          s[1] += w * node.h.contact * dT;
          s[2] += w * node.h.gas * dT;
          s[3] += w * node.h.radiation * dT;
          s[4] += w * node.h.function * dT;
          s[5] += w * node.h.total();
          s[6] += w;
        }
    // Mortar nodes (the same on every rank): counted once, by rank 0, pair by
    // pair from side k to side l.
    if (Utilities::MPI::this_mpi_process(mpi_communicator) == 0)
      for (const auto &node : mortar_conductance_nodes)
        {
          double      *s    = &sums[7 * node.interface];
          const double sign = node.slave_is_k ? 1. : -1.;
          for (const auto &[master, w] : node.masters)
            {
              const double dT =
                sign * w * (temperature_ghosted[node.dof] - temperature_ghosted[master]);
              s[0] += node.h.constant * dT;
              s[1] += node.h.contact * dT;
              s[2] += node.h.gas * dT;
              s[3] += node.h.radiation * dT;
              s[4] += node.h.function * dT;
            }
          s[5] += node.D * node.h.total();
          s[6] += node.D;
        }
    Utilities::MPI::sum(sums, mpi_communicator, sums);
    std::vector<InterfaceHeat> result(n);
    for (unsigned int i = 0; i < n; ++i)
      {
        const double *s            = &sums[7 * i];
        result[i].name             = conductance_interfaces[i].name;
        result[i].rates            = {s[0], s[1], s[2], s[3], s[4]};
        result[i].rate             = result[i].rates.total();
        result[i].mean_conductance = s[6] > 0 ? s[5] / s[6] : 0.;
      }
    return result;
  }



  template void   ThermalField<2>::setup_slots(const std::vector<BodyInterface<2>> &);
  template void   ThermalField<2>::setup_conductance_nodes(const std::vector<BodyInterface<2>> &);
  template void ThermalField<2>::add_conductance_sparsity(DynamicSparsityPattern &) const;
  template bool ThermalField<2>::conductance_depends_on_contact() const;
  template double ThermalField<2>::update_conductances();
  template void   ThermalField<2>::contact_state(const ConductanceInterface &,
                                               const unsigned int,
                                               const Point<2> &,
                                               ConductanceState &) const;
  template void ThermalField<2>::add_conductance_matrix(TrilinosWrappers::SparseMatrix &) const;
  template void ThermalField<2>::add_conductance_product(const Vector &, Vector &) const;
  template std::vector<InterfaceHeat> ThermalField<2>::interface_heat() const;
} // namespace ContactStefan
