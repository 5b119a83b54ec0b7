// Recovered nodal fields that respect the bodies (doc/output.md, "Point data").
//
// A value known at the cell centres (a stress, a strain, a heat flux: where the
// gradient of Q1 is accurate) becomes a continuous field by a lumped L2
// projection onto FE_Q(1): a node takes the mean of the centre values of the
// cells around it, each weighted by the cell's vertex-rule weight there. The
// projection is onto each body's own copy of the Q1 space (step-46's slots:
// FE_Q(1) in the body's slot, FE_Nothing in the others), so a recovered field is
// never averaged across a body boundary, where a stress or a heat flux may
// jump (a tangential flux does across an interface between two
// conductivities). Hanging nodes take their constrained values.
//
// recover_pair_in_slots() is the projection on any such DoFHandler (the
// mechanical field's displacement slots); BodyRecovery owns a DoFHandler of
// its own for a field that has none (the heat flux of the thermal field,
// whose temperature is shared across perfect thermal contact).
#ifndef contact_stefan_body_recovery_h
#define contact_stefan_body_recovery_h

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_values.h>

#include <deal.II/hp/fe_collection.h>

#include <deal.II/lac/affine_constraints.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <boost/signals2/connection.hpp>

#include <contact-stefan/core/common.h>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace ContactStefan
{
  /**
   * The lumped L2 projection of one pair of values per active cell
   * (cell_values[active_cell_index]) onto components (c0, c0 + 1) of each
   * cell's body slot, c0 = slot_of_body[material id] * components_per_slot;
   * `nodal` is reinitialised on `owned`. Collective.
   */
  template <int dim>
  void recover_pair_in_slots(const DoFHandler<dim>                      &dof_handler,
                             const AffineConstraints<double>            &hanging_node_constraints,
                             const std::map<unsigned int, unsigned int> &slot_of_body,
                             const unsigned int                          components_per_slot,
                             const std::vector<std::array<double, 2>>   &cell_values,
                             const IndexSet                             &owned,
                             const MPI_Comm                              mpi_communicator,
                             Vector                                     &nodal);

  /**
   * Two scalars stored in components (c0, c0 + 1) of the cell's body slot,
   * written under their own names (the recovered nodal pairs).
   */
  template <int dim>
  class BodyPair : public DataPostprocessor<dim>
  {
  public:
    BodyPair(const std::map<unsigned int, unsigned int> &slots,
             const unsigned int                          components_per_slot,
             const std::vector<std::string>             &names)
      : slot_of_body(slots)
      , stride(components_per_slot)
      , names(names)
    {}
    void evaluate_vector_field(const DataPostprocessorInputs::Vector<dim> &inputs,
                               std::vector<dealii::Vector<double>>        &computed) const override
    {
      const auto         cell = inputs.template get_cell<dim>();
      const unsigned int c0   = slot_of_body.at(cell->material_id()) * stride;
      for (unsigned int q = 0; q < computed.size(); ++q)
        for (unsigned int k = 0; k < names.size(); ++k)
          computed[q](k) = inputs.solution_values[q][c0 + k];
    }
    std::vector<std::string> get_names() const override
    {
      return names;
    }
    std::vector<DataComponentInterpretation::DataComponentInterpretation>
    get_data_component_interpretation() const override
    {
      return std::vector<DataComponentInterpretation::DataComponentInterpretation>(
        names.size(), DataComponentInterpretation::component_is_scalar);
    }
    UpdateFlags get_needed_update_flags() const override
    {
      return update_values;
    }

  private:
    const std::map<unsigned int, unsigned int> slot_of_body;
    const unsigned int                         stride;
    const std::vector<std::string>             names;
  };

  /**
   * A recovered pair on a DoFHandler of its own: FE_Q(1)^2 in each body's
   * slot. recover() distributes the DoFs again only after the mesh changed
   * (the triangulation's any_change signal).
   */
  template <int dim>
  class BodyRecovery
  {
  public:
    BodyRecovery(const Triangulation<dim>        &triangulation,
                 const std::vector<unsigned int> &body_ids,
                 const MPI_Comm                   mpi_communicator);
    ~BodyRecovery();

    /** Project the centre values (one pair per active cell). Collective. */
    void recover(const std::vector<std::array<double, 2>> &cell_values);

    /** Write the last recovery under `names` (two); alive until the next call. */
    void add_output(DataOut<dim> &data_out, const std::vector<std::string> &names);

    /**
     * Visit every vertex of every owned cell with its vertex-rule weight, the
     * last recovered pair of the cell's body there and the cell's centre (to
     * evaluate a field that jumps across a body boundary on the cell's side).
     */
    void for_each_vertex(
      const std::function<
        void(const Point<dim> &, double, const std::array<double, 2> &, const Point<dim> &)> &visit)
      const;

  private:
    const Triangulation<dim>            &triangulation;
    const MPI_Comm                       mpi_communicator;
    std::map<unsigned int, unsigned int> slot_of_body;
    hp::FECollection<dim>                fe;
    DoFHandler<dim>                      dof_handler;
    AffineConstraints<double>            hanging_node_constraints;
    IndexSet                             owned, relevant;
    Vector                               ghosted;
    std::unique_ptr<BodyPair<dim>>       postprocessor;
    bool                                 mesh_changed = true;
    boost::signals2::connection          mesh_change;
  };
} // namespace ContactStefan

#endif
