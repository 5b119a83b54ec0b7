// CoupledProblem: the time loop of the Nedoma-Dvorak scheme and the data it needs.
//
// The members are spread over source files by concern:
//   setup.cc          mesh, DoFs, nodal enthalpy laws, per-cell operators, boundary data
//   enthalpy_step.cc  the primal-dual active-set solver of the enthalpy (Stefan) step
//                     and its relaxation fallback
//   output.cc         VTU/PVD, the statistics table, errors against exact solutions
//   coupled_problem.cc  construction and the time loop
// Everything is distributed (p4est triangulation, Trilinos linear algebra), so
// `mpirun -np N` runs the same scene; results do not depend on N beyond the
// linear solver tolerance.
#ifndef contact_stefan_coupled_problem_h
#define contact_stefan_coupled_problem_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_q.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <contact-stefan/enthalpy_law.h>
#include <contact-stefan/neumann_solution.h>
#include <contact-stefan/parameters.h>

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  // What one enthalpy step did, for the screen and the statistics table.
  struct EnthalpyStepReport
  {
    unsigned int active_set_iterations = 0;
    unsigned int damped_steps          = 0; // iterations whose Newton step was shortened
    unsigned int relaxation_iterations = 0; // > 0 only if the fallback ran
    unsigned int plateau_nodes         = 0;
    unsigned int state_changes         = 0; // summed over the iterations
    double       energy_residual       = 0; // relative, see compute_energy_balance()
  };

  template <int dim>
  class CoupledProblem
  {
  public:
    CoupledProblem(const AllParameters &parameters, const MPI_Comm mpi_communicator);
    void run();

  private:
    using Vector      = TrilinosWrappers::MPI::Vector;
    using LocalMatrix = FullMatrix<double>;

    // --- setup.cc ---------------------------------------------------------
    void make_mesh();
    void setup_thermal_system();
    void setup_nodal_enthalpy_laws();
    void setup_boundary_and_source_functions();
    std::unique_ptr<Function<dim>> exact_function() const;
    void assemble_cell_conductivities();
    void assemble_heat_load(const double time);
    void make_dirichlet_constraints(const double time);
    void set_initial_condition();
    void set_nodal_state_from_enthalpy();

    // --- enthalpy_step.cc -------------------------------------------------
    EnthalpyStepReport solve_enthalpy_step();
    void               assemble_enthalpy_system(const bool assemble_matrix);
    void               solve_linear_system(Vector &solution);
    void               compute_conductivity_residual(const Vector &theta_ghosted,
                                                     Vector       &result) const;
    unsigned int
    solve_for_pieces(const std::function<LinearPiece(const types::global_dof_index)> &piece_of,
                     Vector                                                          &h_new);
    bool active_set_iteration(EnthalpyStepReport &report);
    unsigned int       relaxation_fallback();
    double             compute_energy_balance();
    const EnthalpyLaw &law(const types::global_dof_index dof) const;

    // --- output.cc --------------------------------------------------------
    void   output_vtu(const unsigned int step);
    void   write_statistics_row(const unsigned int step, const EnthalpyStepReport &report);
    void   accumulate_errors(const double tau);
    void   print_results();
    double liquid_area(const double transition_temperature) const;

    // --- data -------------------------------------------------------------
    const AllParameters &prm;
    MPI_Comm             mpi_communicator;
    ConditionalOStream   pcout;
    TimerOutput          timer;
    Timer                wall_clock;

    parallel::distributed::Triangulation<dim> triangulation;
    FE_Q<dim>                                 fe;
    DoFHandler<dim>                           dof_handler;
    IndexSet                                  locally_owned_dofs, locally_relevant_dofs;

    // Hanging-node constraints alone, the Dirichlet ones on top (rebuilt each step),
    // and the full set used in an active-set iteration (plus the plateau nodes).
    AffineConstraints<double> hanging_node_constraints;
    AffineConstraints<double> dirichlet_constraints;
    AffineConstraints<double> constraints;

    TrilinosWrappers::SparseMatrix system_matrix;
    Vector                         system_rhs;

    // Nodal unknowns: temperature and enthalpy (owned and ghosted), the lumped
    // mass m_i, the heat load F_i of the current step, and the phase state of each
    // node (stored as a double so that it travels with the ghost exchange).
    Vector temperature, temperature_ghosted;
    Vector enthalpy, old_enthalpy, enthalpy_ghosted;
    Vector lumped_mass, heat_load;
    Vector phase_state, phase_state_ghosted;
    // The per-node coefficients of the linear system of one iteration:
    // row i reads m_i d_i Theta_i + tau (A Theta)_i = m_i g_i + tau F_i.
    Vector nodal_diagonal, nodal_diagonal_ghosted, nodal_rhs, nodal_rhs_ghosted;

    // The enthalpy law of each locally relevant node: body laws first, then the
    // mass-weighted sums for nodes shared by bodies with different laws.
    std::vector<EnthalpyLaw>  laws;
    std::vector<unsigned int> law_of_node; // by index within locally_relevant_dofs
    std::map<unsigned int, unsigned int> law_of_body;
    bool phase_change_present = false;
    bool conductivity_depends_on_phase = false;

    // Per-cell operators, by active cell index: conductivity matrix A_K (with the
    // lagged phase mixture), lumped vertex weights m_K and heat load F_K.
    std::vector<LocalMatrix>            cell_conductivity;
    std::vector<dealii::Vector<double>> cell_mass, cell_load;

    // Data functions of x, y, t.
    std::map<unsigned int, std::unique_ptr<Function<dim>>> boundary_functions;
    std::map<unsigned int, std::unique_ptr<Function<dim>>> heat_sources;
    bool heat_load_present = false;
    std::unique_ptr<NeumannSolution> neumann;
    std::unique_ptr<Function<dim>>   exact_temperature;

    double       time, time_step, previous_time_step = 0;
    unsigned int step_number = 0;

    // Output records.
    std::vector<std::pair<double, std::string>> pvd_records;
    double                                     mesh_width = 0;
    std::map<types::global_dof_index, Point<dim>> support_points; // for nodal errors

    // Statistics and accumulated errors.
    double last_l2_error = 0, last_l2_norm = 0, last_max_error = 0;
    double       space_time_error_squared = 0, space_time_norm_squared = 0;
    double       max_energy_residual      = 0;
    unsigned int total_active_set_iterations = 0, steps_with_fallback = 0;
  };
} // namespace ContactStefan

#endif
