// Postprocessor: everything a run reports. The VTU/PVD fields (each field adds
// its own), the per-step statistics table, the errors against an exact solution
// accumulated over the run, and the RESULT lines that end a run. It reads the
// fields through their const queries and never changes them.
#ifndef contact_stefan_postprocessor_h
#define contact_stefan_postprocessor_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <boost/serialization/map.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <contact-stefan/core/common.h>
#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/parameters.h>
#include <contact-stefan/core/scene_functions.h>
#include <contact-stefan/mechanics/mechanical_field.h>
#include <contact-stefan/output/output_parameters.h>
#include <contact-stefan/output/run_guard.h>
#include <contact-stefan/thermal/thermal_field.h>
#include <contact-stefan/verification/neumann_solution.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ContactStefan
{
  // What the coupling did in one time step.
  struct CouplingReport
  {
    unsigned int iterations        = 0;          // passes of contact + enthalpy step (1: staggered)
    unsigned int reassembled_cells = 0;          // stiffness re-assembled for a new phase mixture
    double       change_u = 0, change_theta = 0; // last fixed-point changes, max norm
  };

  template <int dim>
  class Postprocessor
  {
  public:
    // Creates the output directory and checks that it is writable (an
    // InputError naming Output/Directory otherwise), before any work is done.
    // prm: the scene; output_prm: subsection Output; adaptive: the mesh
    // adapts during the run (errors are then reported per mesh); neumann: the
    // exact solution of a Neumann scene (else null).
    Postprocessor(const SceneParameters                           &prm,
                  const Parameters::Output                        &output_prm,
                  const bool                                       adaptive,
                  const NeumannSolution                           *neumann,
                  const Materials                                 &materials,
                  SceneFunctions<dim>                             &functions,
                  const parallel::distributed::Triangulation<dim> &triangulation,
                  TimerOutput                                     &timer,
                  const ConditionalOStream                        &pcout);

    // The fields to report on (either may be null: that physics is off).
    void attach(const ThermalField<dim> *thermal, const MechanicalField<dim> *mechanical);

    // At the start time: the initial state's errors, statistics row 0 (with the
    // contact step that made the initial equilibrium), VTU 0.
    void start(const double time, const ContactStepReport &initial_contact, const double wall_time);
    // After a time step.
    void end_step(const unsigned int        step,
                  const double              time,
                  const double              time_step,
                  const bool                last_step,
                  const EnthalpyStepReport &thermal_report,
                  const ContactStepReport  &contact_report,
                  const CouplingReport     &coupling_report,
                  const double              wall_time);
    // A mesh adaptation between two steps changed the total enthalpy by this
    // (relative) amount; coarsened: it coarsened cells (else refinement only).
    void record_adaptation(const double relative_enthalpy_change, const bool coarsened);
    // Everything accumulated over the run (errors, counters, histories, the
    // PVD records), for checkpoints: the same on every rank.
    template <class Archive>
    void serialize(Archive &ar, const unsigned int)
    {
      ar &pvd_records &initial_total_enthalpy &last_l2_error &last_l2_norm &last_max_error
        &space_time_error_squared &space_time_norm_squared &max_max_error &max_exact_temperature
          &max_liquid_fraction_error &mean_errors &max_energy_residual &total_active_set_iterations
            &steps_with_fallback &inconsistent_enthalpy_nodes &total_contact_iterations
              &max_contact_iterations &first_contact_iterations &max_contact_iterations_warm
                &last_contact_report &total_coupling_iterations &max_coupling_iterations
                  &reassembled_cells &contact_factorisations &enthalpy_factorisations
                    &reused_contact_steps &max_active_nodes &total_thermoelastic_heat
                      &total_contact_work &elastic_energy &max_relative_stress_error &
                        max_pressure_error &max_exact_pressure &loaded_force_history &opening_time &
                          largest_force &n_adaptations &max_refinement_change &max_coarsening_change
                            &pending_change &dof_time_integral &start_time &elasticity_linear
                              &steps_with_truncated_newton &max_strain &max_section_error_cell
                                &max_section_error_recovered &max_section_error_cell_uniform
                                  &max_exact_section_force &max_relative_stress_error_cell
                                    &max_relative_stress_error_recovered &section_sides_checked &
                                      section_sides_uniform &max_von_mises &max_von_mises_over_steps
                                        &max_von_mises_time &max_von_mises_point;
    }
    // The RESULT lines.
    void print_results(const unsigned int n_steps, const double time) const;
    // The self-checks the run failed, one sentence each (empty: none failed).
    std::vector<std::string> failed_diagnostics() const;
    // Removes the VTU/PVTU/PVD files of the output directory that this run
    // does not own (those of steps after last_kept_step; -1: all) and says so.
    // Collective.
    void remove_stale_output(const long last_kept_step) const;

  private:
    void accumulate_errors(const double time, const double tau);
    // The geometry the error norms need, computed once per mesh: the errors
    // are evaluated at every step, and re-running FEValues over all cells
    // cost more than the step itself on large meshes.
    void update_error_geometry();
    struct ErrorGeometry
    {
      types::global_dof_index n_dofs          = 0; // of the mesh it was built for
      unsigned int            mesh_generation = 0; // of the field's mesh it was built for (0: none)
      unsigned int            n_cells = 0, n_q_points = 0, dofs_per_cell = 0;
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
    } error_geometry;
    std::vector<double> exact_values; // at the evaluation points, per step
    void                write_statistics_row(const unsigned int        step,
                                             const double              time,
                                             const EnthalpyStepReport &report,
                                             const ContactStepReport  &contact_report,
                                             const CouplingReport     &coupling_report,
                                             const double              wall_time) const;
    // The steps of write_statistics_row() (postprocessor.cc): a row of
    // columns (name, unit, meaning, this step's value), the enthalpy step's
    // and the coupling's columns (area: the melt area), the contact step's.
    class StatisticsRow;
    void add_thermal_columns(StatisticsRow            &row,
                             const double              area,
                             const EnthalpyStepReport &report,
                             const CouplingReport     &coupling_report) const;
    void add_mechanical_columns(StatisticsRow &row, const ContactStepReport &contact_report) const;
    // Exact stress and contact pressure (any scene with mechanics), the
    // energy terms of the step and the opening of each contact group.
    void accumulate_mechanical_results(const double time, const ContactStepReport &contact_report);
    // Its steps (mechanical_results.cc): the opening time of each contact
    // group; the errors against the exact stress, section force and contact
    // pressure at time (the last three collective).
    void track_contact_opening(const double time, const ContactStepReport &contact_report);
    void accumulate_stress_errors(Function<dim> &exact, const double time);
    void accumulate_section_force_errors(Function<dim> &exact, const double time);
    void accumulate_pressure_errors(Function<dim> &exact, const double time);
    void print_coupling_results(const unsigned int n_steps) const;
    void print_timer_calls() const;
    void output_vtu(const unsigned int step, const double time);
    void print_thermal_results(const unsigned int n_steps, const double time) const;
    void print_mechanical_results(const unsigned int n_steps) const;

    // Parts of the RESULT lines: the equilibrium scene's and the fronts of a
    // Neumann scene (h: the mesh width) of print_thermal_results(), the section
    // forces of print_mechanical_results().
    void print_equilibrium_results() const;
    void print_front_results(const double time, const double h) const;
    void print_section_force_results() const;

    void print_hertz_results() const;
    void print_patch_results() const;
    double mesh_width() const;
    void   add_result(const std::string &name, const double value) const;

    const SceneParameters                           &prm;
    const Parameters::Output                        &output_prm;
    const bool                                       adaptive;
    const NeumannSolution                           *neumann;
    const Materials                                 &materials;
    SceneFunctions<dim>                             &functions;
    const parallel::distributed::Triangulation<dim> &triangulation;
    const MPI_Comm                                   mpi_communicator;
    TimerOutput                                     &timer;
    const ConditionalOStream                        &pcout;
    const ThermalField<dim>                         *thermal    = nullptr;
    const MechanicalField<dim>                      *mechanical = nullptr;

    std::vector<std::pair<double, std::string>> pvd_records;

    // Accumulated over the run.
    double              initial_total_enthalpy = 0;
    double              last_l2_error = 0, last_l2_norm = 0, last_max_error = 0;
    double              space_time_error_squared = 0, space_time_norm_squared = 0;
    double              max_max_error = 0, max_exact_temperature = 0, max_liquid_fraction_error = 0;
    std::vector<double> mean_errors; // mean signed temperature error after each step
    double              max_energy_residual         = 0;
    unsigned int        total_active_set_iterations = 0, steps_with_fallback = 0;
    unsigned int        steps_with_truncated_newton = 0;
    unsigned int        inconsistent_enthalpy_nodes = 0;
    unsigned int        total_contact_iterations = 0, max_contact_iterations = 0;
    unsigned int        first_contact_iterations = 0, max_contact_iterations_warm = 0;
    ContactStepReport   last_contact_report;
    // Coupling and energy bookkeeping.
    unsigned int total_coupling_iterations = 0, max_coupling_iterations = 0;
    unsigned int reassembled_cells = 0, contact_factorisations = 0, enthalpy_factorisations = 0;
    // The elasticity system's CG + AMG work over the run.
    LinearSolverStatistics elasticity_linear;
    unsigned int           reused_contact_steps = 0, max_active_nodes = 0;
    double                 total_thermoelastic_heat = 0, total_contact_work = 0, elastic_energy = 0;
    double                 max_strain = 0; // over the steps, for the small-strain check
    // The largest von Mises stress of the cell-centre values: of the last step
    // (statistics), and over the steps with its time and the centre of its cell
    // (RESULT lines).
    double     max_von_mises = 0, max_von_mises_over_steps = 0, max_von_mises_time = 0;
    Point<dim> max_von_mises_point;
    // Exact stress: the largest L2 error over the steps relative to
    // the exact stress plus the thermal stress; exact contact pressure: the
    // largest nodal error and the largest exact pressure.
    // By the vertex rule at the vertices (the historical measure), and of the
    // two stress outputs (doc/output.md).
    double max_relative_stress_error = 0, max_relative_stress_error_cell = 0,
           max_relative_stress_error_recovered = 0;
    double max_pressure_error = 0, max_exact_pressure = 0;
    // Against 'Exact solution/Section normal force', over lines, sides and steps.
    // The cell-centre error on rows of equal cells alone, and how many sides
    // (over lines and steps) were compared, and how many of them were such rows.
    double       max_section_error_cell = 0, max_section_error_recovered = 0;
    double       max_section_error_cell_uniform = 0;
    unsigned int section_sides_checked = 0, section_sides_uniform = 0;
    double       max_exact_section_force = 0;
    // Per contact group: the last two (t, force) with force > 0 and, once the
    // force has dropped to zero after them, the interpolated opening time.
    std::map<std::string, std::vector<std::pair<double, double>>> loaded_force_history;
    std::map<std::string, double>                                 opening_time, largest_force;

    // Mesh adaptation: the number of adaptations, the largest enthalpy changes
    // through pure refinement and through adaptations that coarsened, the
    // change of the adaptation before the next statistics row, and the integral
    // of the number of DoFs over time (the time-averaged DoFs).
    unsigned int n_adaptations         = 0;
    double       max_refinement_change = 0;
    double       max_coarsening_change = 0;
    double       pending_change        = 0;
    double       dof_time_integral     = 0;
    double       start_time            = 0;

    // The RESULT lines of a run, collected and checked before any is printed:
    // researchers publish these numbers, so a non-finite one stops the run with
    // an error (exit code 2) instead of reaching the output.
    mutable std::vector<std::pair<std::string, double>> results;

    // Rank 0 holds the output directory's lock for the run's lifetime.
    std::unique_ptr<OutputDirectoryLock> output_lock;
  };
} // namespace ContactStefan

#endif
