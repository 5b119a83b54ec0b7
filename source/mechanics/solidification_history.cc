// SolidificationHistory: the references of the material points, their update
// rule and how they move with the mesh (solidification_history.h).
#include <deal.II/base/exceptions.h>

// The transfer of a value type of our own is instantiated here.
#include <deal.II/distributed/cell_data_transfer.templates.h>

#include <contact-stefan/mechanics/solidification_history.h>

#include <type_traits>

namespace ContactStefan
{
  // The transfer packs the references bit for bit (Utilities::pack copies a
  // trivially copyable value of less than 256 bytes as it is).
  static_assert(std::is_trivially_copyable<CellReferences>::value && sizeof(CellReferences) < 256,
                "CellReferences must be packed as raw bytes");

  bool update_corner(CornerReference             &corner,
                     const bool                   solid_now,
                     const SymmetricTensor<2, 2> &strain,
                     const double                 theta_transition,
                     const double                 t,
                     const double                 strain_zz)
  {
    if ((corner.solid != 0) == solid_now)
      return false;
    // Born anew (frozen, or molten: a melt keeps no memory of the solid's
    // configuration either). The transition temperature, not the node's
    // temperature now: a node that crossed the plateau within the step and
    // cooled below it is strained by that cooling, as it would have been had
    // the step been short enough to catch it on the plateau.
    corner.solid     = solid_now ? 1 : 0;
    corner.born      = 1;
    corner.theta     = theta_transition;
    corner.time      = t;
    corner.strain[0] = strain[0][0];
    corner.strain[1] = strain[1][1];
    corner.strain[2] = strain[0][1];
    corner.strain[3] = strain_zz;
    return true;
  }



  std::vector<CellReferences> refine_references(const CellReferences &parent,
                                                const unsigned int    n_children)
  {
    AssertThrow(n_children == 4, ExcMessage("isotropic refinement of a quadrilateral expected"));
    std::vector<CellReferences> children(n_children);
    for (unsigned int k = 0; k < n_children; ++k)
      children[k].fill(parent[k]);
    return children;
  }



  CellReferences coarsen_references(const std::vector<CellReferences> &children)
  {
    AssertThrow(children.size() == 4,
                ExcMessage("isotropic coarsening of a quadrilateral expected"));
    CellReferences parent;
    for (unsigned int k = 0; k < 4; ++k)
      {
        parent[k] = children[k][k];
        for (unsigned int s = 0; s < 4; ++s)
          // The mean, summed in pairs in a fixed order: the same bits on any
          // partition, and four equal values give that value exactly (a + a
          // and 2a + 2a are exact; a + a + a need not be).
          parent[k].strain[s] = 0.25 * ((children[k][0].strain[s] + children[k][1].strain[s]) +
                                        (children[k][2].strain[s] + children[k][3].strain[s]));
      }
    return parent;
  }



  template <int dim>
  SolidificationHistory<dim>::SolidificationHistory(
    const parallel::distributed::Triangulation<dim> &triangulation)
    : triangulation(triangulation)
  {}



  template <int dim>
  void SolidificationHistory<dim>::resize()
  {
    references.assign(triangulation.n_active_cells(), CellReferences());
  }



  template <int dim>
  std::unique_ptr<typename SolidificationHistory<dim>::Transfer>
  SolidificationHistory<dim>::make_transfer() const
  {
    return std::make_unique<Transfer>(
      triangulation,
      false,
      [](const typename Triangulation<dim>::cell_iterator &parent, const CellReferences &value) {
        return refine_references(value, parent->n_children());
      },
      [](const typename Triangulation<dim>::cell_iterator &,
         const std::vector<CellReferences> &children) { return coarsen_references(children); });
  }



  template <int dim>
  void SolidificationHistory<dim>::prepare_for_coarsening_and_refinement()
  {
    transfer = make_transfer();
    transfer->prepare_for_coarsening_and_refinement(references);
  }



  template <int dim>
  void SolidificationHistory<dim>::unpack()
  {
    Assert(transfer, ExcInternalError());
    std::vector<CellReferences> moved(triangulation.n_active_cells());
    transfer->unpack(moved);
    references = std::move(moved);
    transfer.reset();
  }



  template <int dim>
  void SolidificationHistory<dim>::prepare_for_serialization()
  {
    transfer = make_transfer();
    transfer->prepare_for_serialization(references);
  }



  template <int dim>
  void SolidificationHistory<dim>::deserialize()
  {
    transfer = make_transfer();
    std::vector<CellReferences> loaded(triangulation.n_active_cells());
    transfer->deserialize(loaded);
    references = std::move(loaded);
    transfer.reset();
  }



  template class SolidificationHistory<2>;
} // namespace ContactStefan
