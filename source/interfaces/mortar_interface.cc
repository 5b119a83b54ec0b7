// The mortar interfaces of the mesh, gathered and coupled (doc/contact.md,
// "Non-matching interfaces"). Every rank builds the whole coupling of an
// interface from the faces of all ranks: in 2D an interface has a few
// thousand faces at most, and the exchange and the O(slave edges x master
// edges) pairing are small against a solve.
#include <deal.II/base/mpi.h>

#include <contact-stefan/core/checked_input.h>
#include <contact-stefan/interfaces/mortar_interface.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

namespace ContactStefan
{
  namespace
  {
    // One face of a side, as every rank receives it: its two nodes
    // (positions where the side is coupled, mesh positions X, and DoFs) and
    // its cell's centre (moved with the face's mean displacement).
    struct MortarFace
    {
      std::array<Mortar::Vector2, 2>                      x, X;
      Mortar::Vector2                                     inside_on_mesh;
      std::array<std::vector<types::global_dof_index>, 2> dofs;
      Mortar::Vector2                                     inside;
    };

    // The faces of one side from all ranks, in an order that does not depend
    // on the partition or on the displacement (by the midpoint of the mesh
    // positions, then by the ends), as a polyline whose nodes are numbered in
    // that order; a node is known by its first DoF. With 'deformed' the side's
    // nodes are the faces' x and its reference the mesh positions X.
    void gather_side(const std::vector<MortarFace>                     &own,
                     const unsigned int                                 n_dofs,
                     const MPI_Comm                                     comm,
                     const bool                                         deformed,
                     Mortar::Side                                      &side,
                     std::vector<Mortar::Vector2>                      &inside_on_mesh,
                     std::vector<std::vector<types::global_dof_index>> &node_dofs)
    {
      // Flattened: 12 coordinates and 2 n_dofs DoFs per face.
      constexpr unsigned int               n_coordinates = 12;
      std::vector<double>                  coordinates;
      std::vector<types::global_dof_index> dofs;
      for (const MortarFace &f : own)
        {
          coordinates.insert(coordinates.end(),
                             {f.x[0][0],
                              f.x[0][1],
                              f.x[1][0],
                              f.x[1][1],
                              f.X[0][0],
                              f.X[0][1],
                              f.X[1][0],
                              f.X[1][1],
                              f.inside[0],
                              f.inside[1],
                              f.inside_on_mesh[0],
                              f.inside_on_mesh[1]});
          for (const auto &d : f.dofs)
            dofs.insert(dofs.end(), d.begin(), d.end());
        }
      std::vector<MortarFace> faces;
      const auto              all_coordinates = Utilities::MPI::all_gather(comm, coordinates);
      const auto              all_dofs        = Utilities::MPI::all_gather(comm, dofs);
      for (unsigned int r = 0; r < all_coordinates.size(); ++r)
        for (unsigned int f = 0; n_coordinates * f < all_coordinates[r].size(); ++f)
          {
            const double                  *c = &all_coordinates[r][n_coordinates * f];
            const types::global_dof_index *d = &all_dofs[r][2 * n_dofs * f];
            MortarFace                     face;
            face.x      = {{{{c[0], c[1]}}, {{c[2], c[3]}}}};
            face.X              = {{{{c[4], c[5]}}, {{c[6], c[7]}}}};
            face.inside         = {{c[8], c[9]}};
            face.inside_on_mesh = {{c[10], c[11]}};
            face.dofs   = {{std::vector<types::global_dof_index>(d, d + n_dofs),
                            std::vector<types::global_dof_index>(d + n_dofs, d + 2 * n_dofs)}};
            faces.push_back(std::move(face));
          }
      std::sort(faces.begin(), faces.end(), [](const MortarFace &a, const MortarFace &b) {
        const auto key = [](const MortarFace &f) {
          return std::make_tuple(f.X[0][0] + f.X[1][0],
                                 f.X[0][1] + f.X[1][1],
                                 f.X[0][0],
                                 f.X[0][1]);
        };
        return key(a) < key(b);
      });
      std::map<types::global_dof_index, unsigned int> node_of_dof;
      for (const MortarFace &f : faces)
        {
          std::array<unsigned int, 2> edge;
          for (unsigned int v = 0; v < 2; ++v)
            {
              const auto [it, inserted] = node_of_dof.emplace(f.dofs[v][0], side.nodes.size());
              if (inserted)
                {
                  side.nodes.push_back(f.x[v]);
                  if (deformed)
                    side.reference.push_back(f.X[v]);
                  node_dofs.push_back(f.dofs[v]);
                }
              edge[v] = it->second;
            }
          side.edges.push_back(edge);
          side.inside.push_back(f.inside);
          inside_on_mesh.push_back(f.inside_on_mesh);
        }
    }

    // The DoFs of vertex v of a cell, by component: a Q1 element (or a
    // system of Q1 and FE_Nothing) has one DoF per component at each vertex.
    template <int dim>
    std::vector<types::global_dof_index>
    node_dofs(const typename DoFHandler<dim>::active_cell_iterator &cell, const unsigned int v)
    {
      const auto                          &fe = cell->get_fe();
      std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
      cell->get_dof_indices(dofs);
      std::vector<std::pair<unsigned int, types::global_dof_index>> at_vertex;
      for (unsigned int i = 0; i < fe.n_dofs_per_cell(); ++i)
        if (fe.system_to_component_index(i).second == v)
          at_vertex.emplace_back(fe.system_to_component_index(i).first, dofs[i]);
      std::sort(at_vertex.begin(), at_vertex.end());
      std::vector<types::global_dof_index> result;
      for (const auto &[component, dof] : at_vertex)
        result.push_back(dof);
      return result;
    }
  } // namespace



  template <int dim>
  MortarInterface couple_mortar_interface(const DoFHandler<dim>                       &dof_handler,
                                          const std::pair<unsigned int, unsigned int> &pair,
                                          const Parameters::InterfacePair             &law,
                                          const MortarConfiguration *configuration)
  {
    using Law              = Parameters::InterfacePair;
    const std::string path = "Contact/" + Law::section(pair.first, pair.second) + "/";
    MortarInterface   mi;
    mi.name = "interface " + std::to_string(pair.first) + "-" + std::to_string(pair.second);
    mi.body = {{pair.first, pair.second}};
    // (Decided by all ranks together: a rank that owns no cell of a side has
    // no displacement to give, but gathers the moved sides like the others.)
    const MPI_Comm comm = dof_handler.get_triangulation().get_communicator();
    mi.deformed         = law.mortar_large_sliding && configuration &&
                  Utilities::MPI::logical_or(!configuration->displacement.empty(), comm);
    std::array<std::vector<MortarFace>, 2> own;
    unsigned int                           n_dofs = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int face : cell->face_indices())
          if (cell->face(face)->at_boundary())
            for (unsigned int s = 0; s < 2; ++s)
              if (cell->material_id() == mi.body[s] &&
                  cell->face(face)->boundary_id() == law.mortar_boundaries[s])
                {
                  MortarFace f;
                  // With large sliding: where the configuration moved the node.
                  Mortar::Vector2 mean_displacement{{0., 0.}};
                  for (unsigned int fv = 0; fv < 2; ++fv)
                    {
                      const unsigned int v = GeometryInfo<dim>::face_to_cell_vertices(face, fv);
                      f.X[fv]              = {{cell->vertex(v)[0], cell->vertex(v)[1]}};
                      f.x[fv]              = f.X[fv];
                      if (mi.deformed)
                        {
                          const auto it =
                            configuration->displacement.find({mi.body[s], f.X[fv][0], f.X[fv][1]});
                          if (it == configuration->displacement.end())
                            throw std::logic_error("the sliding configuration of " + mi.name +
                                                   " has no displacement of the node at (" +
                                                   std::to_string(f.X[fv][0]) + ", " +
                                                   std::to_string(f.X[fv][1]) + ")");
                          for (unsigned int i = 0; i < 2; ++i)
                            {
                              f.x[fv][i] += it->second[i];
                              mean_displacement[i] += 0.5 * it->second[i];
                            }
                        }
                      f.dofs[fv] = node_dofs<dim>(cell, v);
                      n_dofs     = f.dofs[fv].size();
                    }
                  f.inside_on_mesh = {{cell->center()[0], cell->center()[1]}};
                  f.inside         = {{cell->center()[0] + mean_displacement[0],
                                       cell->center()[1] + mean_displacement[1]}};
                  own[s].push_back(f);
                }
    n_dofs = Utilities::MPI::max(n_dofs, comm);
    for (unsigned int s = 0; s < 2; ++s)
      gather_side(own[s], n_dofs, comm, mi.deformed, mi.sides[s], mi.inside_on_mesh[s], mi.dofs[s]);

    // The slave side: 'finer' takes the shorter mean edge (k if equal), on
    // the mesh (a deformation must not swap the sides).
    const auto on_mesh = [](const Mortar::Side &side) {
      Mortar::Side mesh_side = side;
      if (!side.reference.empty())
        mesh_side.nodes = side.reference;
      return mesh_side;
    };
    const double h_k = Mortar::mean_edge_length(on_mesh(mi.sides[0])),
                 h_l = Mortar::mean_edge_length(on_mesh(mi.sides[1]));
    mi.slave         = law.mortar_slave == Law::MortarSlave::k ? 0 :
                       law.mortar_slave == Law::MortarSlave::l ? 1 :
                                                                 (h_l < h_k ? 1 : 0);
    Mortar::Parameters parameters;
    parameters.search_distance = law.mortar_search_distance;
    if (!(parameters.search_distance > 0))
      for (const Mortar::Side &side : mi.sides)
        for (const auto &e : side.edges)
          parameters.search_distance =
            std::max(parameters.search_distance,
                     std::hypot(side.nodes[e[1]][0] - side.nodes[e[0]][0],
                                side.nodes[e[1]][1] - side.nodes[e[0]][1]));
    mi.search_distance = parameters.search_distance;
    try
      {
        mi.coupling = Mortar::couple(mi.sides[mi.slave], mi.sides[1 - mi.slave], parameters);
      }
    catch (const std::exception &e)
      {
        throw InputError(path + "Mortar boundaries", e.what());
      }

    // A slave node that the master side covers to less than 'Mortar minimum
    // coverage' of its support (beyond or at the end of the master side) has
    // no condition: the dual basis of a barely covered edge extrapolates.
    for (const Mortar::SlaveNode &node : mi.coupling.slave)
      {
        const bool c = node.D > 1e-10 * node.edge_length &&
                       node.D >= law.mortar_min_coverage * 0.5 * node.edge_length;
        mi.conditioned.push_back(c);
        if (!c)
          continue;
        ++mi.n_conditions;
        double sum = 0;
        for (const auto &[m, value] : node.M)
          sum += value / node.D;
        mi.weight_defect = std::max(mi.weight_defect, std::abs(1 - sum));
      }
    const unsigned int s = mi.slave;
    if (mi.n_conditions == 0 && mi.deformed)
      throw InputError(path + "Mortar sliding",
                       "after the displacement moved the sides, no node of body " +
                         std::to_string(mi.body[s]) + "'s side faces body " +
                         std::to_string(mi.body[1 - s]) + "'s side within " +
                         std::to_string(parameters.search_distance) +
                         " m: one body has slid off the other (or lifted off it by more than "
                         "'Mortar search distance')");
    if (mi.n_conditions == 0)
      throw InputError(path + "Mortar boundaries",
                       "no node of body " + std::to_string(mi.body[s]) + "'s side (id " +
                         std::to_string(law.mortar_boundaries[s]) + ", " +
                         std::to_string(mi.sides[s].edges.size()) + " faces) faces body " +
                         std::to_string(mi.body[1 - s]) + "'s side (id " +
                         std::to_string(law.mortar_boundaries[1 - s]) + ", " +
                         std::to_string(mi.sides[1 - s].edges.size()) +
                         " faces) within the search distance " +
                         std::to_string(parameters.search_distance) +
                         " m: check the ids and 'Mortar search distance'");
    return mi;
  }



  template MortarInterface couple_mortar_interface<2>(const DoFHandler<2> &,
                                                      const std::pair<unsigned int, unsigned int> &,
                                                      const Parameters::InterfacePair &,
                                                      const MortarConfiguration *);
} // namespace ContactStefan
