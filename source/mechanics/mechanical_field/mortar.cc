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
#include <contact-stefan/interfaces/mortar.h>
#include <contact-stefan/mechanics/mechanical_field.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "pieces.h"

namespace ContactStefan
{
  using namespace MechanicalFieldPieces;

  namespace
  {
    // One face of a side of a mortar interface, as every rank receives it:
    // its two nodes (positions and x, y DoFs) and its cell's centre.
    struct MortarFace
    {
      std::array<Mortar::Vector2, 2>              x;
      std::array<std::array<std::uint64_t, 2>, 2> dofs;
      Mortar::Vector2                             inside;
    };

    // One side of a mortar interface: its faces as a polyline, and each
    // node's displacement DoFs.
    struct MortarSide
    {
      Mortar::Side                              side;
      std::vector<std::array<std::uint64_t, 2>> dofs;
    };

    // The faces of both sides of one interface from all ranks, in an order
    // that does not depend on the partition (by midpoint, then by the ends),
    // as polylines whose nodes are numbered in that order.
    std::array<MortarSide, 2> gather_sides(const std::array<std::vector<MortarFace>, 2> &own,
                                           const MPI_Comm                                comm)
    {
      std::array<MortarSide, 2> sides;
      for (unsigned int s = 0; s < 2; ++s)
        {
          // Flattened: 6 coordinates and 4 DoFs per face.
          std::vector<double>        coordinates;
          std::vector<std::uint64_t> dofs;
          for (const MortarFace &f : own[s])
            {
              coordinates.insert(
                coordinates.end(),
                {f.x[0][0], f.x[0][1], f.x[1][0], f.x[1][1], f.inside[0], f.inside[1]});
              dofs.insert(dofs.end(), {f.dofs[0][0], f.dofs[0][1], f.dofs[1][0], f.dofs[1][1]});
            }
          std::vector<MortarFace> faces;
          const auto              all_coordinates = Utilities::MPI::all_gather(comm, coordinates);
          const auto              all_dofs        = Utilities::MPI::all_gather(comm, dofs);
          for (unsigned int r = 0; r < all_coordinates.size(); ++r)
            for (unsigned int f = 0; 6 * f < all_coordinates[r].size(); ++f)
              {
                const double        *c = &all_coordinates[r][6 * f];
                const std::uint64_t *d = &all_dofs[r][4 * f];
                faces.push_back({{{{{c[0], c[1]}}, {{c[2], c[3]}}}},
                                 {{{{d[0], d[1]}}, {{d[2], d[3]}}}},
                                 {{c[4], c[5]}}});
              }
          std::sort(faces.begin(), faces.end(), [](const MortarFace &a, const MortarFace &b) {
            const auto key = [](const MortarFace &f) {
              return std::make_tuple(f.x[0][0] + f.x[1][0],
                                     f.x[0][1] + f.x[1][1],
                                     f.x[0][0],
                                     f.x[0][1]);
            };
            return key(a) < key(b);
          });
          std::map<std::uint64_t, unsigned int> node_of_dof;
          for (const MortarFace &f : faces)
            {
              std::array<unsigned int, 2> edge;
              for (unsigned int v = 0; v < 2; ++v)
                {
                  const auto [it, inserted] =
                    node_of_dof.emplace(f.dofs[v][0], sides[s].side.nodes.size());
                  if (inserted)
                    {
                      sides[s].side.nodes.push_back(f.x[v]);
                      sides[s].dofs.push_back(f.dofs[v]);
                    }
                  edge[v] = it->second;
                }
              sides[s].side.edges.push_back(edge);
              sides[s].side.inside.push_back(f.inside);
            }
        }
      return sides;
    }
  } // namespace



  // Every rank builds the whole coupling of each mortar interface from the
  // faces of all ranks (in 2D an interface has a few thousand faces at most:
  // the exchange and the O(slave edges x master edges) pairing are small
  // against a contact step, doc/contact.md) and keeps the conditions of the
  // slave nodes whose DoFs it sees. Their master nodes' DoFs join the locally
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
        const std::string path = "Contact/" + Law::section(pair.first, pair.second) + "/";
        const std::array<unsigned int, 2> body{{pair.first, pair.second}};
        std::array<std::vector<MortarFace>, 2> own;
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned int face : cell->face_indices())
              if (cell->face(face)->at_boundary())
                for (unsigned int s = 0; s < 2; ++s)
                  if (cell->material_id() == body[s] &&
                      cell->face(face)->boundary_id() == law.mortar_boundaries[s])
                    {
                      const auto dofs = vertex_dofs<dim>(cell);
                      MortarFace f;
                      for (unsigned int fv = 0; fv < 2; ++fv)
                        {
                          const unsigned int v = GeometryInfo<dim>::face_to_cell_vertices(face, fv);
                          f.x[fv]              = {{cell->vertex(v)[0], cell->vertex(v)[1]}};
                          f.dofs[fv]           = {{dofs[v][0], dofs[v][1]}};
                        }
                      f.inside = {{cell->center()[0], cell->center()[1]}};
                      own[s].push_back(f);
                    }
        const std::array<MortarSide, 2> sides = gather_sides(own, mpi_communicator);
        // The slave side: 'finer' takes the shorter mean edge (k if equal).
        const double h_k         = Mortar::mean_edge_length(sides[0].side),
                     h_l         = Mortar::mean_edge_length(sides[1].side);
        const unsigned int slave = law.mortar_slave == Law::MortarSlave::k ? 0 :
                                   law.mortar_slave == Law::MortarSlave::l ? 1 :
                                                                             (h_l < h_k ? 1 : 0);
        const MortarSide  &S = sides[slave], &M = sides[1 - slave];
        Mortar::Parameters parameters;
        parameters.search_distance = law.mortar_search_distance;
        if (!(parameters.search_distance > 0))
          for (const MortarSide *side : {&S, &M})
            for (const auto &e : side->side.edges)
              parameters.search_distance =
                std::max(parameters.search_distance,
                         std::hypot(side->side.nodes[e[1]][0] - side->side.nodes[e[0]][0],
                                    side->side.nodes[e[1]][1] - side->side.nodes[e[0]][1]));
        Mortar::Coupling coupling;
        try
          {
            coupling = Mortar::couple(S.side, M.side, parameters);
          }
        catch (const std::exception &e)
          {
            throw InputError(path + "Mortar boundaries", e.what());
          }
        const std::string group =
          "interface " + std::to_string(pair.first) + "-" + std::to_string(pair.second);
        // A slave node that the master side covers to less than 'Mortar minimum
        // coverage' of its support (beyond or at the end of the master side)
        // has no condition.
        const auto conditioned = [&](const Mortar::SlaveNode &node) {
          return node.D > 1e-10 * node.edge_length &&
                 node.D >= law.mortar_min_coverage * 0.5 * node.edge_length;
        };
        const auto n_conditions =
          std::count_if(coupling.slave.begin(), coupling.slave.end(), conditioned);
        if (n_conditions == 0)
          throw InputError(path + "Mortar boundaries",
                           "no node of body " + std::to_string(body[slave]) + "'s side (id " +
                             std::to_string(law.mortar_boundaries[slave]) + ", " +
                             std::to_string(S.side.edges.size()) + " faces) faces body " +
                             std::to_string(body[1 - slave]) + "'s side (id " +
                             std::to_string(law.mortar_boundaries[1 - slave]) + ", " +
                             std::to_string(M.side.edges.size()) +
                             " faces) within the search distance " +
                             std::to_string(parameters.search_distance) +
                             " m: check the ids and 'Mortar search distance'");
        double weight_defect = 0;
        for (const Mortar::SlaveNode &node : coupling.slave)
          if (conditioned(node))
            {
              double sum = 0;
              for (const auto &[m, value] : node.M)
                sum += value / node.D;
              weight_defect = std::max(weight_defect, std::abs(1 - sum));
            }
        mortar_summary[group] = {body[slave],
                                 coupling.n_segments,
                                 coupling.uncovered_length,
                                 static_cast<unsigned int>(n_conditions),
                                 weight_defect};
        for (unsigned int j = 0; j < S.side.nodes.size(); ++j)
          {
            const Mortar::SlaveNode &node = coupling.slave[j];
            // (Only the nodes this rank sees.)
            if (!conditioned(node) || !relevant.is_element(S.dofs[j][0]))
              continue;
            NormalCondition c;
            c.kind        = NormalCondition::Kind::interface;
            c.group       = group;
            c.body_k      = pair.first;
            c.body_l      = pair.second;
            c.tied        = false;
            c.boundary_id = 0;
            c.position    = Point<2>(S.side.nodes[j][0], S.side.nodes[j][1]);
            c.vertex      = numbers::invalid_unsigned_int;
            c.dofs_k      = S.dofs[j];
            c.has_partner = false;
            c.normal      = node.normal;
            c.weight      = node.D;
            c.corner      = node.max_deviation > contact_prm.corner_angle * numbers::PI / 180;
            c.mortar      = true;
            c.mortar_gap  = node.gap / node.D;
            for (const auto &[m, value] : node.M)
              {
                c.masters.emplace_back(M.dofs[m], value / node.D);
                masters.add_indices(M.dofs[m].begin(), M.dofs[m].end());
              }
            mortar_cache.push_back(c);
          }
      }
    relevant.add_indices(masters);
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
  template void MechanicalField<2>::check_mortar_junctions() const;
} // namespace ContactStefan
