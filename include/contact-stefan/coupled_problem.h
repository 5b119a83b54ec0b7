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

#include <deal.II/hp/fe_collection.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/trilinos_vector.h>
#include <deal.II/lac/vector.h>

#include <contact-stefan/enthalpy_law.h>
#include <contact-stefan/neumann_solution.h>
#include <contact-stefan/parameters.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <functional>
#include <map>
#include <set>
#include <memory>
#include <vector>

namespace ContactStefan
{
  using namespace dealii;

  // Tolerances at the level of floating-point round-off (not parameters): a
  // quantity computed from terms of size s is exact to round_off_factor * eps * s.
  constexpr double round_off_factor = 64;

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

  // What one contact step did.
  struct ContactStepReport
  {
    unsigned int iterations   = 0;
    unsigned int active_nodes = 0; // obstacle and interface nodes in contact
    unsigned int changes      = 0; // summed over the iterations
    unsigned int c_reductions = 0; // cycling remedies applied
    double       max_pressure = 0;
    // Total compressive normal force per obstacle boundary / interface.
    std::map<std::string, double> forces;
  };

  // A node with a normal condition: a roller (u.n = 0), a rigid obstacle
  // (u.n <= g) or a contact interface between bodies k and l
  // ((u_k - u_l).n <= g, n pointing out of body k, k the smaller body id).
  struct NormalCondition
  {
    enum class Kind
    {
      roller,
      interface,
      obstacle
    } kind;
    std::string                   group; // "boundary N" or "interface k-l"
    unsigned int                  boundary_id; // roller and obstacle nodes
    Point<2>                      position;
    std::array<std::uint64_t, 2>  dofs_k, dofs_l;
    bool                          has_partner;
    std::array<double, 2>         normal;
    double                        weight;
    double                        stiffness; // normal diagonal of the stiffness matrix
    double                        gap = 0;   // g at the current time
    bool                          corner = false; // faces disagree by more than the corner angle
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

    // --- mechanics.cc -----------------------------------------------------
    void setup_mechanical_system();
    void assemble_cell_stiffness();
    void assemble_mechanical_load(const double time);
    void make_fixed_mechanical_constraints(const double time);
    void find_normal_conditions();

    // --- contact_step.cc --------------------------------------------------
    ContactStepReport solve_contact_step();
    void              build_contact_constraints(unsigned int &n_skipped);
    void              assemble_mechanical_system();
    void              solve_mechanical_linear_system();
    void              compute_mechanical_residual(Vector &residual) const;
    void              update_condition_gaps();
    void              check_rigid_body_modes() const;
    double            normal_displacement_jump(const NormalCondition &c) const;

    // --- enthalpy_step.cc -------------------------------------------------
    EnthalpyStepReport solve_enthalpy_step();
    void               assemble_enthalpy_system(const bool assemble_matrix);
    void               solve_linear_system(Vector &solution);
    void               solve_linear(const TrilinosWrappers::SparseMatrix &A, Vector &x, const Vector &b) const;
    void               compute_conductivity_residual(const Vector &theta_ghosted,
                                                     Vector       &result,
                                                     const bool    absolute = false) const;
    unsigned int
    solve_for_pieces(const std::function<LinearPiece(const types::global_dof_index)> &piece_of,
                     Vector                                                          &h_new);
    bool active_set_iteration(EnthalpyStepReport &report);
    unsigned int       relaxation_fallback();
    double             compute_energy_balance();
    const EnthalpyLaw &law(const types::global_dof_index dof) const;

    // --- output.cc --------------------------------------------------------
    void   output_vtu(const unsigned int step);
    void   write_statistics_row(const unsigned int        step,
                                const EnthalpyStepReport &report,
                                const ContactStepReport  &contact_report);
    void   print_mechanical_results();
    void   accumulate_errors(const double tau);
    void   print_results();
    double liquid_area(const double transition_temperature) const;
    double total_enthalpy() const;

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
    Vector nodal_diagonal, nodal_rhs;

    // The enthalpy law of each locally relevant node: body laws first, then the
    // mass-weighted sums for nodes shared by bodies with different laws.
    std::vector<EnthalpyLaw>  laws;
    std::vector<unsigned int> law_of_node; // by index within locally_relevant_dofs
    std::map<unsigned int, unsigned int> law_of_body;
    bool phase_change_present = false;
    bool conductivity_depends_on_phase = false;

    // Per-cell operators, by active cell index: conductivity matrix A_K (with the
    // lagged phase mixture), lumped vertex weights m_K and heat load F_K.
    std::vector<LocalMatrix>            cell_conductivity, cell_shape_conductivity;
    std::vector<dealii::Vector<double>> cell_mass, cell_load;

    // --- Mechanics: displacement on an hp DoFHandler whose element on body b is
    // FE_Q(1)^dim in body b's slot of components and FE_Nothing elsewhere, so
    // that each body has its own displacement on an interface. -----------------
    hp::FECollection<dim>                 mechanical_fe;
    DoFHandler<dim>                       mechanical_dof_handler;
    IndexSet                              mechanical_owned, mechanical_relevant;
    std::map<unsigned int, unsigned int>  body_slot; // material id -> slot
    AffineConstraints<double>             mechanical_hanging, mechanical_fixed, mechanical_constraints;
    TrilinosWrappers::SparseMatrix        mechanical_matrix;
    Vector                                mechanical_rhs, mechanical_load, stiffness_diagonal;
    Vector                                displacement, displacement_ghosted;
    std::vector<LocalMatrix>              cell_stiffness;
    std::vector<dealii::Vector<double>>   cell_mechanical_load;
    bool                                  mechanical_load_present = false;
    std::vector<NormalCondition>          normal_conditions;
    std::vector<std::string>              contact_groups; // on every rank, sorted
    std::map<std::string, unsigned int>   placed_per_group; // owned active conditions imposed
    std::set<std::pair<std::uint64_t, int>> imposed_conditions; // (dofs_k[0], kind) imposed
    // Body slot, component and position of every locally relevant displacement
    // DoF, and per slot the centre and size of the body (for its rotation mode).
    struct DofInfo
    {
      unsigned int slot, component;
      Point<dim>   position;
    };
    std::unordered_map<types::global_dof_index, DofInfo> dof_info;
    std::vector<std::pair<Point<dim>, double>>      body_frame;
    std::vector<std::pair<Point<dim>, Point<dim>>>  body_box; // bounding box per slot
    double body_height(const unsigned int slot) const
    {
      return body_box[slot].second[1] - body_box[slot].first[1];
    }
    // Active flags (1 or 0) at the x DoF of side k, owned and ghosted, for the
    // obstacle and the interface conditions.
    Vector obstacle_active, obstacle_active_ghosted, interface_active, interface_active_ghosted;
    // Nodal contact pressure and gap for output (at the x DoF of side k).
    Vector contact_pressure, contact_gap;
    double complementarity_scale = 1; // divided by 10 per cycling remedy
    ContactStepReport last_contact_report;

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
    double initial_total_enthalpy = 0;
    double       space_time_error_squared = 0, space_time_norm_squared = 0;
    double       max_energy_residual      = 0;
    unsigned int total_active_set_iterations = 0, steps_with_fallback = 0;
    unsigned int inconsistent_enthalpy_nodes = 0; // h not in H(Theta) at the end of a step
    unsigned int total_contact_iterations = 0, max_contact_iterations = 0, first_contact_iterations = 0;
    unsigned int max_contact_iterations_warm = 0; // over the steps after the first
  };
} // namespace ContactStefan

#endif
