// ThermalField: the temperature/enthalpy field and the enthalpy (Stefan) step.
//
// It owns everything of the heat problem on the shared triangulation: the scalar
// FE_Q(1) DoFHandler, the hanging-node, Dirichlet and plateau constraints, the
// system matrix, the nodal vectors, the enthalpy law of every node and the
// per-cell operators (lumped mass, conductivity, heat load). The coupled problem
// drives it through the step contract of doc/architecture.md:
//
//   setup_dofs()             mesh-dependent structures; rebuilds every per-cell
//                            cache and every nodal law (call after any mesh change)
//   initialize(t0)           initial enthalpy from the initial condition
//   begin_time_step(t, tau)  old enthalpy, warm start of the phase states, the
//                            conductivity (if it depends on the phase), heat load
//                            and Dirichlet data at t
//   solve()                  the enthalpy step; repeatable within a time step
//   primary_state()          h and h_old: all that survives a mesh change
//   after_transfer()         temperature and phase states re-derived from h
//
// The enthalpy step itself (the primal-dual active-set method with its line
// search, and the relaxation fallback) is in thermal_field/enthalpy_step.cc; the set-up in
// thermal_field/setup.cc, its side of the coupling in thermal_field/coupling.cc.
// doc/algorithms.md explains the method.
//
// Interfaces whose 'Thermal contact' is 'conductance' (doc/interface_heat.md,
// thermal_field/interface_heat.cc) give each side its own temperature: the
// DoFHandler is then an hp one whose element on a body is FE_Q(1) in the
// body's slot of components and FE_Nothing in the others (step-46's device,
// as the mechanical field does), with as few slots as the conductance
// interfaces need; bodies in perfect contact share a slot and their nodes.
// A scene without conductance interfaces has one slot: the plain FE_Q(1).
#ifndef contact_stefan_thermal_field_h
#define contact_stefan_thermal_field_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_q.h>

#include <deal.II/hp/fe_collection.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <contact-stefan/core/body_recovery.h>
#include <contact-stefan/core/common.h>
#include <contact-stefan/core/enthalpy_law.h>
#include <contact-stefan/core/interface_conductance.h>
#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/parameters.h>
#include <contact-stefan/core/scene_context.h>
#include <contact-stefan/core/scene_functions.h>
#include <contact-stefan/interfaces/body_interface.h>
#include <contact-stefan/interfaces/mortar_interface.h>
#include <contact-stefan/linear_algebra/linear_solver.h>
#include <contact-stefan/thermal/enthalpy_step_parameters.h>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include <Epetra_Import.h>
#include <Epetra_Vector.h>

namespace ContactStefan
{
  /** What one enthalpy step did, for the screen and the statistics table. */
  struct EnthalpyStepReport
  {
    unsigned int active_set_iterations = 0;
    unsigned int damped_steps          = 0; // iterations whose Newton step was shortened
    unsigned int relaxation_iterations = 0; // > 0 only if the fallback ran
    unsigned int plateau_nodes         = 0;
    unsigned int state_changes         = 0;     // summed over the iterations
    double       energy_residual       = 0;     // relative, see compute_energy_balance()
    unsigned int inconsistent_nodes    = 0;     // free nodes with h not in H(Theta) at the end
    unsigned int factorisations        = 0;     // matrices factorised (reused otherwise)
    double       thermoelastic_heat    = 0;     // -sum_i G_i, J per unit thickness
    bool         truncated_newton      = false; // solved by it (it converged)
    LinearSolverStatistics linear;                        // the linear solver's work
  };

  /**
   * The heat through one conductance interface at the end of a solve: the
   * rate from side k to side l (W per m of thickness) in total and by term,
   * and the mean of h over the interface (W/(m^2 K)), weighted by length.
   */
  struct InterfaceHeat
  {
    std::string      name; // "interface k-l"
    double           rate = 0, mean_conductance = 0;
    ConductanceTerms rates; // the rate of each term (W/m)
  };

  template <int dim>
  class ThermalField
  {
  public:
    /**
     * prm: the scene; step_prm: the enthalpy step's own entries; linear_prm:
     * the shared linear-solver entries; verbosity: Output/Verbosity.
     */
    ThermalField(const SceneContext<dim>         &context,
                 const Parameters::EnthalpyStep  &step_prm,
                 const Parameters::LinearSolvers &linear_prm);

    // --- the step contract ----------------------------------------------------
    void                  setup_dofs();
    void                  initialize(const double t0);
    void                  begin_time_step(const double t, const double tau);
    EnthalpyStepReport    solve();
    std::vector<Vector *> primary_state(); // {h, h_old}, owned vectors
    void                  after_transfer();
    /**
     * Large sliding (doc/contact.md): where set_up_dofs() couples the mortar
     * sides of 'Mortar sliding = large' interfaces (null or empty: on the
     * mesh), the configuration the mechanical field's set-up uses too.
     */
    void set_mortar_configuration(const MortarConfiguration *configuration)
    {
      mortar_configuration = configuration;
    }
    /**
     * Forget factorisations, preconditioners and the last solution, as a new
     * set-up does. A checkpoint calls it (after re-deriving the state with
     * after_transfer()), so that the steps after it do exactly the work of a
     * run resumed from it.
     */
    void restart_solvers()
    {
      have_factorisation  = false;
      have_preconditioner = false;
      linear_solver.clear();
    }
    /**
     * Adds temperature, enthalpy, phase index and liquid fraction. The vectors
     * stay alive in this object until the next call.
     */
    void add_output(DataOut<dim> &data_out) const;
    /**
     * The heat flux -k K grad(Theta) at the centre of each owned cell (zero
     * elsewhere), with the cell's conductivity as the step used it.
     */
    std::vector<std::array<double, 2>> cell_centre_heat_flux() const;
    /**
     * Visit every vertex of every owned cell with its vertex-rule weight and
     * the recovered heat flux of the cell's body there (the L2 error of the
     * recovered field by the vertex rule). Collective (the recovery).
     */
    void for_each_recovered_vertex_heat_flux(
      const std::function<
        void(const Point<dim> &, double, const std::array<double, 2> &, const Point<dim> &)> &visit)
      const;

    // --- coupling (doc/coupling.md) -------------------------------------------------
    // Per-cell vertex arrays indexed by active cell index (owned cells only);
    // vertex v of a cell is its v-th FE_Q(1) DoF.
    // Theta at the vertices of each owned cell (the current temperature).
    void cell_temperatures(CellVertexValues &theta) const;
    /**
     * The phase weights of each owned cell (one per phase of its body): the
     * phase fractions of its nodes at the previous time level, averaged.
     */
    void cell_phase_weights(std::vector<std::vector<double>> &weights) const;
    /**
     * Per owned cell and vertex, the solid fraction of the node (current
     * enthalpy) with respect to the last transition of the cell's body: 1
     * minus the node's fraction through that transition temperature (1 for a
     * body without transitions). With crossing: also the fraction s in [0, 1]
     * of the last step (old to current enthalpy, linear in time) at which the
     * node's enthalpy passed the value where its solid fraction is the body's
     * 'Solid fraction at birth' (1 if it did not move). What decides the
     * births of doc/solidification.md.
     */
    void cell_solid_fractions(CellVertexValues &solid, CellVertexValues *crossing = nullptr) const;
    /**
     * The thermoelastic work at the vertices (MechanicalField::thermoelastic_work):
     * times the absolute Theta_0 it is the heat G the step's strain increment
     * takes out of each node, m_i (h_i - h_i^old) + tau (A Theta)_i + G_i = tau F_i.
     */
    void set_thermoelastic_work(const CellVertexValues &work);
    /**
     * -sum_i G_i: the heat the step's strain increment released (J per unit
     * thickness; > 0 under compression, < 0 where the body expands).
     */
    double thermoelastic_heat() const;
    /**
     * The largest gamma / rho c over the bodies and phases, gamma = Theta_0^abs
     * beta : C^{-1} : beta: the contraction factor of the coupled step's lag.
     */
    double coupling_strength() const
    {
      return max_coupling_strength;
    }

    // --- the block correction of the coupling (coupled_block.h) ---------------
    // The system matrix of the last linear solve (Dirichlet and plateau values
    // eliminated), its fingerprint, the constraints of that solve, and the
    // absolute Theta_0 at the vertices of each owned cell.
    const TrilinosWrappers::SparseMatrix &get_system_matrix() const
    {
      return system_matrix;
    }
    std::uint64_t get_matrix_signature() const
    {
      return matrix_signature;
    }
    const AffineConstraints<double> &get_constraints() const
    {
      return constraints;
    }
    const CellVertexValues &get_absolute_reference() const
    {
      return cell_absolute_reference;
    }
    /**
     * The start of the next linear solve of the enthalpy step (the block
     * correction of the coupling). A guess that already solves that system to
     * 'Solver/CG tolerance' (relative residual of the free rows) stands without a linear solve,
     * on the direct path too, as the contact step's does. Only the starting
     * point: the phase states stay.
     */
    void set_initial_guess(const Vector &theta)
    {
      temperature   = theta;
      guess_pending = true;
    }
    /** How many linear solves a guess answered without solving. */
    unsigned int n_guesses_accepted() const
    {
      return guesses_accepted;
    }
    /**
     * The values of a nodal vector (all relevant entries readable) at the
     * vertices of each owned cell.
     */
    void cell_values(const Vector &theta, CellVertexValues &values) const;

    // --- conductance interfaces (thermal_field/interface_heat.cc) ---------------
    bool has_conductance_interfaces() const
    {
      return !conductance_interfaces.empty();
    }
    /** Whether a conductance changes with the gap or pressure of the contact step. */
    bool conductance_depends_on_contact() const;
    /**
     * The contact step's state at the interface vertices (gap, pressure,
     * closed), read by the conductances of the next solve(). Without it (no
     * mechanics) the interface's Gap function stands in: closed where <= 0.
     */
    void set_interface_contact(const InterfaceContactStates &states)
    {
      interface_contact      = states;
      have_interface_contact = true;
    }
    /** The heat through each conductance interface. Collective. */
    std::vector<InterfaceHeat> interface_heat() const;

    // --- queries ----------------------------------------------------------------
    // Incremented by every setup_dofs(): caches of mesh data compare it.
    unsigned int mesh_generation() const
    {
      return n_setups;
    }
    const DoFHandler<dim> &get_dof_handler() const
    {
      return dof_handler;
    }
    const Vector &get_temperature() const // ghosted
    {
      return temperature_ghosted;
    }
    const Vector &get_enthalpy() const // owned
    {
      return enthalpy;
    }
    const Vector &get_lumped_mass() const // owned, hanging nodes condensed
    {
      return lumped_mass;
    }
    const EnthalpyLaw &law(const types::global_dof_index dof) const;
    /** Where each DoF of a locally owned cell sits (the nodes of the mesh). */
    const std::map<types::global_dof_index, Point<dim>> &get_support_points() const
    {
      return support_points;
    }
    bool phase_change_present() const
    {
      return materials.phase_change_present();
    }
    // --- adaptivity (doc/adaptivity.md) ----------------------------------------
    // Centres of the owned cells that carry a phase front: nodes in different
    // phases, or a node on a plateau.
    void front_points(std::vector<Point<dim>> &points) const;
    /**
     * One entry per locally owned node, nonzero within `layers` matrix
     * neighbours of a phase front (a node on a plateau, or one with a
     * neighbour of the same material in another phase): the rows the next
     * active sets change, which the
     * direct solver orders last (LinearSolver::set_volatile_rows). Empty on
     * several ranks (the direct path there is not CHOLMOD's).
     */
    std::vector<char> volatile_rows(const unsigned int layers) const;
    /**
     * The Kelly jump indicator of the temperature, per active cell (zero on
     * cells that are not owned).
     */
    void error_indicator(dealii::Vector<float> &indicator) const;

    /**
     * What a restart needs besides the primary state: whether a step was taken,
     * the length of the last one (the warm start extrapolates from it), and
     * whether the steps start with the truncated Newton method (large-step mode).
     */
    std::vector<double> restart_state() const
    {
      return {first_step ? 1. : 0., previous_time_step, large_step_mode ? 1. : 0.};
    }
    void set_restart_state(const std::vector<double> &state)
    {
      first_step         = state.at(0) != 0;
      previous_time_step = state.at(1);
      large_step_mode    = state.at(2) != 0;
    }

    /** sum_i m_i h_i: the heat content (J per unit thickness) of the mesh. */
    double total_enthalpy() const;
    /** sum_i m_i (fraction of node i through the transition at T). */
    double liquid_area(const double transition_temperature) const;
    /** sum_i m_i (liquid fraction of node i): the melt area. */
    double melt_area() const;
    /**
     * The largest change of a free node's temperature (K) and of a node's
     * phase index between the old and the current enthalpy: what the adaptive
     * step control measures (core/step_control.h). Nodes with a prescribed
     * temperature do not count: their change is data. Collective.
     */
    std::pair<double, double> step_change() const;
    /** A one-line description of what the field will do, for the start of a run. */
    std::string describe() const;
    /**
     * A warning if cells give the conductivity matrix positive off-diagonal
     * entries (cells far from square), empty if none do. Collective.
     */
    std::string mesh_warning() const;
    /**
     * result = A theta (hanging-node condensed), integrated cell by cell from
     * the A_K, independently of the assembled matrix the step itself uses (the
     * field tests probe the conductivity with it).
     */
    void apply_conductivity(const Vector &theta_ghosted, Vector &result) const;

  private:
    using LocalMatrix = FullMatrix<double>;

    /** thermal_field/setup.cc */
    void setup_nodal_enthalpy_laws();
    /** initialize(): the lumped-mass mean of the bodies' initial enthalpies
     *  at a node they share, where their values differ (setup.cc). */
    void mix_initial_enthalpy_at_shared_nodes(const Function<dim>     &f,
                                              const bool               from_temperature,
                                              const std::vector<bool> &two_sided);
    void assemble_cell_conductivities();
    void assemble_heat_load();
    void make_dirichlet_constraints();
    void set_nodal_state_from_enthalpy();
    void setup_coupling();
    /** Phase weights of one owned cell of the given enthalpy (ghosted). */
    void phase_weights(const typename DoFHandler<dim>::active_cell_iterator &cell,
                       const Vector                                         &h,
                       std::vector<double>                                  &weights) const;
    /** The heat a node receives in the step: tau F_i - G_i. */
    double step_heat(const types::global_dof_index dof) const
    {
      return time_step * heat_load[dof] - coupling_heat[dof];
    }

    /** thermal_field/enthalpy_step.cc */
    void assemble_conductivity_matrix();
    void assemble_step_load();
    void assemble_system(const bool assemble_matrix);
    /**
     * result = A Theta (hanging nodes condensed) for the current temperature,
     * from the assembled A.
     */
    void conductivity_times(Vector &result) const;
    /**
     * A Theta and, entrywise, |A| |Theta| (the size of the terms against which
     * the round-off of (A Theta)_i is measured), in one pass over the rows.
     */
    void conductivity_times(Vector &product, Vector &absolute_product) const;
    /**
     * Imports owned values (one per row of the conductivity matrix) onto its
     * column map.
     */
    void to_columns(const Epetra_Vector &values, std::vector<double> &result) const;
    /**
     * ghosted <- values (an owned vector), the ghost entries included, through
     * ghost_import. Collective.
     */
    void to_ghosted(const Vector &values, Vector &ghosted) const;
    /**
     * One linear solve with every node on the linear piece of its current
     * phase state: the plateau constraints come from phase_state_ghosted, the
     * nodal diagonal and right-hand side from phase_state, so every write to
     * phase_state must be copied to phase_state_ghosted before the call.
     */
    unsigned int solve_for_pieces(Vector &h_new, const double tolerance = 0);
    /** At most max_iterations solves; false if the set did not settle. */
    bool active_set_iteration(EnthalpyStepReport &report, const unsigned int max_iterations);
    /**
     * The steps of one active-set iteration: the size of the enthalpy changes
     * that matter; and, collective, whether every free node of the Newton
     * target h_new lies on the piece it was computed with, whether the step to
     * it moves no enthalpy beyond round-off, the Armijo line search's step
     * length along it, and taking the (damped) step and moving the nodes to
     * their new pieces (returns the free nodes that moved).
     */
    double       enthalpy_change_scale() const;
    bool         newton_target_consistent(const Vector &h_new) const;
    bool         newton_step_negligible(const Vector &h_new, const double enthalpy_scale) const;
    double       line_search_step(const Vector &h_new, const Vector &z) const;
    unsigned int take_step_and_update_states(const Vector &h_new, Vector &z, const double alpha);
    /** thermal_field/enthalpy_newton.cc: the truncated nonsmooth Newton method in Theta. */
    bool truncated_newton_iteration(EnthalpyStepReport &report);
    /**
     * One forward nonlinear Gauss-Seidel sweep over the free owned nodes
     * (ghost values held fixed); theta is owned, hanging nodes distributed.
     */
    void gauss_seidel_sweep(Vector &theta);
    /**
     * Exact minimisation of the step functional on theta + alpha v, alpha in
     * [0, 1]; theta moves there, nodes the minimiser stops at snapped onto
     * their transition temperature. Returns alpha.
     */
    double       exact_line_search(Vector &theta, const Vector &v);
    unsigned int relaxation_fallback();
    double       compute_energy_balance(unsigned int &inconsistent_nodes) const;

    /**
     * thermal_field/mortar.cc: the hanging-node constraints and, for every
     * mortar interface in perfect thermal contact, one line per coupled slave
     * node Theta_j = sum_m (M_jm / D_j) Theta_m (its master DoFs join the
     * locally relevant set first).
     */
    void make_node_constraints();
    /**
     * The law through which a coupled slave node's interpolated enthalpy is
     * read (its phase, its melt share): its masters' laws mixed with the
     * line's positive weights, which on matching sides is its partner's law,
     * as at a node the two bodies share.
     */
    void set_mortar_slave_laws();
    /**
     * After a step: a coupled slave node's enthalpy is the line's
     * interpolation of its masters' (as on a new mesh, after_transfer()),
     * not its law's enthalpy at the interpolated temperature, which on a
     * plateau would be an end of it; its phase state follows.
     */
    void interpolate_mortar_slave_enthalpies();
    /**
     * With thermal mortar lines: every free node's lumped mass is > 0 after
     * the slave nodes handed theirs to their masters (the dual weights can
     * be negative); else the run stops, naming the node (collective).
     */
    void check_condensed_mass() const;
    /** Whether a mortar interface is in perfect thermal contact (all ranks). */
    bool have_thermal_mortar = false;
    /** The lines of make_node_constraints() on the relevant slave DoFs. */
    std::vector<
      std::pair<types::global_dof_index, std::vector<std::pair<types::global_dof_index, double>>>>
      mortar_lines;

    /** thermal_field/interface_heat.cc */
    /** interfaces: the mesh's (find_body_interfaces), found once per set-up. */
    void setup_slots(const std::vector<BodyInterface<dim>> &interfaces);
    void setup_conductance_nodes(const std::vector<BodyInterface<dim>> &interfaces);
    void add_conductance_sparsity(DynamicSparsityPattern &dsp) const;
    /**
     * h at every node from the current state; moves conductivity_version if
     * it changed. Returns the largest change of h relative to the largest h
     * (collective).
     */
    double update_conductances();
    /** One enthalpy step with the conductances as they are (solve() above it). */
    EnthalpyStepReport solve_enthalpy_step();
    /** Adds the interface terms to A (assembled) or to result = A theta (theta ghosted). */
    void add_conductance_matrix(TrilinosWrappers::SparseMatrix &matrix) const;
    void add_conductance_product(const Vector &theta, Vector &result) const;

    const SceneParameters                           &prm;
    const Parameters::EnthalpyStep                  &step_prm;
    const unsigned int                               verbosity;
    const Materials                                 &materials;
    SceneFunctions<dim>                             &functions;
    const parallel::distributed::Triangulation<dim> &triangulation;
    const MPI_Comm                                   mpi_communicator;
    TimerOutput                                     &timer;
    const ConditionalOStream                        &pcout;

    const FE_Q<dim> fe; // the element of every slot (FEValues are built on it)
    /**
     * The element of each slot (one slot: fe itself), the slot of each body,
     * and which slot each cell's active FE index names.
     */
    hp::FECollection<dim>                fe_collection;
    std::map<unsigned int, unsigned int> slot_of_body;
    unsigned int                         n_slots = 1;
    DoFHandler<dim>                      dof_handler;

    /**
     * The conductance interfaces: their bodies and laws; and one node per
     * interface vertex of the owned cells, with the two sides' DoFs, the
     * lumped weight (half its faces' length), which of the DoFs this rank owns
     * (it writes their rows; the node's heat is counted by the owner of
     * dof_k) and the terms of h of the last update.
     */
    struct ConductanceInterface
    {
      unsigned int                    body_k, body_l;
      std::string                     name;
      std::unique_ptr<ConductanceLaw> law;
      /** Discretisation = mortar: its nodes are mortar_conductance_nodes. */
      bool mortar = false;
    };
    struct ConductanceNode
    {
      unsigned int            interface, vertex;
      Point<dim>              position, centre_k, centre_l; // and the two sides' cell centres
      types::global_dof_index dof_k, dof_l;
      double                  weight;
      bool                    owned_k, owned_l; // this rank owns the DoF

      ConductanceTerms h;
    };
    std::vector<ConductanceInterface> conductance_interfaces;
    std::vector<ConductanceNode>      conductance_nodes;
    /**
     * Gap, pressure and closed flag of a node (key: its vertex, or its slave
     * node number on a mortar interface) into state.
     */
    void contact_state(const ConductanceInterface &interface,
                       const unsigned int          key,
                       const Point<dim>           &position,
                       ConductanceState           &state) const;
    /**
     * A coupled slave node of a mortar interface with a conductance
     * (thermal_field/mortar.cc): its number j in the interface's coupling
     * (the contact step's key for its state), its DoF, D_j, the pair weights
     * W_jm of its master DoFs (interfaces/mortar.h), whether the slave is
     * body k, and the terms of h of the last update. Every rank keeps every
     * node (their DoFs are all locally relevant), evaluates h alike and
     * writes the rows it owns.
     */
    struct MortarConductanceNode
    {
      unsigned int                                            interface, node;
      Point<dim>                                              position;
      types::global_dof_index                                 dof;
      double                                                  D;
      std::vector<std::pair<types::global_dof_index, double>> masters;
      bool                                                    slave_is_k;
      ConductanceTerms                                        h;
    };
    std::vector<MortarConductanceNode> mortar_conductance_nodes;
    /**
     * The nodes of the mortar conductance interfaces and where a function
     * is evaluated for each (interface_side_offset into a cell of its side).
     * Adds their DoFs to 'dofs' (for the locally relevant set).
     */
    void couple_mortar_conductances(IndexSet &dofs);
    std::vector<std::pair<types::global_dof_index, Point<dim>>> mortar_interface_points;
    /** The state of a mortar node: (T, liquid fraction) of side k and side l. */
    ConductanceState mortar_conductance_state(const MortarConductanceNode &node,
                                              const Vector                &h_old) const;
    /**
     * Where a function is evaluated for a node: the vertex, or for a node on a
     * conductance interface the point interface_side_offset of the way from
     * the vertex to the centre of a cell of its side (interface_point; per
     * mesh; interfaces/body_interface.h).
     */
    std::map<types::global_dof_index, Point<dim>> interface_point;
    Point<dim> node_point(const types::global_dof_index dof, const Point<dim> &vertex) const
    {
      const auto it = interface_point.find(dof);
      return it == interface_point.end() ? vertex : it->second;
    }
    InterfaceContactStates            interface_contact;
    bool                              have_interface_contact = false;
    /** Scheme = fixed point and an h that depends on temperatures or phases. */
    bool            iterate_conductances = false;
    const MortarConfiguration *mortar_configuration = nullptr;
    IndexSet        owned, relevant;

    /**
     * Hanging-node constraints alone (with the lines of mortar interfaces in
     * perfect thermal contact: a coupled slave node is a hanging node of the
     * master side), the Dirichlet ones on top (rebuilt each step), and the
     * full set of one active-set iteration (plus the plateau nodes).
     */
    AffineConstraints<double> hanging_node_constraints, dirichlet_constraints, constraints;

    TrilinosWrappers::SparseMatrix system_matrix;
    Vector                         system_rhs;
    /**
     * A itself (hanging nodes condensed, no other constraint), assembled when
     * conductivity_version moves; the load tau F - G of the current solve();
     * per column of the matrix, the prescribed value of that node (NaN: free).
     */
    TrilinosWrappers::SparseMatrix conductivity_matrix;
    unsigned int                   conductivity_matrix_version = 0;
    Vector                         step_load;
    std::vector<double>            fixed_column_value;
    // (Scratch of the row loops: column_values holds |Theta| or another
    // imported vector, signed_column_values Theta.)
    mutable std::vector<double>    column_values, signed_column_values;
    LinearSolver                   linear_solver;
    // set_initial_guess(): a guess to test before the next linear solve, the
    // relative residual that lets it stand, and how many stood.
    const double guess_tolerance;
    bool         guess_pending    = false;
    unsigned int guesses_accepted = 0;

    /** Primary state: the nodal enthalpy now and at the previous time level. */
    Vector enthalpy, old_enthalpy;
    /**
     * Derived state: Theta = beta(h) and the phase state of each node (stored as
     * a double so that it travels with the ghost exchange), owned and ghosted.
     */
    Vector temperature, temperature_ghosted, enthalpy_ghosted;
    Vector phase_state, phase_state_ghosted;
    /**
     * The exchange from the owned vectors' layout to the ghosted ones' (the
     * same for all of them), built with the DoFs: deal.II's assignment of an
     * owned vector to a ghosted one builds it afresh, which cost a few per cent
     * of the Stefan strip's run (the owned-to-ghosted copies of every
     * active-set iteration).
     */
    std::unique_ptr<Epetra_Import> ghost_import;
    /**
     * Per-node data: lumped mass m_i, heat load F_i of the step, and the
     * coefficients of one iteration's system m_i d_i Theta_i + tau (A Theta)_i =
     * m_i g_i + tau F_i.
     */
    Vector lumped_mass, heat_load, nodal_diagonal, nodal_rhs;
    /**
     * The truncated Newton method's first iterate: Theta of the enthalpy
     * extrapolated by begin_time_step().
     */
    Vector predicted_temperature;
    /**
     * The thermoelastic heat G of the step (condensed) and its cell parts G_K,
     * the absolute Theta_0 at the vertices, and whether the scene has the term.
     */
    Vector                              coupling_heat;
    std::vector<dealii::Vector<double>> cell_heating;
    CellVertexValues                    cell_absolute_reference;
    const bool                          heating;
    double                              max_coupling_strength = 0;

    /**
     * The matrix last factorised: its fingerprint (tau, conductivity version,
     * constraint pattern, nodal diagonal), so that an unchanged one is reused.
     */
    unsigned int  conductivity_version    = 0;
    bool          have_factorisation      = false;
    std::uint64_t factorisation_signature = 0;
    /**
     * The values the system matrix holds (after solves that borrowed the AMG
     * hierarchy, not those of factorisation_signature).
     */
    std::uint64_t matrix_signature = 0;
    /** The operator (tau, conductivity) the AMG hierarchy was built for. */
    bool          have_preconditioner      = false;
    std::uint64_t preconditioner_signature = 0;
    unsigned int  n_factorisations         = 0; // in the current solve()

    /**
     * The enthalpy law of each locally relevant node: body laws first, then the
     * mass-weighted sums for nodes shared by bodies with different laws.
     */
    std::vector<EnthalpyLaw>             laws;
    std::vector<unsigned int>            law_of_node; // index within `relevant`
    std::map<unsigned int, unsigned int> law_of_body;

    /**
     * Per-cell operators by active cell index: the conductivity shape matrix
     * S_K (per mesh), A_K = k_K S_K (with the lagged phase mixture), the lumped
     * vertex weights m_K and the heat load F_K.
     */
    std::vector<LocalMatrix> cell_shape_conductivity, cell_conductivity;
    /** k_K of each owned cell (A_K = k_K S_K): the heat flux of the output. */
    std::vector<double>                           cell_conductivity_factor;
    std::vector<dealii::Vector<double>>           cell_mass, cell_load;
    std::map<types::global_dof_index, Point<dim>> support_points;

    /**
     * Direct access to the entries of the per-node loops. The owned DoFs are
     * one contiguous range (p4est numbering), so owned entry dof of an owned
     * vector is its local entry dof - first_owned; for relevant node k (k-th
     * element of `relevant`) relevant_entry[k] is its local entry in a ghosted
     * vector. Per owned node: its law and whether it is free (no Dirichlet
     * value). Element access through TrilinosWrappers maps every index through
     * Epetra's hash table: 13 % of a Stefan strip run before these.
     */
    types::global_dof_index first_owned = 0;
    unsigned int            n_owned     = 0;
    std::vector<int>        relevant_entry;
    /**
     * Per owned cell (by active cell index): the relevant-node numbers k of its
     * vertices.
     */
    std::vector<std::array<unsigned int, GeometryInfo<dim>::vertices_per_cell>> cell_nodes;
    /**
     * The melt area's weights, per mesh: for each body law with a transition,
     * its melting temperature and, per relevant node k, the lumped mass the
     * node carries in the owned cells of bodies with that law.
     */
    std::vector<std::pair<double, std::vector<double>>> melt_weights;
    /**
     * The nodes of each temperature boundary, per mesh: (id, [(DoF, vertex)]) in
     * the order of the boundaries; the DoFs of the non-artificial cells' faces.
     */
    std::vector<
      std::pair<types::boundary_id, std::vector<std::pair<types::global_dof_index, Point<dim>>>>>
                              dirichlet_nodes;
    std::vector<unsigned int> owned_law;
    std::vector<char>         owned_free;
    /**
     * Per owned row, per mesh: a hanging node?, and the local column index of
     * its diagonal entry in system_matrix and conductivity_matrix (the same
     * layout).
     */
    std::vector<char>         owned_hanging;
    std::vector<int>          owned_diagonal_column;
    void                      index_local_entries();
    static double            *entries(Vector &v)
    {
      return v.trilinos_vector()[0];
    }
    static const double *entries(const Vector &v)
    {
      return v.trilinos_vector()[0];
    }
    const EnthalpyLaw &owned_node_law(const unsigned int i) const
    {
      return laws[owned_law[i]];
    }

    unsigned int n_setups = 0;
    double       time = 0, time_step = 0, previous_time_step = 0;
    bool         first_step = true; // no previous step to extrapolate from
    /** Whether the warm start of this step moved a node to another piece. */
    bool predicted_set_changed = false;
    /**
     * With 'Enthalpy solver = active-set': whether a step was handed over to
     * the truncated Newton method ('Truncated Newton hand-over') and no step
     * since has handed back; the next step then starts with it.
     */
    bool large_step_mode = false;
    /**
     * The mode of the current step (set by begin_time_step(), and by a
     * hand-over within the step, so that later passes of a coupling loop use
     * the method that solved the first), and whether solve() has not yet run
     * in this step (the truncated Newton method starts later passes from the
     * last pass's temperature).
     */
    bool step_in_large_step_mode = false, first_pass_of_step = true;

    /** Output fields, alive until the next add_output(). */
    mutable Vector                                output_phase_index, output_liquid_fraction;
    mutable std::array<dealii::Vector<double>, 2> output_heat_flux; // cell data
    // The recovered heat flux: each body's own nodes (built at the first use).
    mutable std::unique_ptr<BodyRecovery<dim>> heat_flux_recovery;
    void recover_heat_flux(const std::vector<std::array<double, 2>> &flux) const;
    mutable std::vector<std::shared_ptr<DataPostprocessor<dim>>> output_slot_sums; // SlotSum
  };
} // namespace ContactStefan

#endif
