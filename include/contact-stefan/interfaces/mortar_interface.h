// One mortar interface of the mesh (Contact/Interface k-l/Discretisation =
// mortar, doc/contact.md): the boundary faces of body k and body l that carry
// the interface's two 'Mortar boundaries' ids, gathered from every rank,
// and their dual mortar coupling (interfaces/mortar.h). Both fields build it
// from the same faces with the same rules, so that they agree on the slave
// side, on which slave nodes are coupled and on the weights: the contact step
// turns it into one Signorini condition per slave node, the enthalpy step
// into one constraint Theta_j = sum_m (M_jm / D_j) Theta_m (perfect thermal
// contact). A node carries the field's own DoFs (two displacement
// components, one temperature).
#ifndef contact_stefan_mortar_interface_h
#define contact_stefan_mortar_interface_h

#include <deal.II/dofs/dof_handler.h>

#include <contact-stefan/core/interface_laws.h>
#include <contact-stefan/interfaces/mortar.h>

#include <array>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  /**
   * The deformed configuration of the mortar sides with large sliding
   * (Contact/Interface k-l/Mortar sliding = large, doc/contact.md): the
   * displacement at the start of the step of every side node this rank's
   * cells own, by (body, x, y) of its mesh position (the bodies' copies of a
   * node that lies on both sides are distinct). Empty: every interface is
   * coupled on the mesh. The coupled problem fills it before every step,
   * both fields read it at their set-up.
   */
  struct MortarConfiguration
  {
    std::map<std::tuple<unsigned int, double, double>, std::array<double, 2>> displacement;
  };

  /** The coupling of one mortar interface, the same on every rank. */
  struct MortarInterface
  {
    /** 'interface k-l'. */
    std::string name;
    /** The bodies k < l; which of the two sides (0: k, 1: l) is the slave. */
    std::array<unsigned int, 2> body{{0, 0}};
    unsigned int                slave = 0;
    /**
     * The two sides as polylines (nodes numbered in an order that does not
     * depend on the partition) and each node's DoFs, as the field named them.
     */
    std::array<Mortar::Side, 2>                                      sides;
    std::array<std::vector<std::vector<types::global_dof_index>>, 2> dofs;
    /** A point of each edge's cell on the mesh (Side::inside moves with large sliding). */
    std::array<std::vector<Mortar::Vector2>, 2>                      inside_on_mesh;
    double                                                           search_distance = 0;
    /** Whether the sides were coupled in a deformed configuration (large sliding). */
    bool deformed = false;
    /** D, M, normals and gaps by slave node. */
    Mortar::Coupling coupling;
    /**
     * Whether slave node j has a condition: the master side covers at least
     * 'Mortar minimum coverage' of its support.
     */
    std::vector<bool> conditioned;
    unsigned int      n_conditions = 0;
    /** max |1 - sum_m M_jm / D_j| over the conditioned nodes. */
    double weight_defect = 0;

    const Mortar::Side &slave_side() const
    {
      return sides[slave];
    }
    /** Node v of a side (0: body k's) at its position on the mesh (also with large sliding). */
    Point<2> mesh_position(const unsigned int side, const unsigned int v) const
    {
      const Mortar::Side &S = sides[side];
      const auto         &x = S.reference.empty() ? S.nodes[v] : S.reference[v];
      return Point<2>(x[0], x[1]);
    }
    Point<2> slave_position(const unsigned int j) const
    {
      return mesh_position(slave, j);
    }
    const std::vector<std::vector<types::global_dof_index>> &slave_dofs() const
    {
      return dofs[slave];
    }
    const std::vector<std::vector<types::global_dof_index>> &master_dofs() const
    {
      return dofs[1 - slave];
    }
  };

  /**
   * The coupling of the mortar interface between bodies pair.first <
   * pair.second whose law is 'law', built from the locally owned cells of
   * every rank (collective). Throws InputError naming 'Contact/Interface
   * k-l/Mortar boundaries' if a nodal normal is undefined or if no slave node
   * faces the master side within the search distance. A node's DoFs are those
   * of the field's Q1 element at the vertex, by component (the displacement's
   * x and y, or the temperature; FE_Nothing slots have none). With large
   * sliding and a non-empty configuration the sides are coupled where the
   * configuration puts them (mortar.h: normals and weights there, the gap
   * of the mesh positions); std::logic_error if it lacks a side node.
   */
  template <int dim>
  MortarInterface couple_mortar_interface(const DoFHandler<dim>                       &dof_handler,
                                          const std::pair<unsigned int, unsigned int> &pair,
                                          const Parameters::InterfacePair             &law,
                                          const MortarConfiguration *configuration = nullptr);
} // namespace ContactStefan

#endif
