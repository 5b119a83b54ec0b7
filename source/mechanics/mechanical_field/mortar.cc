// The normal conditions of the mortar interfaces (Contact/Interface k-l/
// Discretisation = mortar, doc/contact.md): the two sides are the boundary
// faces of body k and body l that carry the interface's two 'Mortar
// boundaries' ids; the dual mortar integrals of interfaces/mortar.h turn them
// into one condition per slave node,
//   n_j.(u_j - sum_m (M_jm / D_j) u_m) <= g(x_j) + gtilde_j / D_j,
// which the contact step imposes, tests and reports like a node-to-node
// condition: the active set lives in AffineConstraints (one line per active
// slave node, naming the master nodes' DoFs), the multiplier is read off the
// residual at the slave node (the force D_j lambda_j n_j, so that the
// reported pressure is lambda_j), and the master side takes the opposite
// forces through the condensation.
#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/interfaces/mortar_interface.h>
#include <contact-stefan/mechanics/mechanical_field.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "pieces.h"

namespace ContactStefan
{
  using namespace MechanicalFieldPieces;

  // Every rank builds the whole coupling of each mortar interface
  // (interfaces/mortar_interface.h) and keeps the conditions of the slave
  // nodes whose DoFs it sees. Their master nodes' DoFs join the locally
  // relevant set: the constraint lines name them and the gap reads them.
  template <int dim>
  void MechanicalField<dim>::couple_mortar_interfaces()
  {
    using Law = Parameters::InterfacePair;
    mortar_cache.clear();
    mortar_summary.clear();
    IndexSet masters(dof_handler.n_dofs());
    for (const auto &[pair, law] : prm.interface_pairs)
      {
        if (law.discretisation != Law::Discretisation::mortar)
          continue;
        const MortarInterface mi =
          couple_mortar_interface<dim>(dof_handler, pair, law, mortar_configuration);
        // The shortest edge at each master node, on the mesh: the unit in
        // which a step's slide is measured (CoupledProblem::
        // follow_sliding_interfaces()).
        const unsigned int  master = 1 - mi.slave;
        std::vector<double> edge_at(mi.sides[master].nodes.size(), HUGE_VAL);
        for (const auto &e : mi.sides[master].edges)
          {
            const double length =
              mi.mesh_position(master, e[0]).distance(mi.mesh_position(master, e[1]));
            edge_at[e[0]] = std::min(edge_at[e[0]], length);
            edge_at[e[1]] = std::min(edge_at[e[1]], length);
          }
        mortar_summary[mi.name] = {mi.body[mi.slave],
                                   mi.coupling.n_segments,
                                   mi.coupling.uncovered_length,
                                   mi.n_conditions,
                                   mi.weight_defect,
                                   law.mortar_large_sliding};
        const Mortar::Side &S   = mi.slave_side();
        for (unsigned int j = 0; j < S.nodes.size(); ++j)
          {
            const Mortar::SlaveNode &node = mi.coupling.slave[j];
            // (Only the nodes this rank sees.)
            if (!mi.conditioned[j] || !relevant.is_element(mi.slave_dofs()[j][0]))
              continue;
            NormalCondition c;
            c.kind        = NormalCondition::Kind::interface;
            c.group       = mi.name;
            c.body_k      = pair.first;
            c.body_l      = pair.second;
            c.tied        = false;
            c.boundary_id = 0;
            c.position    = mi.slave_position(j);
            c.vertex      = numbers::invalid_unsigned_int;
            c.dofs_k      = {{mi.slave_dofs()[j][0], mi.slave_dofs()[j][1]}};
            c.has_partner = false;
            c.normal      = node.normal;
            c.weight      = node.D;
            c.corner      = node.max_deviation > contact_prm.corner_angle * numbers::PI / 180;
            c.mortar      = true;
            c.mortar_gap  = node.gap / node.D;
            c.mortar_node = j;
            c.facing      = mi.deformed ? Point<2>() : c.position;
            c.facing_edge = HUGE_VAL;
            for (const auto &[m, value] : node.M)
              {
                c.facing_edge = std::min(c.facing_edge, edge_at[m]);
                if (mi.deformed)
                  c.facing += (value / node.D) * mi.mesh_position(1 - mi.slave, m);
                const auto &dofs = mi.master_dofs()[m];
                c.masters.emplace_back(std::array<std::uint64_t, 2>{{dofs[0], dofs[1]}},
                                       value / node.D);
                masters.add_indices(dofs.begin(), dofs.end());
              }
            mortar_cache.push_back(c);
          }
      }
    relevant.add_indices(masters);
  }



  template <int dim>
  bool MechanicalField<dim>::large_sliding() const
  {
    for (const auto &[pair, law] : prm.interface_pairs)
      if (law.discretisation == Parameters::InterfacePair::Discretisation::mortar &&
          law.mortar_large_sliding)
        return true;
    return false;
  }



  // The configuration a large-sliding interface is coupled in: u at the
  // vertices of this rank's cells on its sides (the vertices of owned cells
  // are locally relevant), by body and mesh position, as
  // couple_mortar_interface() looks them up for the faces it gathers.
  template <int dim>
  void MechanicalField<dim>::mortar_side_displacements(MortarConfiguration &configuration) const
  {
    configuration.displacement.clear();
    // From u itself: right after a mesh change the ghosted copy is not made
    // yet (after_transfer() makes it).
    Vector u(owned, relevant, mpi_communicator);
    u = displacement;
    for (const auto &[pair, law] : prm.interface_pairs)
      {
        if (law.discretisation != Parameters::InterfacePair::Discretisation::mortar ||
            !law.mortar_large_sliding)
          continue;
        const std::array<unsigned int, 2> body{{pair.first, pair.second}};
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned int face : cell->face_indices())
              if (cell->face(face)->at_boundary())
                for (unsigned int s = 0; s < 2; ++s)
                  if (cell->material_id() == body[s] &&
                      cell->face(face)->boundary_id() == law.mortar_boundaries[s])
                    {
                      const auto dofs = vertex_dofs<dim>(cell);
                      for (unsigned int fv = 0; fv < GeometryInfo<dim>::vertices_per_face; ++fv)
                        {
                          const unsigned int v = GeometryInfo<dim>::face_to_cell_vertices(face, fv);
                          configuration
                            .displacement[{body[s], cell->vertex(v)[0], cell->vertex(v)[1]}] = {
                            {u[dofs[v][0]], u[dofs[v][1]]}};
                        }
                    }
      }
  }



  // A mortar slave node may carry no other contact condition: where the
  // slave sides of two mortar interfaces meet, or a slave side meets a nodal
  // interface or an obstacle, the second condition would be counted twice or
  // close a cycle of constraints. (A roller there is fine.)
  template <int dim>
  void MechanicalField<dim>::check_mortar_junctions() const
  {
    std::map<types::global_dof_index, std::vector<const NormalCondition *>> at;
    for (const auto &c : normal_conditions)
      if (c.kind != NormalCondition::Kind::roller)
        {
          at[c.dofs_k[0]].push_back(&c);
          if (c.has_partner)
            at[c.dofs_l[0]].push_back(&c);
        }
    std::string problem;
    for (const auto &c : normal_conditions)
      if (c.mortar && problem.empty())
        for (const NormalCondition *other : at[c.dofs_k[0]])
          if (other != &c)
            {
              problem = "parameter 'Contact/" +
                        Parameters::InterfacePair::section(c.body_k, c.body_l) +
                        "/Mortar boundaries': the slave node at (" + std::to_string(c.position[0]) +
                        ", " + std::to_string(c.position[1]) + ") is also on " + other->group +
                        "; a node takes one contact condition: let the sides end apart or "
                        "make that node's other side the slave";
              break;
            }
    throw_collectively<InputError>(problem, mpi_communicator);
  }



  template void MechanicalField<2>::couple_mortar_interfaces();
  template bool MechanicalField<2>::large_sliding() const;
  template void MechanicalField<2>::mortar_side_displacements(MortarConfiguration &) const;
  template void MechanicalField<2>::check_mortar_junctions() const;
} // namespace ContactStefan
