// The errors against an exact temperature, accumulated after each step: the
// L2 error and norm, the space-time error, the max-norm error at the nodes and
// the mean signed error. The common base of the parts that give the scene an
// exact temperature (verification/function.cc, verification/neumann.cc).
#ifndef contact_stefan_temperature_errors_h
#define contact_stefan_temperature_errors_h

#include <boost/serialization/vector.hpp>

#include <contact-stefan/output/part.h>

#include <vector>

namespace ContactStefan
{
  struct TemperatureErrorState
  {
    double              last_l2_error = 0, last_l2_norm = 0, last_max_error = 0;
    double              space_time_error_squared = 0, space_time_norm_squared = 0;
    double              max_max_error = 0, max_exact_temperature = 0;
    std::vector<double> mean_errors; // mean signed temperature error after each step

    template <class Archive>
    void serialize(Archive &ar, const unsigned int)
    {
      ar &last_l2_error &last_l2_norm &last_max_error &space_time_error_squared
        &space_time_norm_squared &max_max_error &max_exact_temperature &mean_errors;
    }
  };

  template <int dim>
  class TemperatureErrors : public PartWithState<dim, TemperatureErrorState>
  {
  public:
    /**
     * x_only: the exact temperature depends on x alone (and t), so that it is
     * evaluated once per distinct abscissa.
     */
    TemperatureErrors(const RunContext<dim> &run, const bool x_only);

    /** The errors at the step's time (tau = 0 at the start: the user's data). */
    void update(const StepData &data) override;
    /** Slot 'temperature'. */
    void
    add_results(ResultLines &results, const unsigned int n_steps, const double time) const override;

  private:
    /**
     * The geometry the error norms need, computed once per mesh: the errors
     * are evaluated at every step, and re-running FEValues over all cells
     * cost more than the step itself on large meshes.
     */
    void update_geometry();
    struct Geometry
    {
      unsigned int mesh_generation = 0; // of the field's mesh it was built for (0: none)
      unsigned int n_cells = 0, n_q_points = 0, dofs_per_cell = 0;
      // Per owned cell: the local (ghosted-vector) indices of its DoFs, its
      // quadrature points and JxW; the shape values (the same on every cell).
      std::vector<int>        local_dofs;
      std::vector<Point<dim>> points;
      std::vector<double>     JxW, shape;
      // The owned nodes: their local index in the ghosted temperature and in
      // the owned lumped mass.
      std::vector<std::pair<int, int>> nodes;
      // Where the exact solution is evaluated: the distinct points among the
      // quadrature points and the nodes (for a solution of x alone, such as
      // the Neumann solution on a strip, one per distinct abscissa: 40 times
      // fewer erfc calls on a strip 40 cells high), and for each quadrature
      // point, then each node, its index in that list.
      std::vector<Point<dim>>   evaluation_points;
      std::vector<unsigned int> point_evaluation, node_evaluation;
    } geometry;
    const bool          x_only;
    std::vector<double> exact_values; // at the evaluation points, per step
  };
} // namespace ContactStefan

#endif
