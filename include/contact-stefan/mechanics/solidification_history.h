// SolidificationHistory: the reference state of every material point of the
// bodies that are stress-free at solidification (doc/solidification.md).
//
// The seed's model measures every strain from one reference state: e = 0 at
// the global Theta_0. A point that freezes out of a melt is, however, born
// stress-free in the configuration it has when it freezes and at the
// temperature at which it freezes; only what happens after its birth strains
// it. So each material point carries its own reference (e_ref, Theta_ref),
// and its stress is
//     sigma = C : (e - e_ref) - beta (Theta - Theta_ref).
//
// Material points. The discrete scheme already evaluates the two parts of the
// stress at different points of a cell: C : e with the 2x2 Gauss rule (the
// stiffness), beta (Theta - Theta_0) with the vertex rule (the thermal load,
// whose weights are the lumped mass). Quadrant q of a Q1 cell holds both
// Gauss point q and vertex q (both rules are numbered lexicographically), so
// a material point here is a corner: the pair (Gauss point q, vertex q) of a
// cell. e_ref lives at the Gauss point, Theta_ref at the vertex, and the
// phase that decides births is that of the node at vertex q (the enthalpy
// step's nodal phase states, exactly; nothing is interpolated).
//
// This class only keeps and moves the references (with the mesh, and into a
// checkpoint); the pure rules are free functions below, unit-tested in
// tests/unit/solidification_history.cc; MechanicalField applies them.
#ifndef contact_stefan_solidification_history_h
#define contact_stefan_solidification_history_h

#include <deal.II/base/symmetric_tensor.h>

#include <deal.II/distributed/cell_data_transfer.h>
#include <deal.II/distributed/tria.h>

#include <contact-stefan/core/common.h>

#include <array>
#include <memory>
#include <vector>

namespace ContactStefan
{
  /**
   * The reference state of one material point (one corner of a cell).
   * Trivially copyable: the transfer packs it bit for bit.
   */
  struct CornerReference
  {
    /** 1 if the point counted as solid at the last update, 0 if not. */
    float solid = 1;
    /**
     * 1 once the point has its own reference (born anew, or melt at the
     * start: e_ref = 0 at the transition temperature); 0 while it keeps the
     * scene's (e_ref = 0, Theta_ref = Theta_0 at its vertex, evaluated where
     * the vertex is: a refined point keeps Theta_0(x) exactly).
     */
    float born = 0;
    /** Theta_ref at the corner's vertex (when born). */
    double theta = 0;
    /** When the reference was set (the start time for the initial one). */
    double time = 0;
    /**
     * e_ref at the corner's Gauss point: xx, yy, xy (tensor component), and
     * zz (the body's uniform e_zz at the birth, generalized plane strain;
     * zero otherwise).
     */
    std::array<double, 4> strain = {{0., 0., 0., 0.}};

    /**
     * (The transfer copies the bytes; deal.II's packing also instantiates the
     * boost path, which this serves.)
     */
    template <class Archive>
    void serialize(Archive &ar, const unsigned int)
    {
      ar &solid &born &theta &time &strain[0] & strain[1] & strain[2] & strain[3];
    }

    SymmetricTensor<2, 2> reference_strain() const
    {
      SymmetricTensor<2, 2> e;
      e[0][0] = strain[0];
      e[1][1] = strain[1];
      e[0][1] = strain[2];
      return e;
    }
  };

  using CellReferences = std::array<CornerReference, 4>;

  /**
   * The update of one material point at the start of a step (pure): if its
   * node's class (solid or not) differs from the one it had at the last
   * update, the point is born anew, stress-free in the configuration it has
   * now and at the transition temperature: e_ref = strain, Theta_ref =
   * theta_transition, time = t (and e_ref,zz = strain_zz, the body's e_zz in
   * generalized plane strain). Returns whether it was reset.
   */
  bool update_corner(CornerReference             &corner,
                     const bool                   solid_now,
                     const SymmetricTensor<2, 2> &strain,
                     const double                 theta_transition,
                     const double                 t,
                     const double                 strain_zz = 0);

  /**
   * The transfer rules (pure). Refinement: each child (child k sits in
   * quadrant k of its parent, and its vertex k is the parent's vertex k)
   * takes the state of the parent's corner k at all four of its corners.
   * Coarsening: the parent's corner k takes the phase class, Theta_ref and
   * time of child k's corner k (the vertex that survives) and the mean of
   * child k's four e_ref (the parent's Gauss point k lies in child k). So
   * the mean of e_ref over a coarsened family is kept, and refining then
   * coarsening gives back the parent's state bit for bit.
   */
  std::vector<CellReferences> refine_references(const CellReferences &parent,
                                                const unsigned int    n_children);
  CellReferences              coarsen_references(const std::vector<CellReferences> &children);

  template <int dim>
  class SolidificationHistory
  {
  public:
    using Transfer = parallel::distributed::CellDataTransfer<dim, dim, std::vector<CellReferences>>;

    explicit SolidificationHistory(const parallel::distributed::Triangulation<dim> &triangulation);

    /** The references of an active cell (by active cell index). */
    CellReferences &operator[](const unsigned int cell_index)
    {
      return references[cell_index];
    }
    const CellReferences &operator[](const unsigned int cell_index) const
    {
      return references[cell_index];
    }
    /** One (default) entry per active cell of the current mesh. */
    void resize();

    /** Before Triangulation::execute_coarsening_and_refinement(). */
    void prepare_for_coarsening_and_refinement();
    /** After it (and after every other transfer registered before this one). */
    void unpack();
    /** Before Triangulation::save(); in the order of the other attached data. */
    void prepare_for_serialization();
    /** After Triangulation::load(); in the same order. */
    void deserialize();

  private:
    const parallel::distributed::Triangulation<dim> &triangulation;
    std::vector<CellReferences>                      references;
    std::unique_ptr<Transfer>                        transfer;
    std::unique_ptr<Transfer>                        make_transfer() const;
  };
} // namespace ContactStefan

#endif
