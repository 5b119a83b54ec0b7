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

#include "pieces.h"

namespace ContactStefan
{
  using namespace MechanicalFieldPieces;

  namespace
  {
    // One side of a mortar interface: its faces as a polyline, and each
    // node's displacement DoFs and vertex.
    struct MortarSide
    {
      Mortar::Side                              side;
      std::vector<std::array<std::uint64_t, 2>> dofs;
      std::vector<unsigned int>                 vertex;
      std::map<unsigned int, unsigned int>      node_of_vertex;
    };
  } // namespace



  template <int dim>
  std::vector<NormalCondition> MechanicalField<dim>::mortar_conditions()
  {
    using Law = Parameters::InterfacePair;
    std::vector<NormalCondition> result;
    mortar_summary.clear();
    for (const auto &[pair, law] : prm.interface_pairs)
      {
        if (law.discretisation != Law::Discretisation::mortar)
          continue;
        const std::string path = "Contact/" + Law::section(pair.first, pair.second) + "/";
        if (Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
          throw InputError(path + "Discretisation",
                           "'mortar' runs on one MPI rank so far (the interface segments are "
                           "not exchanged between ranks): run it without mpirun");
        const std::array<unsigned int, 2> body{{pair.first, pair.second}};
        std::array<MortarSide, 2>         sides;
        for (const auto &cell : dof_handler.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned int face : cell->face_indices())
              if (cell->face(face)->at_boundary())
                for (unsigned int s = 0; s < 2; ++s)
                  if (cell->material_id() == body[s] &&
                      cell->face(face)->boundary_id() == law.mortar_boundaries[s])
                    {
                      MortarSide                 &side = sides[s];
                      const auto                  dofs = vertex_dofs<dim>(cell);
                      std::array<unsigned int, 2> edge;
                      for (unsigned int fv = 0; fv < 2; ++fv)
                        {
                          const unsigned int v = GeometryInfo<dim>::face_to_cell_vertices(face, fv);
                          const unsigned int index = cell->vertex_index(v);
                          const auto [it, inserted] =
                            side.node_of_vertex.emplace(index, side.side.nodes.size());
                          if (inserted)
                            {
                              side.side.nodes.push_back({{cell->vertex(v)[0], cell->vertex(v)[1]}});
                              side.dofs.push_back({{dofs[v][0], dofs[v][1]}});
                              side.vertex.push_back(index);
                              for (unsigned int d = 0; d < dim; ++d)
                                if (hanging_node_constraints.is_constrained(dofs[v][d]))
                                  throw InputError(
                                    path + "Discretisation",
                                    "the mesh has a hanging node on a side of the mortar "
                                    "interface, at (" +
                                      std::to_string(cell->vertex(v)[0]) + ", " +
                                      std::to_string(cell->vertex(v)[1]) +
                                      "): refine the cells along each side alike (adaptive "
                                      "refinement along a mortar side is not supported yet)");
                            }
                          edge[fv] = it->second;
                        }
                      side.side.edges.push_back(edge);
                      side.side.inside.push_back({{cell->center()[0], cell->center()[1]}});
                    }
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
        mortar_summary[group] = {body[slave], coupling.n_segments, coupling.uncovered_length};
        for (unsigned int j = 0; j < S.side.nodes.size(); ++j)
          {
            const Mortar::SlaveNode &node = coupling.slave[j];
            // A slave node that no master edge faces (beyond the end of the
            // master side) has no condition.
            if (!(node.D > 1e-10 * node.edge_length))
              continue;
            NormalCondition c;
            c.kind        = NormalCondition::Kind::interface;
            c.group       = group;
            c.body_k      = pair.first;
            c.body_l      = pair.second;
            c.tied        = false;
            c.boundary_id = 0;
            c.position    = Point<2>(S.side.nodes[j][0], S.side.nodes[j][1]);
            c.vertex      = S.vertex[j];
            c.dofs_k      = S.dofs[j];
            c.has_partner = false;
            c.normal      = node.normal;
            c.weight      = node.D;
            c.corner      = node.max_deviation > contact_prm.corner_angle * numbers::PI / 180;
            c.mortar      = true;
            c.mortar_gap  = node.gap / node.D;
            for (const auto &[m, value] : node.M)
              c.masters.emplace_back(M.dofs[m], value / node.D);
            result.push_back(c);
          }
      }
    return result;
  }



  template std::vector<NormalCondition> MechanicalField<2>::mortar_conditions();
} // namespace ContactStefan
