// Perfect thermal contact across a mortar interface (Contact/Interface k-l/
// Discretisation = mortar, Thermal contact = perfect; doc/contact.md,
// "Non-matching interfaces"). The two sides are meshed independently, so
// each has its own temperature DoFs; continuity is imposed weakly with the
// dual basis psi_j of the slave side,
//
//   int_Gamma psi_j (Theta_slave - Theta_master) = 0   for every slave node j,
//
// which, psi_j being biorthogonal to the slave hat functions, is one equation
// per slave node: D_j Theta_j = sum_m M_jm Theta_m. It is statically
// condensed: Theta_j = sum_m (M_jm / D_j) Theta_m is a constraint line, and
// the slave node becomes a hanging node of the master side. Everything the
// enthalpy step does with hanging nodes then holds for it: its lumped mass,
// its conductivity rows and its loads are distributed to the master nodes by
// the same weights, its enthalpy and temperature are interpolated, and the
// totals (stored heat, energy balance) count the master nodes only. The
// condensed system is the mortar (weakly continuous) Galerkin system, whose
// heat leaving the slave side enters the master side exactly (sum_m M_jm =
// D_j to round-off), and which reproduces a temperature linear along the
// interface exactly (the dual basis reproduces linear functions).
//
// The coupling is the contact step's: interfaces/mortar_interface.h builds it
// from the same faces with the same rules, so that the contact conditions
// and the thermal lines name the same slave nodes.
#include <deal.II/base/mpi.h>

#include <deal.II/dofs/dof_tools.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/interfaces/mortar_interface.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>

namespace ContactStefan
{
  namespace
  {
    // Where a node enters a line: the interface, its position, the pair.
    struct MortarNodeUse
    {
      std::string                           interface;
      std::array<double, 2>                 position;
      std::pair<unsigned int, unsigned int> pair;
    };

    // A slave node takes one line, and no master node is a slave elsewhere:
    // where the sides of two mortar interfaces meet, a second line would
    // count the node's heat twice, and lines that name each other make
    // AffineConstraints::close() substitute them into each other for ever
    // (a chain without a loop would close, but the slave laws and enthalpies
    // read the lines unresolved). Decided on data every rank has in full.
    void refuse_chained_lines(
      const std::map<types::global_dof_index, std::vector<MortarNodeUse>> &slave_of,
      const std::map<types::global_dof_index, std::vector<MortarNodeUse>> &master_of)
    {
      const auto refuse = [](const MortarNodeUse &use, const std::string &why) {
        throw InputError("Contact/" +
                           Parameters::InterfacePair::section(use.pair.first, use.pair.second) +
                           "/Mortar boundaries",
                         "the node at (" + std::to_string(use.position[0]) + ", " +
                           std::to_string(use.position[1]) + ") " + why +
                           "; a node takes one thermal mortar line: let the sides end apart, or "
                           "choose 'Mortar slave' so that the node is a master of both");
      };
      for (const auto &[dof, uses] : slave_of)
        {
          if (uses.size() > 1)
            refuse(uses[0],
                   "is a slave node of " + uses[0].interface + " and of " + uses[1].interface);
          const auto m = master_of.find(dof);
          if (m != master_of.end())
            refuse(uses[0],
                   "is a slave node of " + uses[0].interface + " and a master node of " +
                     m->second[0].interface);
        }
    }
  } // namespace



  template <int dim>
  void ThermalField<dim>::make_node_constraints()
  {
    using Law = Parameters::InterfacePair;
    // Lines (slave DoF, weights of the master DoFs) of the slave nodes this
    // rank sees.
    auto &lines = mortar_lines;
    lines.clear();
    IndexSet     masters(dof_handler.n_dofs());
    unsigned int n_interfaces = 0;
    for (const auto &[pair, law] : prm.interface_pairs)
      if (law.discretisation == Law::Discretisation::mortar &&
          law.thermal_contact == Law::ThermalContact::perfect)
        ++n_interfaces;
    have_thermal_mortar = n_interfaces > 0;
    // The slave nodes of the perfect lines (all ranks), which a conductance
    // may not name.
    std::map<types::global_dof_index, MortarNodeUse> perfect_slaves;
    if (n_interfaces > 0)
      {
        // A slave node on a boundary with a prescribed temperature keeps it:
        // its line would override the boundary value (hanging constraints
        // come first, make_dirichlet_constraints()). Decided from the owned
        // cells of all ranks, so that every rank drops the same lines.
        std::vector<types::global_dof_index> fixed;
        std::vector<types::global_dof_index> dofs;
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned int f : cell->face_indices())
              if (cell->face(f)->at_boundary())
                {
                  const auto bc = prm.thermal_boundaries.find(cell->face(f)->boundary_id());
                  if (bc == prm.thermal_boundaries.end() ||
                      bc->second.type != Parameters::ThermalBoundary::Type::temperature)
                    continue;
                  dofs.resize(cell->get_fe().n_dofs_per_cell());
                  cell->get_dof_indices(dofs);
                  for (unsigned int v = 0; v < GeometryInfo<dim>::vertices_per_face; ++v)
                    fixed.push_back(dofs[GeometryInfo<dim>::face_to_cell_vertices(f, v)]);
                }
        std::set<types::global_dof_index> on_dirichlet;
        for (const auto &part : Utilities::MPI::all_gather(mpi_communicator, fixed))
          on_dirichlet.insert(part.begin(), part.end());
        std::map<types::global_dof_index, std::vector<MortarNodeUse>> slave_of, master_of;

        for (const auto &[pair, law] : prm.interface_pairs)
          {
            if (law.discretisation != Law::Discretisation::mortar ||
                law.thermal_contact != Law::ThermalContact::perfect)
              continue;
            const MortarInterface mi =
              couple_mortar_interface<dim>(dof_handler, pair, law, mortar_configuration);
            // The whole coupling is the same on every rank: record every
            // line's slave and masters (by position, for the message) to
            // refuse a node that two lines would name.
            for (unsigned int j = 0; j < mi.slave_side().nodes.size(); ++j)
              if (mi.conditioned[j] && !on_dirichlet.count(mi.slave_dofs()[j][0]))
                {
                  const Point<2> x = mi.slave_position(j);
                  slave_of[mi.slave_dofs()[j][0]].push_back({mi.name, {{x[0], x[1]}}, pair});
                  for (const auto &[m, value] : mi.coupling.slave[j].M)
                    {
                      const Point<2> y = mi.mesh_position(1 - mi.slave, m);
                      master_of[mi.master_dofs()[m][0]].push_back({mi.name, {{y[0], y[1]}}, pair});
                    }
                }
            for (unsigned int j = 0; j < mi.slave_side().nodes.size(); ++j)
              {
                const types::global_dof_index slave = mi.slave_dofs()[j][0];
                if (!mi.conditioned[j] || !relevant.is_element(slave) || on_dirichlet.count(slave))
                  continue;
                const Mortar::SlaveNode &node = mi.coupling.slave[j];
                auto                    &line =
                  lines
                    .emplace_back(slave, std::vector<std::pair<types::global_dof_index, double>>())
                    .second;
                for (const auto &[m, value] : node.M)
                  {
                    const types::global_dof_index master = mi.master_dofs()[m][0];
                    line.emplace_back(master, value / node.D);
                    masters.add_index(master);
                  }
              }
          }
        relevant.add_indices(masters);
        refuse_chained_lines(slave_of, master_of);
        for (const auto &[dof, uses] : slave_of)
          perfect_slaves.emplace(dof, uses[0]);
      }
    {
      IndexSet conductance_dofs(dof_handler.n_dofs());
      couple_mortar_conductances(conductance_dofs);
      relevant.add_indices(conductance_dofs);
      // A conductance exchanges heat between free nodes: a node that a
      // perfect mortar line constrains would take raw, uncondensed entries
      // (and lose the heat to round-off of nothing: the energy balance
      // breaks). Decided on data every rank has in full.
      for (const auto &node : mortar_conductance_nodes)
        {
          std::vector<types::global_dof_index> named{node.dof};
          for (const auto &[master, w] : node.masters)
            named.push_back(master);
          for (const auto dof : named)
            if (const auto it = perfect_slaves.find(dof); it != perfect_slaves.end())
              {
                const ConductanceInterface &ci = conductance_interfaces[node.interface];
                throw InputError("Contact/" +
                                   Parameters::InterfacePair::section(ci.body_k, ci.body_l) +
                                   "/Mortar boundaries",
                                 "the node at (" + std::to_string(it->second.position[0]) + ", " +
                                   std::to_string(it->second.position[1]) +
                                   ") is a slave node of " + it->second.interface +
                                   " (perfect thermal contact) and a node of the conductance of " +
                                   ci.name +
                                   "; let the sides end apart, or choose 'Mortar slave' of " +
                                   it->second.interface + " so that the node is its master");
              }
        }
    }

    hanging_node_constraints.clear();
    hanging_node_constraints.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dof_handler, hanging_node_constraints);
    // (A boundary node is never hanging: no line is there yet.)
    for (const auto &[slave, entries] : lines)
      {
        hanging_node_constraints.add_line(slave);
        hanging_node_constraints.add_entries(slave, entries);
      }
    hanging_node_constraints.close();
  }



  // A conductance across a mortar interface (Thermal contact = conductance):
  // the flux h (Theta_slave - Theta_master) between the two sides' own
  // temperatures, lumped pair by pair: slave node j and master node m
  // exchange h_j W_jm (Theta_j - Theta_m), with the pair weights W_jm >= 0 of
  // interfaces/mortar.h (sum_m W_jm = D_j). The term is symmetric with zero
  // row sums and non-positive off-diagonal entries, so what leaves one side
  // enters the other to round-off and the conductivity matrix stays an
  // M-matrix (the dual weights M_jm can be negative and would not keep it);
  // on matching sides W = D I and it is the nodal term, w h [1 -1; -1 1]; a
  // jump of temperature that is uniform along the interface crosses it
  // exactly. h_j is evaluated at the slave node from the contact step's gap,
  // pressure and closed flag there, the slave's temperature and liquid
  // fraction, and the W-weighted mean of its masters'. Only the slave nodes
  // with a contact condition (coverage above 'Mortar minimum coverage')
  // exchange heat. Every rank keeps every node, so that each can write the
  // rows it owns: the interface's DoFs join the locally relevant set.
  template <int dim>
  void ThermalField<dim>::couple_mortar_conductances(IndexSet &dofs)
  {
    mortar_conductance_nodes.clear();
    mortar_interface_points.clear();
    std::map<types::global_dof_index, Point<dim>> points;
    for (unsigned int i = 0; i < conductance_interfaces.size(); ++i)
      {
        const ConductanceInterface &ci = conductance_interfaces[i];
        if (!ci.mortar)
          continue;
        const std::pair<unsigned int, unsigned int> pair(ci.body_k, ci.body_l);
        const MortarInterface                       mi = couple_mortar_interface<dim>(
          dof_handler, pair, prm.interface_pair(ci.body_k, ci.body_l), mortar_configuration);
        for (unsigned int j = 0; j < mi.slave_side().nodes.size(); ++j)
          {
            if (!mi.conditioned[j])
              continue;
            const Mortar::SlaveNode &sn = mi.coupling.slave[j];
            MortarConductanceNode    node;
            node.interface  = i;
            node.node       = j;
            node.position   = mi.slave_position(j);
            node.dof        = mi.slave_dofs()[j][0];
            node.D          = sn.D;
            node.slave_is_k = mi.slave == 0;
            dofs.add_index(node.dof);
            for (const auto &[m, w] : sn.W)
              {
                node.masters.emplace_back(mi.master_dofs()[m][0], w);
                dofs.add_index(mi.master_dofs()[m][0]);
              }
            mortar_conductance_nodes.push_back(std::move(node));
          }
        // Functions (initial condition, boundary values, exact solution) are
        // evaluated for a node of either side inside a cell of its side.
        for (unsigned int side = 0; side < 2; ++side)
          {
            const Mortar::Side &S = mi.sides[side];
            for (unsigned int e = 0; e < S.edges.size(); ++e)
              for (const unsigned int v : S.edges[e])
                {
                  const Point<dim> x = mi.mesh_position(side, v),
                                   inside(mi.inside_on_mesh[side][e][0],
                                          mi.inside_on_mesh[side][e][1]);
                  points.emplace(mi.dofs[side][v][0], x + interface_side_offset * (inside - x));
                }
          }
      }
    mortar_interface_points.assign(points.begin(), points.end());
  }



  template <int dim>
  ConductanceState ThermalField<dim>::mortar_conductance_state(const MortarConductanceNode &node,
                                                               const Vector &h_old) const
  {
    double temperature = 0, fraction = 0;
    for (const auto &[master, w] : node.masters)
      {
        temperature += w * temperature_ghosted[master];
        fraction += w * law(master).liquid_fraction(h_old[master]);
      }
    const std::array<double, 2> slave{
      {temperature_ghosted[node.dof], law(node.dof).liquid_fraction(h_old[node.dof])}};
    const std::array<double, 2> master{{temperature / node.D, fraction / node.D}};
    const auto                 &k = node.slave_is_k ? slave : master;
    const auto                 &l = node.slave_is_k ? master : slave;
    ConductanceState            state;
    state.temperature     = {{k[0], l[0]}};
    state.liquid_fraction = {{k[1], l[1]}};
    state.position        = {{node.position[0], node.position[1]}};
    state.time            = time;
    return state;
  }



  template <int dim>
  void ThermalField<dim>::set_mortar_slave_laws()
  {
    for (const auto &[slave, entries] : mortar_lines)
      {
        std::map<unsigned int, double> weight_of_law;
        double                         total = 0;
        for (const auto &[master, w] : entries)
          if (w > 0)
            {
              weight_of_law[law_of_node[relevant.index_within_set(master)]] += w;
              total += w;
            }
        if (weight_of_law.empty())
          continue;
        unsigned int &law = law_of_node[relevant.index_within_set(slave)];
        if (weight_of_law.size() == 1)
          law = weight_of_law.begin()->first;
        else
          {
            std::vector<std::pair<double, const EnthalpyLaw *>> terms;
            for (const auto &[l, w] : weight_of_law)
              terms.emplace_back(w / total, &laws[l]);
            laws.push_back(EnthalpyLaw::weighted_sum(terms));
            law = laws.size() - 1;
          }
      }
  }



  template <int dim>
  void ThermalField<dim>::interpolate_mortar_slave_enthalpies()
  {
    if (!have_thermal_mortar)
      return;
    to_ghosted(enthalpy, enthalpy_ghosted);
    double *h = entries(enthalpy), *state = entries(phase_state);
    for (const auto &[slave, line] : mortar_lines)
      if (owned.is_element(slave))
        {
          const unsigned int i     = slave - first_owned;
          double             value = 0;
          for (const auto &[master, w] : line)
            value += w * enthalpy_ghosted[master];
          h[i]     = value;
          state[i] = owned_node_law(i).state_of_enthalpy(value);
        }
    to_ghosted(enthalpy, enthalpy_ghosted);
    to_ghosted(phase_state, phase_state_ghosted);
  }



  template <int dim>
  void ThermalField<dim>::check_condensed_mass() const
  {
    if (!have_thermal_mortar)
      return;
    std::string problem;
    for (const auto dof : owned)
      if (!hanging_node_constraints.is_constrained(dof) && !(lumped_mass[dof] > 0))
        {
          const Point<dim> &x = support_points.at(dof);
          problem             = "the lumped mass of the node at (" + std::to_string(x[0]) + ", " +
                    std::to_string(x[1]) + ") is " + std::to_string(lumped_mass[dof]) +
                    " after the slave nodes of the mortar interfaces handed theirs to their "
                    "masters (negative dual weights where a slave side is much coarser than "
                    "its master): make the finer side the slave ('Mortar slave = finer')";
          break;
        }
    throw_collectively<std::runtime_error>(problem, mpi_communicator);
  }



  template void ThermalField<2>::make_node_constraints();
  template void ThermalField<2>::check_condensed_mass() const;
  template void ThermalField<2>::interpolate_mortar_slave_enthalpies();
  template void ThermalField<2>::set_mortar_slave_laws();
  template void             ThermalField<2>::couple_mortar_conductances(IndexSet &);
  template ConductanceState ThermalField<2>::mortar_conductance_state(const MortarConductanceNode &,
                                                                      const Vector &) const;
} // namespace ContactStefan
