// The conditions of the mechanical field that the mesh decides (doc/contact.md):
// the constraints that do not depend on the contact state (prescribed
// displacements, ties, rollers), and the normal conditions of the contact step
// -- rollers and obstacles from the boundary faces, interfaces from their
// geometry (interfaces/body_interface.h) with each interface's law.
#include <deal.II/base/geometry_info.h>
#include <deal.II/base/function.h>
#include <deal.II/base/mpi.h>

#include <deal.II/numerics/vector_tools.h>

#include <contact-stefan/interfaces/body_interface.h>
#include <contact-stefan/interfaces/contact.h>
#include <contact-stefan/mechanics/mechanical_field.h>

#include "pieces.h"

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

namespace ContactStefan
{
  using namespace MechanicalFieldPieces;

  namespace
  {
    // A two-component function of x, y, t replicated into every body's slot of
    // components (the hp element has n_slots * dim components).
    template <int dim>
    class Replicated : public Function<dim>
    {
    public:
      Replicated(const Function<dim> &f, const unsigned int n_slots)
        : Function<dim>(n_slots * dim)
        , f(f)
      {}
      double value(const Point<dim> &p, const unsigned int component) const override
      {
        return f.value(p, component % dim);
      }

    private:
      const Function<dim> &f;
    };



    // Where two interfaces meet at a vertex, their conditions share the
    // vertex's DoFs and its active flag: that works only for contacts of one
    // gap (a tie beside another condition can close a cycle of constraints,
    // which AffineConstraints::close() would not leave). The first such vertex
    // of this rank, as a message naming the interface's Kind; empty if none.
    template <int dim>
    std::string junction_problem(const SceneParameters                 &prm,
                                 const std::vector<BodyInterface<dim>> &interfaces)
    {
      std::map<unsigned int, std::vector<const BodyInterface<dim> *>> at;
      for (const auto &interface : interfaces)
        {
          const auto &law = prm.interface_pair(interface.body_k, interface.body_l);
          for (const auto &vertex : interface.vertices)
            {
              for (const BodyInterface<dim> *other : at[vertex.index])
                {
                  const auto &other_law = prm.interface_pair(other->body_k, other->body_l);
                  if (law.kind == Parameters::Contact::Interfaces::tied ||
                      other_law.kind != law.kind || other_law.gap != law.gap)
                    return "parameter 'Contact/" +
                           Parameters::InterfacePair::section(interface.body_k, interface.body_l) +
                           "/Kind': the vertex at (" + std::to_string(vertex.position[0]) + ", " +
                           std::to_string(vertex.position[1]) + ") is on " + other->name() +
                           " and " + interface.name() +
                           "; interfaces may meet at a vertex only if both are contacts with "
                           "the same gap (a tie beside another interface would close a cycle "
                           "of constraints)";
                }
              at[vertex.index].push_back(&interface);
            }
        }
      return "";
    }
  } // namespace



  // Constraints that do not depend on the contact state, in order of priority:
  // hanging nodes, prescribed displacements, tied interfaces, rollers. A later
  // condition never overrides an earlier one on the same DoF; a roller or tie
  // whose DoFs are all taken already is dropped (a corner with a displacement
  // condition on both components needs nothing more).
  template <int dim>
  void MechanicalField<dim>::make_fixed_constraints()
  {
    fixed_constraints.clear();
    fixed_constraints.reinit(relevant);
    fixed_constraints.merge(hanging_node_constraints);
    const unsigned int n_slots = prm.body_ids.size();
    for (const auto &[id, bc] : prm.mechanical_boundaries)
      if (bc.type == Parameters::MechanicalBoundary::Type::displacement)
        {
          Function<dim> &f = functions.mechanical_boundary(id);
          f.set_time(time);
          const Replicated<dim> value(f, n_slots);
          std::vector<bool>     mask(n_slots * dim, false);
          for (unsigned int s = 0; s < n_slots; ++s)
            for (unsigned int d = 0; d < dim; ++d)
              mask[s * dim + d] = bc.components[d];
          VectorTools::interpolate_boundary_values(
            dof_handler, id, value, fixed_constraints, ComponentMask(mask));
        }
    // Ties first: u_k = u_l componentwise, or u_l = u_k where u_k is taken.
    for (const auto &c : normal_conditions)
      if (c.kind == NormalCondition::Kind::interface && c.tied)
        for (unsigned int d = 0; d < dim; ++d)
          {
            const auto [target, other] = !fixed_constraints.is_constrained(c.dofs_k[d]) ?
                                           std::pair(c.dofs_k[d], c.dofs_l[d]) :
                                           std::pair(c.dofs_l[d], c.dofs_k[d]);
            if (!fixed_constraints.is_constrained(target))
              {
                fixed_constraints.add_line(target);
                fixed_constraints.add_entry(target, other, 1.);
              }
          }
    // Then rollers: u.n = 0, solved for the component with the larger |n_c| that
    // is free. At a corner of a roller boundary (face normals differing by more
    // than the corner angle) u.n = 0 must hold for both faces: both components
    // are fixed, as deal.II's no-normal-flux constraints do.
    for (const auto &c : normal_conditions)
      if (c.kind == NormalCondition::Kind::roller && c.corner)
        for (unsigned int d = 0; d < dim; ++d)
          if (!fixed_constraints.is_constrained(c.dofs_k[d]))
            fixed_constraints.add_line(c.dofs_k[d]);
    for (const auto &c : normal_conditions)
      if (c.kind == NormalCondition::Kind::roller && !c.corner)
        {
          unsigned int order[2] = {0, 1};
          if (std::abs(c.normal[1]) > std::abs(c.normal[0]))
            std::swap(order[0], order[1]);
          for (const unsigned int comp : order)
            if (c.normal[comp] != 0 && !fixed_constraints.is_constrained(c.dofs_k[comp]))
              {
                auto row = Contact::normal_constraint(c.dofs_k, nullptr, c.normal, 0., comp, false);
                // (Two slanted rollers at a vertex: u_x = a u_y, then u_y = b u_x.)
                if (!break_cycles(row, fixed_constraints))
                  continue;
                fixed_constraints.add_line(row.target);
                for (const auto &[dof, coefficient] : row.entries)
                  fixed_constraints.add_entry(row.target, dof, coefficient);
                break;
              }
        }
    if (Utilities::MPI::n_mpi_processes(mpi_communicator) > 1)
      fixed_constraints.make_consistent_in_parallel(owned, relevant, mpi_communicator);
    fixed_constraints.close();

    // The fixed lines (not hanging-node ones) that name each DoF as an entry (a
    // tie u_k = u_l names u_l): the contact multipliers need them per vertex.
    named_by.clear();
    for (const auto &line : fixed_constraints.get_lines())
      if (!hanging_node_constraints.is_constrained(line.index))
        for (const auto &[j, a] : line.entries)
          named_by[j].push_back(line.index);
  }
  // Every node with a normal condition, found from the cells this rank sees:
  // roller and obstacle nodes on boundaries of those types, interface nodes on
  // faces between cells of different bodies (side k is the smaller body id; the
  // normal points out of it). Each condition's normal averages the faces around
  // the vertex, so only vertices of locally owned cells are kept: all their
  // neighbouring cells are owned or ghosts, so the average is complete and every
  // rank that assembles at the vertex builds the same constraint.
  template <int dim>
  void MechanicalField<dim>::find_normal_conditions()
  {
    using Kind = NormalCondition::Kind;
    std::vector<bool> vertex_of_owned_cell(triangulation.n_vertices(), false);
    for (const auto &cell : triangulation.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned int v : cell->vertex_indices())
          vertex_of_owned_cell[cell->vertex_index(v)] = true;

    // One entry per vertex, kind and group, in the order of their x DoF: the
    // order of normal_conditions. Rollers and obstacles sum their faces'
    // normals here; an interface vertex comes with its geometry
    // (BodyInterface).
    struct Entry
    {
      NormalCondition            condition;
      Contact::NormalAccumulator normals;
      bool                       given = false; // normal, weight, corner from the interface
    };
    std::map<std::tuple<types::global_dof_index, int, std::string>, Entry> entries;
    const auto add_boundary_face = [&](const typename DoFHandler<dim>::active_cell_iterator &cell,
                                       const unsigned int                                    face,
                                       const Kind                                            kind,
                                       const unsigned int boundary_id) {
      const auto dofs = vertex_dofs<dim>(cell);
      const auto a    = cell->face(face)->vertex(0);
      const auto b    = cell->face(face)->vertex(1);
      const auto c    = cell->center();
      for (unsigned int fv = 0; fv < 2; ++fv)
        {
          const unsigned int v = GeometryInfo<dim>::face_to_cell_vertices(face, fv);
          if (!vertex_of_owned_cell[cell->vertex_index(v)])
            continue;
          const std::string group = boundary_group(boundary_id);
          Entry            &e     = entries[{dofs[v][0], static_cast<int>(kind), group}];
          e.condition.kind        = kind;
          e.condition.group       = group;
          e.condition.boundary_id = boundary_id;
          e.condition.position    = cell->vertex(v);
          e.condition.dofs_k      = {{dofs[v][0], dofs[v][1]}};
          e.condition.has_partner = false;
          e.normals.add_face({{a[0], a[1]}}, {{b[0], b[1]}}, {{c[0], c[1]}});
        }
    };
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (!cell->is_artificial())
        for (const unsigned int face : cell->face_indices())
          if (cell->face(face)->at_boundary())
            {
              const auto bc = prm.mechanical_boundaries.find(cell->face(face)->boundary_id());
              if (bc == prm.mechanical_boundaries.end())
                continue;
              if (bc->second.type == Parameters::MechanicalBoundary::Type::roller)
                add_boundary_face(cell, face, Kind::roller, bc->first);
              else if (bc->second.type == Parameters::MechanicalBoundary::Type::obstacle)
                add_boundary_face(cell, face, Kind::obstacle, bc->first);
            }

    // The interfaces: the vertices of each, mapped to the displacement DoFs of
    // the two sides through the cells that have them, with the interface's
    // law (tied or contact, Contact/Interface k-l).
    std::string problem; // found on this rank
    const auto  interfaces = find_body_interfaces(triangulation, contact_prm.corner_angle, problem);
    if (problem.empty())
      problem = junction_problem(prm, interfaces);
    for (const auto &interface : interfaces)
      {
        const bool tied = prm.interface_pair(interface.body_k, interface.body_l).kind ==
                          Parameters::Contact::Interfaces::tied;
        for (const auto &vertex : interface.vertices)
          {
            const typename DoFHandler<dim>::active_cell_iterator cell_k(&triangulation,
                                                                        vertex.cell_k->level(),
                                                                        vertex.cell_k->index(),
                                                                        &dof_handler);
            const typename DoFHandler<dim>::active_cell_iterator cell_l(&triangulation,
                                                                        vertex.cell_l->level(),
                                                                        vertex.cell_l->index(),
                                                                        &dof_handler);
            const auto dofs_k = vertex_dofs<dim>(cell_k)[vertex.vertex_k];
            const auto dofs_l = vertex_dofs<dim>(cell_l)[vertex.vertex_l];
            Entry &e = entries[{dofs_k[0], static_cast<int>(Kind::interface), interface.name()}];
            NormalCondition &c = e.condition;
            c.kind             = Kind::interface;
            c.group            = interface.name();
            c.boundary_id      = 0;
            c.position         = vertex.position;
            c.vertex           = vertex.index;
            c.dofs_k           = {{dofs_k[0], dofs_k[1]}};
            c.dofs_l           = {{dofs_l[0], dofs_l[1]}};
            c.has_partner      = true;
            c.body_k           = interface.body_k;
            c.body_l           = interface.body_l;
            c.tied             = tied;
            c.normal           = vertex.normal;
            c.weight           = vertex.weight;
            c.corner           = vertex.corner;
            e.given            = true;
          }
      }
    for (const NormalCondition &c : mortar_cache) // per slave node: mortar.cc
      entries[{c.dofs_k[0], static_cast<int>(Kind::interface), c.group}] = {c, {}, true};
    if (!problem.empty() && problem.rfind("parameter", 0) != 0)
      problem = "the mesh: " + problem;

    normal_conditions.clear();
    std::set<std::string> groups;
    // One obstacle condition per vertex: the active flag and the output are kept
    // per vertex and kind, and a corner of two obstacle boundaries has no single
    // normal. Refuse it instead of mixing them.
    std::map<types::global_dof_index, std::string> obstacle_at;
    for (auto &[key, e] : entries)
      if (e.condition.kind == Kind::obstacle)
        {
          const auto [it, inserted] = obstacle_at.emplace(std::get<0>(key), e.condition.group);
          if (!inserted && problem.empty())
            problem = "parameter 'Boundary conditions/Mechanical boundaries': the vertex at (" +
                      std::to_string(e.condition.position[0]) + ", " +
                      std::to_string(e.condition.position[1]) +
                      ") is on two obstacle boundaries (" + it->second + ", " + e.condition.group +
                      "); give the corner to one of them";
        }
    for (auto &[key, e] : entries)
      if (problem.empty() && !e.given)
        try
          {
            e.normals.normal();
          }
        catch (const std::exception &error)
          {
            problem = "parameter 'Boundary conditions/Mechanical boundaries': at (" +
                      std::to_string(e.condition.position[0]) + ", " +
                      std::to_string(e.condition.position[1]) + ") " + error.what();
          }
    throw_collectively<InputError>(problem, mpi_communicator);
    for (auto &[key, e] : entries)
      {
        NormalCondition &c = e.condition;
        if (!e.given)
          {
            const auto n = e.normals.normal();
            c.normal     = {{n[0], n[1]}};
            c.weight     = e.normals.weight();
            c.corner     = e.normals.max_deviation() > contact_prm.corner_angle * numbers::PI / 180;
          }
        normal_conditions.push_back(c);
        if (c.kind != Kind::roller)
          groups.insert(c.group);
      }
    gather_contact_groups(groups);
  }



  // Every rank reports every group of obstacle and interface nodes, even one
  // it has no node of (the statistics columns and RESULT lines are the same
  // on every rank).
  template <int dim>
  void MechanicalField<dim>::gather_contact_groups(const std::set<std::string> &groups)
  {
    contact_groups.clear();
    for (const auto &rank_groups :
         Utilities::MPI::all_gather(mpi_communicator,
                                    std::vector<std::string>(groups.begin(), groups.end())))
      contact_groups.insert(contact_groups.end(), rank_groups.begin(), rank_groups.end());
    std::sort(contact_groups.begin(), contact_groups.end());
    contact_groups.erase(std::unique(contact_groups.begin(), contact_groups.end()),
                         contact_groups.end());
  }



  template void MechanicalField<2>::make_fixed_constraints();
  template void MechanicalField<2>::find_normal_conditions();
  template void MechanicalField<2>::gather_contact_groups(const std::set<std::string> &);
} // namespace ContactStefan
