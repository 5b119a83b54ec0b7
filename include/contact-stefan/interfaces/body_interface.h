// The geometry of the places where two bodies meet, in mesh entities.
//
// A body interface is the set of faces between cells of body k and cells of
// body l (material ids, k < l). It holds its face pairs and, per vertex, the
// cells on either side that have it, the length-weighted average normal
// (pointing out of body k), the lumped weight (half the length of its faces)
// and whether the faces at the vertex disagree by more than a corner angle.
// It knows no DoF: each field maps the vertices to its own DoFs through the
// cells it names (the mechanical field to the two sides' displacements, a
// thermal interface law to the two sides' temperatures). It is rebuilt
// whenever the mesh changes. The laws that act on it -- contact or tied,
// the gap, the thermal law -- are chosen per interface in the parameter file
// (Parameters::InterfacePair, doc/contact.md).
#ifndef contact_stefan_body_interface_h
#define contact_stefan_body_interface_h

#include <deal.II/base/function.h>
#include <deal.II/base/point.h>

#include <deal.II/grid/tria.h>

#include <contact-stefan/core/interface_laws.h>

#include <array>
#include <map>
#include <string>
#include <tuple>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  template <int dim>
  struct BodyInterface
  {
    using Cell = typename Triangulation<dim>::active_cell_iterator;

    unsigned int body_k = 0, body_l = 0; // material ids, k < l

    /** "interface k-l": the name in messages, statistics and RESULT lines. */
    std::string name() const
    {
      return "interface " + std::to_string(body_k) + "-" + std::to_string(body_l);
    }

    /** One face seen from both sides. */
    struct FacePair
    {
      Cell         cell_k, cell_l;
      unsigned int face_k = 0, face_l = 0;
    };

    /** One vertex of the interface, with a cell of each side that has it. */
    struct Vertex
    {
      unsigned int          index = 0; // the triangulation's vertex index
      Point<dim>            position;
      Cell                  cell_k, cell_l;
      unsigned int          vertex_k = 0, vertex_l = 0; // its number in each cell
      std::array<double, 2> normal{{0., 0.}};           // out of body k
      double                weight = 0;
      bool                  corner = false;
    };

    /** The faces of cells that are not artificial, in cell order. */
    std::vector<FacePair> faces;
    /** The vertices of locally owned cells, by vertex index. */
    std::vector<Vertex> vertices;
  };

  /**
   * Where a field evaluates a function for one side of an interface whose
   * sides have their own temperatures (a conductance interface,
   * doc/interface_heat.md): the vertex moved this fraction of the way to the
   * centre of a cell of that side. Far enough inside for the rounding of an
   * expression that jumps along a slanted or curved interface (one ulp was
   * not), near enough that a smooth function changes by at most
   * 1e-10 h |grad f|.
   */
  inline constexpr double interface_side_offset = 1e-10;

  /**
   * Whether a function given for the whole domain is evaluated per body at
   * each vertex of the mesh (indexed by the triangulation's vertex index): at
   * a vertex shared by cells of two or more bodies, and on the boundaries of
   * a mortar interface (each a boundary of its own body, where the two
   * bodies' data meet). Cells that are not artificial are visited, which on a
   * distributed mesh are all cells around a vertex of a locally owned cell.
   * At such a vertex the reference and the initial temperature (and an exact
   * solution) are evaluated for each body inside a cell of that body
   * (point_of_side()), so that a function that jumps along the interface
   * gives each body its own value whatever branch the rounding of the
   * vertex's coordinates would select (doc/coupling.md §2); when the
   * function jumps there (jumps_at()). conductance_only: the vertices of
   * conductance interfaces alone (one temperature per side: always
   * evaluated inside).
   */
  template <int dim>
  std::vector<bool> two_sided_vertices(
    const Triangulation<dim>                                                         &triangulation,
    const std::map<std::pair<unsigned int, unsigned int>, Parameters::InterfacePair> &pairs,
    const bool conductance_only = false);

  /**
   * Whether f jumps at a two-sided vertex: its values just inside some cell
   * (point_of_side()) and just outside it, the same distance beyond the
   * vertex, differ by more than 1e-8 of the
   * largest |f| at the vertices of the mesh (the offset inside moves a smooth
   * function by about 1e-10 h |grad f|). Continuous data are evaluated at the vertices, as they
   * always were: moving them inside by round-off would load a body that
   * starts stress-free. Collective.
   */
  template <int dim>
  bool jumps_at(const Function<dim>      &f,
                const Triangulation<dim> &triangulation,
                const std::vector<bool>  &two_sided);

  /** The point at which a cell evaluates a function for vertex v (above). */
  template <int dim, typename CellIterator>
  Point<dim> point_of_side(const CellIterator &cell, const unsigned int v)
  {
    return cell->vertex(v) + interface_side_offset * (cell->center() - cell->vertex(v));
  }

  /**
   * What the contact step tells the thermal field about an interface vertex
   * (MechanicalField::interface_contact_states, doc/interface_heat.md): the
   * normal gap (m, > 0 open), the contact pressure (Pa) and whether the vertex
   * is closed (in the active set; a tied interface is closed with gap and
   * pressure 0). Keyed by (body k, body l, vertex index); on a mortar
   * interface by (body k, body l, slave node number in its MortarInterface),
   * and every rank has every slave node's state.
   */
  struct InterfaceContactState
  {
    double gap = 0, pressure = 0;
    bool   closed = false;
  };
  using InterfaceContactStates =
    std::map<std::tuple<unsigned int, unsigned int, unsigned int>, InterfaceContactState>;

  /**
   * The interfaces of a mesh, ordered by (k, l). corner_angle (degrees): the
   * deviation of a face normal from the vertex normal above which the vertex
   * is a corner. Faces are visited cell by cell, so that each vertex sums its
   * faces in the order in which the mesh lists them. A refused interface
   * (refined differently on its two sides) throws; a vertex whose normal is
   * undefined (faces that cancel) gets the reason in `problem` (the caller
   * decides collectively).
   */
  template <int dim>
  std::vector<BodyInterface<dim>> find_body_interfaces(const Triangulation<dim> &triangulation,
                                                       const double              corner_angle,
                                                       std::string              &problem);
} // namespace ContactStefan

#endif
