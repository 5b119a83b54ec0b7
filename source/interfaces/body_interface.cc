// The geometry of the places where two bodies meet (interfaces/body_interface.h).
#include <deal.II/base/geometry_info.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/numbers.h>

#include <contact-stefan/interfaces/body_interface.h>
#include <contact-stefan/interfaces/contact.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace ContactStefan
{
  template <int dim>
  std::vector<BodyInterface<dim>> find_body_interfaces(const Triangulation<dim> &triangulation,
                                                       const double              corner_angle,
                                                       std::string              &problem)
  {
    static_assert(dim == 2, "body interfaces are two-dimensional (faces are segments)");
    using Cell = typename BodyInterface<dim>::Cell;
    std::vector<bool> vertex_of_owned_cell(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          vertex_of_owned_cell[cell->vertex_index(v)] = true;

    struct Accumulated
    {
      typename BodyInterface<dim>::Vertex vertex;
      Contact::NormalAccumulator          normals;
    };
    std::map<std::pair<unsigned int, unsigned int>, BodyInterface<dim>> interfaces;
    std::map<std::pair<unsigned int, unsigned int>, std::map<unsigned int, Accumulated>> points;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned int face : cell->face_indices())
          {
            if (cell->face(face)->at_boundary())
              continue;
            const Cell neighbor = cell->neighbor(face);
            if (neighbor->is_artificial() || neighbor->material_id() == cell->material_id())
              continue;
            if (cell->neighbor(face)->has_children() || neighbor->level() != cell->level())
              throw std::runtime_error(
                "the interface between bodies " + std::to_string(cell->material_id()) + " and " +
                std::to_string(neighbor->material_id()) +
                " is not conforming (refined differently on its two sides)");
            if (cell->material_id() > neighbor->material_id())
              continue; // each face once, from side k
            const std::pair<unsigned int, unsigned int> pair(cell->material_id(),
                                                             neighbor->material_id());
            BodyInterface<dim> &interface = interfaces[pair];
            interface.body_k              = pair.first;
            interface.body_l              = pair.second;
            interface.faces.push_back({cell, neighbor, face, cell->neighbor_of_neighbor(face)});

            const auto a = cell->face(face)->vertex(0);
            const auto b = cell->face(face)->vertex(1);
            const auto c = cell->center();
            for (unsigned int fv = 0; fv < 2; ++fv)
              {
                const unsigned int v     = GeometryInfo<dim>::face_to_cell_vertices(face, fv);
                const unsigned int index = cell->vertex_index(v);
                if (!vertex_of_owned_cell[index])
                  continue;
                Accumulated &p    = points[pair][index];
                p.vertex.index    = index;
                p.vertex.position = cell->vertex(v);
                p.vertex.cell_k   = cell;
                p.vertex.vertex_k = v;
                p.vertex.cell_l   = neighbor;
                for (const unsigned int w : neighbor->vertex_indices())
                  if (neighbor->vertex_index(w) == index)
                    p.vertex.vertex_l = w;
                p.normals.add_face({{a[0], a[1]}}, {{b[0], b[1]}}, {{c[0], c[1]}});
              }
          }

    std::vector<BodyInterface<dim>> result;
    for (auto &[pair, interface] : interfaces)
      {
        for (auto &[index, p] : points[pair])
          {
            try
              {
                const auto n    = p.normals.normal();
                p.vertex.normal = {{n[0], n[1]}};
              }
            catch (const std::exception &error)
              {
                if (problem.empty())
                  problem = "at (" + std::to_string(p.vertex.position[0]) + ", " +
                            std::to_string(p.vertex.position[1]) + ") of " + interface.name() +
                            ": " + error.what();
                continue;
              }
            p.vertex.weight = p.normals.weight();
            p.vertex.corner = p.normals.max_deviation() > corner_angle * numbers::PI / 180;
            interface.vertices.push_back(p.vertex);
          }
        result.push_back(std::move(interface));
      }
    return result;
  }



  template <int dim>
  std::vector<bool> two_sided_vertices(
    const Triangulation<dim>                                                         &triangulation,
    const std::map<std::pair<unsigned int, unsigned int>, Parameters::InterfacePair> &pairs,
    const bool conductance_only)
  {
    using ThermalContact = Parameters::InterfacePair::ThermalContact;
    const auto counts    = [&](const unsigned int a, const unsigned int b) {
      if (!conductance_only)
        return true;
      const auto it = pairs.find({std::min(a, b), std::max(a, b)});
      return it != pairs.end() && it->second.thermal_contact == ThermalContact::conductance;
    };
    const auto                      none = numbers::invalid_material_id;
    std::vector<types::material_id> body(triangulation.n_vertices(), none);
    std::vector<bool>               two_sided(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      if (!cell->is_artificial())
        {
          for (const unsigned int v : cell->vertex_indices())
            {
              auto &first = body[cell->vertex_index(v)];
              if (first == none)
                first = cell->material_id();
              else if (first != cell->material_id() && counts(first, cell->material_id()))
                two_sided[cell->vertex_index(v)] = true;
            }
          for (const unsigned int f : cell->face_indices())
            if (cell->face(f)->at_boundary())
              for (const auto &[pair, law] : pairs)
                if (law.discretisation == Parameters::InterfacePair::Discretisation::mortar &&
                    (!conductance_only || law.thermal_contact == ThermalContact::conductance) &&
                    ((cell->material_id() == pair.first &&
                      cell->face(f)->boundary_id() == law.mortar_boundaries[0]) ||
                     (cell->material_id() == pair.second &&
                      cell->face(f)->boundary_id() == law.mortar_boundaries[1])))
                  for (const unsigned int v : cell->face(f)->vertex_indices())
                    two_sided[cell->face(f)->vertex_index(v)] = true;
        }
    return two_sided;
  }



  template <int dim>
  bool jumps_at(const Function<dim>      &f,
                const Triangulation<dim> &triangulation,
                const std::vector<bool>  &two_sided)
  {
    double largest_change = 0, largest_value = 0;
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          {
            const double at = f.value(cell->vertex(v));
            largest_value   = std::max(largest_value, std::abs(at));
            if (two_sided[cell->vertex_index(v)])
              {
                // Just inside the cell and just outside it, across the
                // vertex: on either side of the interface whatever the
                // rounding of the vertex (a mortar side's vertex belongs to
                // one body only, so comparing with the vertex would not do).
                const Point<dim> x = cell->vertex(v), c = cell->center();
                const double     inside = f.value(x + interface_side_offset * (c - x)),
                             outside    = f.value(x - interface_side_offset * (c - x));
                largest_change          = std::max(largest_change, std::abs(inside - outside));
                largest_value = std::max({largest_value, std::abs(inside), std::abs(outside)});
              }
          }
    const MPI_Comm comm = triangulation.get_communicator();
    return Utilities::MPI::max(largest_change, comm) >
           1e-8 * Utilities::MPI::max(largest_value, comm);
  }



  template std::vector<BodyInterface<2>>
  find_body_interfaces<2>(const Triangulation<2> &, const double, std::string &);
  template std::vector<bool> two_sided_vertices<2>(
    const Triangulation<2> &,
    const std::map<std::pair<unsigned int, unsigned int>, Parameters::InterfacePair> &,
    const bool);
  template bool
  jumps_at<2>(const Function<2> &, const Triangulation<2> &, const std::vector<bool> &);
} // namespace ContactStefan
