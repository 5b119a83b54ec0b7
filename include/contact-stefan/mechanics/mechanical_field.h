// MechanicalField: the displacement field and the contact step.
//
// It owns everything of the elasticity/contact problem on the shared
// triangulation: the hp DoFHandler (FE_Q(1)^2 in each body's slot, FE_Nothing
// elsewhere, so that each body has its own displacement on an interface), the
// fixed constraints (hanging nodes, prescribed displacements, ties, rollers),
// the contact constraints of the current active set, the stiffness matrix, the
// per-cell stiffness and load, the nodes that carry a normal condition and the
// per-body frames of the rigid-mode check. The coupled problem drives it through
// the step contract of doc/architecture.md:
//
//   setup_dofs()             mesh-dependent structures: DoFs, cell stiffness,
//                            normal conditions, body frames, the sparsity pattern
//   initialize(t0)           cold-start active set (closed where the gap is <= 0)
//                            and the input checks that need the mesh
//   begin_time_step(t, tau)  old displacement; loads, prescribed displacements
//                            and gaps at t
//   solve()                  the contact step (primal-dual active set); repeatable
//   primary_state()          u and u_old: all that survives a mesh change
//   after_transfer()         contact set, pressures and gaps re-derived from u
//
// Set-up is in mechanical_field/setup.cc, the contact step in mechanical_field/contact_step.cc;
// doc/contact.md explains the design.
#ifndef contact_stefan_mechanical_field_h
#define contact_stefan_mechanical_field_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/index_set.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <deal.II/dofs/dof_handler.h>

#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/fe_values_extractors.h>

#include <deal.II/hp/fe_collection.h>

#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>

#include <boost/serialization/map.hpp>
#include <boost/serialization/string.hpp>
#include <boost/serialization/utility.hpp>
#include <boost/serialization/vector.hpp>

#include <contact-stefan/core/common.h>
#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/parameters.h>
#include <contact-stefan/core/scene_context.h>
#include <contact-stefan/core/scene_functions.h>
#include <contact-stefan/interfaces/body_interface.h>
#include <contact-stefan/interfaces/mortar_interface.h>
#include <contact-stefan/linear_algebra/linear_solver.h>
#include <contact-stefan/mechanics/contact_step_parameters.h>
#include <contact-stefan/mechanics/solidification_history.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace ContactStefan
{
  /** What one contact step did. */
  struct ContactStepReport
  {
    unsigned int iterations          = 0;
    unsigned int active_nodes        = 0;     // obstacle and interface nodes in contact
    unsigned int changes             = 0;     // summed over the iterations
    unsigned int c_reductions        = 0;     // cycling remedies applied
    unsigned int factorisations      = 0;     // matrices factorised (reused otherwise)
    bool         reused              = false; // stationary data: the last solution stands
    double       max_pressure        = 0;
    double       min_active_pressure = 0; // over the nodes in contact (0 if none)
    /**
     * Per window of 'Output/Contact pressure windows' (its name, in their
     * order), per contact group with a contact node in it: the sum of the
     * nodes' multipliers (N/m, > 0 compressive; a sum below its round-off is
     * 0) and of their weights (m, their shares of the boundary's length; an
     * interface node pair once). The quotient is the window's mean pressure.
     */
    std::vector<std::pair<std::string, std::map<std::string, std::pair<double, double>>>>
      window_sums;
    /** Total compressive normal force per obstacle boundary / interface. */
    std::map<std::string, double> forces;
    /**
     * Per obstacle boundary / interface: the length in contact, the sum of the
     * weights (shares of the boundary's length) of its nodes in the active set
     * (m per unit thickness). Unlike the number of active nodes it does not
     * depend on how the boundary's nodes are spaced (adapted meshes).
     */
    std::map<std::string, double> contact_lengths;
    /** What the elasticity system's CG + AMG did (nothing on the direct path). */
    LinearSolverStatistics linear;

    /** For checkpoints (boost serialization). */
    template <class Archive>
    void serialize(Archive &ar, const unsigned int)
    {
      ar &iterations &active_nodes &changes &c_reductions &factorisations &reused &max_pressure
        &min_active_pressure &forces &linear &window_sums &contact_lengths;
    }
  };

  /**
   * A node with a normal condition: a roller (u.n = 0), a rigid obstacle
   * (u.n <= g) or a contact interface between bodies k and l
   * ((u_k - u_l).n <= g, n pointing out of body k, k the smaller body id).
   */
  struct NormalCondition
  {
    enum class Kind
    {
      roller,
      interface,
      obstacle
    } kind;
    std::string                  group;       // "boundary N" or "interface k-l"
    unsigned int                 body_k = 0, body_l = 0; // interfaces: the two bodies, k < l
    bool                         tied = false;           // interfaces: 'Kind' = tied
    unsigned int                 boundary_id; // roller and obstacle nodes
    Point<2>                     position;
    unsigned int                 vertex = 0; // the triangulation's vertex index
    std::array<std::uint64_t, 2> dofs_k, dofs_l;
    bool                         has_partner;
    std::array<double, 2>        normal;
    double                       weight;
    double                       stiffness;      // normal diagonal of the stiffness matrix
    double                       gap    = 0;     // g at the current time
    bool                         corner = false; // faces disagree by more than the corner angle
    // A mortar interface (doc/contact.md): side k above is a slave node (the
    // normal points out of the slave body, `weight` is D_j), the condition is
    // n.(u_k - sum_m w_m u_m) <= gap with the master nodes' DoFs and
    // w_m = M_jm / D_j; `gap` adds mortar_gap = gtilde_j / D_j, the weighted
    // gap of the two sides' polylines. has_partner is false.
    bool                                                         mortar = false;
    std::vector<std::pair<std::array<std::uint64_t, 2>, double>> masters;
    double                                                       mortar_gap = 0;
    // The slave node's number in its MortarInterface (the same on every rank
    // and in both fields): the key of its InterfaceContactState.
    unsigned int mortar_node = 0;
    // Large sliding: the mesh point of the master side that the node faces
    // now, sum_m w_m X_m (the contact zone the adaptation refines is there
    // on the master's mesh); else the node's own position.
    Point<2> facing;
    // The shortest master edge on the mesh at a master node the node is
    // paired with (its M_jm): the unit of a step's slide.
    double facing_edge = 0;

    /**
     * Whether the node carries a contact pressure (an obstacle or contact
     * interface node; not a roller, not a tied pair, whose reaction is no
     * pressure): the nodes of the contact step's decisions and of the
     * pressure windows.
     */
    bool carries_pressure() const
    {
      return kind != Kind::roller && !(kind == Kind::interface && tied);
    }
  };

  template <int dim>
  class MechanicalField
  {
  public:
    /**
     * prm: the scene; contact_prm: the contact step's own entries;
     * linear_prm: the shared linear-solver entries; verbosity:
     * Output/Verbosity; section_lines: the lines (Output/Section lines) that
     * must be mesh lines; pressure_windows: the bands (Output/Contact pressure
     * windows) that must hold a contact node.
     */
    MechanicalField(const SceneContext<dim>                       &context,
                    const Parameters::ContactStep                 &contact_prm,
                    const Parameters::LinearSolvers               &linear_prm,
                    const std::vector<Parameters::SectionLine>    &section_lines,
                    const std::vector<Parameters::PressureWindow> &pressure_windows = {});

    // --- the step contract ----------------------------------------------------
    void                  setup_dofs();
    void                  initialize(const double t0);
    void                  begin_time_step(const double t, const double tau);
    ContactStepReport     solve();
    std::vector<Vector *> primary_state(); // {u, u_old}, owned vectors
    void                  after_transfer();
    /**
     * Large sliding (doc/contact.md): where set_up_dofs() couples the mortar
     * sides of 'Mortar sliding = large' interfaces (null or empty: on the
     * mesh). The coupled problem owns it and fills it with
     * mortar_side_displacements() before every step.
     */
    void set_mortar_configuration(const MortarConfiguration *configuration)
    {
      mortar_configuration = configuration;
    }
    /**
     * The displacement u (the last step's) of every node of this rank's
     * cells on a side of a 'Mortar sliding = large' interface, by body and
     * mesh position; clears 'configuration' first.
     */
    void mortar_side_displacements(MortarConfiguration &configuration) const;
    /** Whether a mortar interface has 'Mortar sliding = large'. */
    bool large_sliding() const;
    /**
     * Forget factorisations, preconditioners and the last solution, as a new
     * set-up does. A checkpoint calls it (after re-deriving the state with
     * after_transfer()), so that the steps after it do exactly the work of a
     * run resumed from it.
     */
    void restart_solvers()
    {
      ++stiffness_version; // the preconditioner is rebuilt for it
      have_matrix = have_factorisation = have_solution = false;
      linear_solver.clear();
      // (The e_zz responses too: CG starts from them, and a resumed run has none.)
      ezz_response.clear();
    }
    /**
     * Adds the displacement, the stresses and strains (doc/output.md: cell-centre
     * values as cell data, their recovered nodal field per body as point data),
     * the contact pressure and the gap.
     */
    void add_output(DataOut<dim> &data_out) const;

    /**
     * The stress where Q1 is accurate: at the cell centre, from the strain there
     * and the mean of the four vertex values of Theta - Theta_0 (the thermal
     * load is integrated by the vertex rule, so this is the thermal stress the
     * discrete equilibrium holds). On a rectangle the elastic stress of Q1 is
     * linear in x and in y separately, so its centre value is its exact mean
     * over the cell, and the sum of sigma n over the cells along a mesh line
     * is the section force (doc/output.md).
     */
    struct CellStress
    {
      SymmetricTensor<2, dim> strain;  // e(u)
      SymmetricTensor<2, dim> sigma;   // C (e(u) - e_ref) - beta (Theta - Theta_ref)
      SymmetricTensor<2, dim> thermal; // - beta (Theta - Theta_ref)
      /**
       * - C e_ref: the stress of the reference strain of the cell's material
       * points (their mean over the cell; zero without a solidification history).
       */
      SymmetricTensor<2, dim> reference;
      double                  sigma_zz = 0, thermal_zz = 0, reference_zz = 0;
      double                  von_mises() const;
    };
    /** Per active cell index (owned cells; the entries of other cells are zero). */
    std::vector<CellStress> cell_centre_stresses() const;
    /**
     * The largest von Mises stress of the cell-centre values over all cells,
     * with the centre of a cell where it is reached (of the cells within 1e-10
     * of it, the first by x, then y: the same on any partition); 0 and the
     * origin below round-off of the stiffness. Collective.
     */
    std::pair<double, Point<dim>> max_cell_von_mises() const;
    /**
     * The recovered nodal stress of each body, {(sigma_xx, sigma_yy),
     * (sigma_xy, sigma_zz)} in the x and y components of the body's slot
     * (recover_nodal_pair() of the cell-centre values); ghosted vectors.
     */
    void recover_stresses(const std::vector<CellStress> &stresses,
                          std::array<Vector, 2>         &ghosted) const;
    /**
     * The section force across each line: the integral of sigma n (n = +x or
     * +y) over the faces on the line of the cells before it (left or below:
     * side 0) and of those after it (side 1), from the cell-centre stresses and
     * from the recovered nodal field (trapezoidal rule on each face: exact for
     * its linear trace); and the length of those faces. Collective.
     * On a side whose cells all have the same extent across the line (a row
     * of equal cells: uniform_row()), the cell-centre force is the exact
     * section force of the discrete equilibrium (doc/output.md); where hanging
     * nodes border the row it is not.
     */
    struct SectionForce
    {
      std::array<Tensor<1, dim>, 2> cell_centre, recovered;
      std::array<double, 2>         length     = {{0., 0.}};
      std::array<double, 2>         min_extent = {{HUGE_VAL, HUGE_VAL}};
      std::array<double, 2>         max_extent = {{0., 0.}};
      // Whether every cell of the row is a parallelogram (the identity of
      // doc/output.md holds on rows of equal parallelograms; with its load
      // term, on lines x = c and y = c).
      std::array<bool, 2> affine = {{true, true}};
      bool                uniform_row(const unsigned int side) const
      {
        return affine[side] && max_extent[side] - min_extent[side] <= 1e-10 * max_extent[side];
      }
    };
    std::vector<SectionForce>
    section_forces(const std::vector<Parameters::SectionLine> &lines) const;
    /**
     * Visit every vertex of every owned cell with its vertex-rule weight and
     * the recovered stress there (sigma, sigma_zz): the L2 error of the
     * recovered field by the vertex rule. Collective (the recovery). At a
     * vertex shared by bodies the point is just inside the cell
     * (point_of_side()), so that an exact solution that jumps there is
     * evaluated for the cell's body.
     */
    void for_each_recovered_vertex_stress(
      const std::function<void(const Point<dim> &, double, const SymmetricTensor<2, dim> &, double)>
        &visit) const;
    /**
     * Refuses (InputError naming 'Output/Section lines') a line that cuts a
     * coarse cell or meets no face of the mesh: refinement keeps the lines of
     * the coarse mesh, so these are mesh lines at every step.
     */
    void check_section_lines(const std::vector<Parameters::SectionLine> &lines) const;
    /**
     * Refuses (InputError naming 'Output/Contact pressure windows') a window
     * that holds no contact node of the mesh. Collective.
     */
    void check_pressure_windows() const;

    // --- coupling (doc/coupling.md) -------------------------------------------------
    // The exchange with the thermal field goes through per-cell vertex arrays
    // indexed by active cell index (entries of locally owned cells only), so
    // that neither field knows the other's DoFs. Vertex v of a cell is its v-th
    // vertex, the v-th point of the trapezoidal rule and the v-th FE_Q(1) DoF.
    // Phase weights of each cell (one per phase of its body), lagged: the
    // stiffness and beta of cells whose mixture changed are re-assembled.
    // Returns the number of cells re-assembled (over all ranks).
    unsigned int set_phase_weights(const std::vector<std::vector<double>> &weights);
    /** Theta at the vertices: the thermal stress load of the next solve(). */
    void set_cell_temperatures(const CellVertexValues &theta);
    /**
     * The thermoelastic work per vertex, sum_i B_K(i, v) (u - u_old)_i with
     * B_K(i, v) = w_v beta_K : e(phi_i)(x_v): times the absolute Theta_0(x_v) it
     * is the heat that the step's strain increment takes out of node v.
     */
    void thermoelastic_work(CellVertexValues &work) const;
    /**
     * Stored elastic energy 1/2 int sigma : C^{-1} : sigma (thermal part
     * included) of the material points (cell corners): each with its
     * quadrant's 2 x 2 Gauss weight, the elastic strain at the Gauss point and
     * the thermal strain of its vertex; and the largest strain (Frobenius norm
     * of e(u) at the Gauss points, for the small-strain check). Collective.
     */
    struct ElasticStatistics
    {
      double energy     = 0;
      double max_strain = 0;
    };
    ElasticStatistics elastic_statistics() const;
    /** Work of the contact forces on the bodies over the last step; collective. */
    double contact_work() const;
    /** sigma and sigma_zz at vertex v of an owned cell for the strain e there. */
    std::pair<SymmetricTensor<2, dim>, double>
    stress(const typename DoFHandler<dim>::active_cell_iterator &cell,
           const unsigned int                                    vertex,
           const SymmetricTensor<2, dim>                        &strain) const;
    /**
     * sigma and sigma_zz of the material point at corner q of an owned cell for
     * the elastic strain e there (the reference strain already taken off):
     * C e less the thermal stress of vertex q, with the body's e_zz.
     */
    std::pair<SymmetricTensor<2, dim>, double>
    point_stress(const typename DoFHandler<dim>::active_cell_iterator &cell,
                 const unsigned int                                    corner,
                 const SymmetricTensor<2, dim>                        &elastic) const;
    /** The moduli (phase mixture included) of an owned cell. */
    const ElasticModuli &moduli(const typename Triangulation<dim>::active_cell_iterator &cell) const
    {
      return cell_moduli[cell->active_cell_index()];
    }
    /**
     * Visit every vertex of every owned cell with its trapezoidal weight, the
     * computed stress there, sigma_zz, the thermal part -beta (Theta -
     * Theta_ref), the cell's moduli and the strain e(u) there. The point as in
     * for_each_recovered_vertex_stress().
     */
    void
    for_each_vertex_stress(const std::function<void(const Point<dim> &,
                                                    double,
                                                    const SymmetricTensor<2, dim> &,
                                                    double,
                                                    const SymmetricTensor<2, dim> &,
                                                    const ElasticModuli &,
                                                    const SymmetricTensor<2, dim> &)> &visit) const;

    // --- solidification stress (doc/solidification.md) ----------------------------
    // A body that is stress-free at solidification gives each material point
    // (cell corner) its own reference state (solidification_history.h); the
    // history exists only when some body asks for it.
    SolidificationHistory<dim> *solidification_history()
    {
      return history.get();
    }
    /**
     * The initial references: e_ref = 0 at every point, Theta_ref = Theta_0 at
     * a solid point and the transition temperature at a melt point of a body
     * that is stress-free at solidification; each point's class (solid or not)
     * from the solid fraction of its node, per cell and vertex
     * (ThermalField::cell_solid_fractions()).
     */
    void initialize_references(const CellVertexValues &solid_fraction, const double t0);
    /**
     * After a step (t: its end, tau: its length), before the next one begins,
     * with the phases of its end: every point of a stress-free body whose node
     * changed class is born anew, with the strain interpolated between u_old
     * and u to the fraction of the step at which its node's enthalpy passed
     * the birth value (crossing, ThermalField::cell_solid_fractions()); with
     * lagged_displacement (the staggered scheme: u is the equilibrium with the
     * temperature at the step's start) extrapolated from them instead.
     * Applies from the next step on (apply_references()). Returns the number
     * of points born (over all ranks).
     */
    unsigned int update_references(const CellVertexValues &solid_fraction,
                                   const CellVertexValues &crossing,
                                   const double            t,
                                   const double            tau,
                                   const bool              lagged_displacement);
    /**
     * Theta_ref at the vertices and the load of e_ref, from the history and
     * the cells' moduli: after the references or the moduli changed, and
     * after a mesh change. Call before set_cell_temperatures().
     */
    void apply_references(const bool all_cells);
    /** The reference of corner v of an owned cell (a default one without a history). */
    CornerReference corner_reference(const unsigned int cell_index, const unsigned int v) const;

    // --- generalized plane strain (mechanical_field/out_of_plane.cc) ------------
    // With Physics/Plane constraint = generalized plane strain each body b has
    // one more unknown, its uniform out-of-plane strain e_b, fixed by a zero
    // net out-of-plane force, int_b sigma_zz = 0. It is condensed out of
    // every linear solve of the contact step exactly (doc/model.md).
    bool out_of_plane_free() const
    {
      return generalized_plane_strain;
    }
    /** e_zz of the body in slot s (0 unless generalized plane strain). */
    double out_of_plane_strain(const unsigned int slot) const
    {
      return generalized_plane_strain ? ezz[slot] : 0.;
    }
    /**
     * The net out-of-plane force int sigma_zz of each body (by slot), with the
     * quadrature rules of the equilibrium (Gauss for the strains, the vertex
     * rule for the thermal part), relative to the sum of the magnitudes of
     * its parts per cell (strain, uniform e_zz, thermal, reference): zero to
     * the solver's tolerance after a solve in generalized plane strain, 0 in
     * the other constraints. Collective.
     */
    std::vector<double> out_of_plane_forces() const;
    /** e_zz and its value at the step's start, per slot, for a checkpoint. */
    std::vector<double> restart_state() const;
    void                set_restart_state(const std::vector<double> &state);

    // --- adaptivity (doc/adaptivity.md) ----------------------------------------
    // Positions of the owned obstacle and interface nodes in contact.
    // --- the block correction of the coupling (coupled_block.h) ---------------
    // The system matrix of the last solve (constraints condensed), its
    // fingerprint (stiffness and constraint pattern), the constraints, and the
    // thermal-stress operator B_K of an owned cell (rows: the cell's DoFs,
    // columns: its vertices).
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
    /** B_K(i, v) as B[i][v]: rows the cell's DoFs (cell order), columns its vertices. */
    using ThermalOperator = std::array<std::array<double, 4>, 4 * dim>;
    const ThermalOperator &thermal_operator(const unsigned int cell_index) const
    {
      return cell_thermal_operator[cell_index];
    }
    /**
     * The start of the next solve's linear solve (a displacement that nearly
     * solves it): if its residual on the free rows is within the CG tolerance, it is
     * the solution (no linear solve, on either path); CG starts from it
     * otherwise. The next solve() never reuses the last solution unchanged.
     */
    void set_initial_guess(const Vector &u)
    {
      displacement  = u;
      have_solution = false;
      guess_pending = true;
    }
    /** How many solves a guess answered without a linear solve. */
    unsigned int n_guesses_accepted() const
    {
      return guesses_accepted;
    }
    /**
     * change = the condensed thermal load of theta minus that of theta_before
     * (what the right-hand side of the contact step moves by). One MPI rank
     * only, as the block correction that calls it.
     */
    void thermal_load_change(const CellVertexValues &theta,
                             const CellVertexValues &theta_before,
                             Vector                 &change) const;

    void contact_points(std::vector<Point<dim>> &points) const;
    /**
     * The gap, contact pressure and closed flag of the last contact step at
     * every interface vertex of the locally owned cells (what a conductance
     * interface of the thermal field reads). Collective.
     */
    void interface_contact_states(InterfaceContactStates &states) const;
    /**
     * The Kelly jump indicator of the displacement, per active cell (zero on
     * cells that are not owned). The jump across a contact interface is not
     * counted (the two bodies' displacements are independent there).
     */
    void error_indicator(dealii::Vector<float> &indicator) const;

    // --- queries ----------------------------------------------------------------
    const DoFHandler<dim> &get_dof_handler() const
    {
      return dof_handler;
    }
    const Vector &get_displacement() const // ghosted
    {
      return displacement_ghosted;
    }
    const std::vector<NormalCondition> &get_normal_conditions() const
    {
      return normal_conditions;
    }
    /** What the mortar coupling of one interface found (at the last set-up). */
    struct MortarSummary
    {
      unsigned int slave_body       = 0; // the body whose side carries the conditions
      unsigned int segments         = 0; // slave-master segments integrated
      double       uncovered_length = 0; // slave side facing no master edge (m)
      unsigned int slave_nodes      = 0; // slave nodes with a condition
      double       weight_defect    = 0; // max_j |1 - sum_m M_jm / D_j| over them
      bool         large_sliding    = false; // Mortar sliding = large
    };
    /** By group ("interface k-l"), for the mortar interfaces. */
    const std::map<std::string, MortarSummary> &get_mortar_summary() const
    {
      return mortar_summary;
    }
    /**
     * Every obstacle boundary and interface ("boundary N", "interface k-l"),
     * the same sorted list on every rank.
     */
    const std::vector<std::string> &get_contact_groups() const
    {
      return contact_groups;
    }
    bool         is_active(const NormalCondition &c) const;        // owned condition in contact
    double       contact_pressure(const NormalCondition &c) const; // owned condition
    double       contact_gap(const NormalCondition &c) const;      // owned condition
    unsigned int body_slot(const unsigned int body) const
    {
      return slot_of_body.at(body);
    }
    /** Height of the bounding box of a body (the patch test's compliance). */
    double body_height(const unsigned int body) const;
    /** How many roller, obstacle and interface nodes the field found. */
    std::string describe() const;
    /**
     * result = K u - f (hanging nodes condensed) for the displacement u
     * (ghosted): the residual from which contact forces are read.
     */
    void apply_stiffness(const Vector &u_ghosted, Vector &result, const bool with_load) const;

  private:
    using LocalMatrix = FullMatrix<double>;

    /** mechanical_field/setup.cc */
    void assemble_cell_stiffness();
    /** K_K and (with coupling) B_K of one owned cell with its cell_moduli. */
    void assemble_cell_operators(const typename DoFHandler<dim>::active_cell_iterator &cell,
                                 hp::FEValues<dim>                                    &gauss_values,
                                 hp::FEValues<dim> &vertex_values);
    void update_stiffness_diagonal();
    void update_condition_stiffness();
    void find_normal_conditions();
    // The conditions of the mortar interfaces (mechanical_field/mortar.cc)
    // into mortar_cache and mortar_summary; adds their master DoFs to
    // `relevant`.
    void couple_mortar_interfaces();
    // Refuses a mortar slave node that carries another contact condition
    // (collective; mechanical_field/mortar.cc).
    void check_mortar_junctions() const;
    void gather_contact_groups(const std::set<std::string> &groups);
    void make_body_frames();
    void make_sparsity_pattern();
    void add_closed_cell_couplings(
      DynamicSparsityPattern                                                        &dsp,
      const std::map<types::global_dof_index, std::vector<types::global_dof_index>> &condition_dofs)
      const;
    void settle_imposable_conditions(std::unordered_set<types::global_dof_index> &contact_dofs);
    void set_rigid_body_modes();
    void assemble_load();
    void make_fixed_constraints();

    /** mechanical_field/contact_step.cc */
    void update_condition_gaps();
    void build_contact_constraints(unsigned int &n_skipped);
    void check_rigid_body_modes() const;
    void assemble_system(const bool with_matrix);
    /** The right-hand side of the system with the current constraints (right_hand_side.cc). */
    void assemble_right_hand_side();
    /** settled: the active set has settled, solve to the full CG tolerance. */
    void solve_linear_system(const bool factorise, const bool settled);
    /**
     * Hash of the constraint lines: their pattern and coefficients (what the
     * matrix depends on), with inhomogeneities if asked; the same on every rank.
     */
    std::uint64_t constraints_hash(const bool with_inhomogeneities) const;
    std::uint64_t gaps_hash() const;
    std::uint64_t loads_hash() const;
    std::uint64_t contact_data_hash() const;
    double        normal_displacement_jump(const NormalCondition &c) const;
    Vector       &active_flags(const NormalCondition &c);
    const Vector &active_flags_ghosted(const NormalCondition &c) const;
    struct Decision
    {
      const NormalCondition *c;
      double                 lambda, d, c_eff;
    };
    std::vector<Decision>
    contact_decisions(const Vector &residual, double &local_scale, double &max_penetration) const;
    void store_contact_output(const std::vector<Decision> &decisions, ContactStepReport &report);
    /** The report's window sums, from the decisions' multipliers (collective). */
    void store_window_sums(const std::vector<Decision> &decisions, ContactStepReport &report) const;
    /**
     * The steps of solve() (doc/contact.md, "The active-set iteration"), all
     * collective: the last converged solve's report if its data are unchanged;
     * the active set moved by the decisions (changes and active nodes counted
     * into the report); the converged set checked with c at full size; c
     * divided by ten where a set keeps recurring.
     */
    struct SetUpdate
    {
      unsigned int  changes;          // on all ranks
      std::uint64_t set_hash;         // of the new set, the same on every rank
      double        local_min_lambda; // this rank's, over the nodes that were active
    };
    bool      reuse_if_stationary(ContactStepReport &report);
    SetUpdate update_active_set(const std::vector<Decision> &decisions,
                                const double                 tolerance,
                                ContactStepReport           &report);
    void      check_converged_set(const std::vector<Decision> &decisions) const;
    void      reduce_complementarity_constant(ContactStepReport &report);

    const SceneParameters                           &prm;
    const Parameters::ContactStep                   &contact_prm;
    const Parameters::LinearSolvers                 &linear_prm;
    const unsigned int                               verbosity;
    const std::vector<Parameters::SectionLine>       section_lines;
    const std::vector<Parameters::PressureWindow>    pressure_windows;
    const Materials                                 &materials;
    SceneFunctions<dim>                             &functions;
    const parallel::distributed::Triangulation<dim> &triangulation;
    const MPI_Comm                                   mpi_communicator;
    TimerOutput                                     &timer;
    const ConditionalOStream                        &pcout;

    std::map<unsigned int, unsigned int> slot_of_body; // material id -> slot
    hp::FECollection<dim>                fe;
    DoFHandler<dim>                      dof_handler;
    IndexSet                             owned, relevant;

    /**
     * Hanging nodes alone; plus prescribed displacements, ties and rollers
     * (rebuilt each step); plus the active contact set (each iteration).
     */
    AffineConstraints<double> hanging_node_constraints, fixed_constraints, constraints;
    /**
     * For each DoF, the targets of the fixed (non-hanging) lines that name it as
     * an entry; rebuilt with the fixed constraints.
     */
    std::unordered_map<types::global_dof_index, std::vector<types::global_dof_index>> named_by;
    TrilinosWrappers::SparseMatrix                                                    system_matrix;
    /**
     * The part of K that no active set changes: the cells whose DoFs (closed
     * under the fixed constraints) carry no contact condition, condensed with
     * the fixed constraints. Each active-set iteration copies its values and
     * adds the few cells along the contact boundaries (assemble_system).
     * bulk_signature: the stiffness version and fixed-constraint pattern it
     * was assembled for.
     */
    TrilinosWrappers::SparseMatrix bulk_matrix;
    std::uint64_t                  bulk_signature = 0;
    bool                           have_bulk      = false;
    /**
     * Whether bulk_matrix and system_matrix store their entries in the same
     * order (checked when bulk_matrix is made): the copy is then one array copy.
     */
    bool bulk_storage_matches = false;
    /**
     * Per active cell index: whether the cell's DoF closure carries a contact
     * condition (make_sparsity_pattern), and whether one of its DoFs is
     * constrained by the fixed constraints (its right-hand side then carries
     * inhomogeneities even without a load).
     */
    std::vector<bool> cell_near_contact, cell_fixed_constrained;
    /** Assemble bulk_matrix for the current stiffness and fixed constraints. */
    void         assemble_bulk_matrix(const std::uint64_t signature);
    Vector       system_rhs, load, stiffness_diagonal;
    LinearSolver linear_solver;

    /** Primary state. */
    Vector displacement, old_displacement;
    /**
     * Derived state: the ghosted displacement; the active flags (1 or 0 at the
     * x DoF of side k) of the obstacle and interface conditions, owned and
     * ghosted; nodal contact pressure and gap for output (at the same DoF).
     */
    Vector displacement_ghosted;
    /**
     * Per owned cell (by active cell index): the local entries of its DoFs,
     * in their cell order, in a vector of displacement_ghosted's layout (the
     * relevant DoFs); and scratch vectors of the owned and that layout. The
     * per-cell loops of the coupling read through these: element access
     * through TrilinosWrappers maps every index through Epetra's hash table.
     */
    std::vector<std::array<int, 4 * dim>> cell_entry;
    mutable Vector                        scratch_owned, scratch_ghosted;
    Vector obstacle_active, obstacle_active_ghosted, interface_active, interface_active_ghosted;
    Vector pressure, gap;

    /**
     * Per-cell operators by active cell index: the moduli of the cell's phase
     * mixture, K_K, the mechanical load F_K; with coupling the thermal operator
     * B_K (8 x 4, stored in one array: the coupling's per-cell loops stream
     * through it), Theta_0 and Theta - Theta_0 at the vertices and the thermal
     * load B_K (Theta - Theta_0).
     */
    std::vector<ElasticModuli>          cell_moduli;
    std::vector<LocalMatrix>            cell_stiffness;
    std::vector<ThermalOperator>        cell_thermal_operator;
    std::vector<dealii::Vector<double>>      cell_load;
    std::vector<std::array<double, 4 * dim>> cell_thermal_load; // (one array, as B_K)
    /**
     * The traction part of F_K of each boundary face with a traction, by
     * (active cell index, face): the section forces leave out the traction on
     * a face that lies on the section line.
     */
    std::map<std::pair<unsigned int, unsigned int>, dealii::Vector<double>> traction_face_load;
    CellVertexValues cell_reference, cell_theta_excess;
    const bool       coupled, thermal_stress;

    /**
     * The references of the material points (null unless some body is
     * stress-free at solidification), and per active cell the load of its
     * reference strains, sum_q w_q e(phi_i)(x_q) : C_K : e_ref,q (empty where
     * every e_ref is zero); it is part of cell_thermal_load.
     */
    std::unique_ptr<SolidificationHistory<dim>> history;
    std::vector<dealii::Vector<double>>         cell_reference_load;
    /**
     * Per active cell, the strain of K_K^+ (load of e_ref) at the four
     * vertices: the part of the reference strain the element can hold
     * (solidification.cc), for the stress at the vertices; zero where the
     * cell has no reference load.
     */
    std::vector<std::array<SymmetricTensor<2, dim>, 4>> cell_vertex_reference_strain;
    /**
     * Per active cell, that displacement K_K^+ (load of e_ref) itself, in the
     * cell's DoF order (empty where the cell has no reference load): the
     * elastic energy takes the strain of u - u_ref (elastic_statistics()).
     */
    std::vector<dealii::Vector<double>> cell_reference_displacement;
    /**
     * Per active cell: its references or moduli changed since the last
     * apply_references() (set by update_references() and set_phase_weights()).
     */
    std::vector<bool> references_changed;
    /** Whether the body of the cell keeps a history (stress-free at solidification). */
    bool keeps_history(const typename DoFHandler<dim>::active_cell_iterator &cell) const;

    /**
     * Generalized plane strain (out_of_plane.cc): e_zz per body slot and at
     * the step's start; per active cell g_K (g_i = int lambda_zz tr e(phi_i),
     * Gauss rule), a_K = int C_zzzz, the vertex weights of the thermal part
     * w_v beta_zz, and the out-of-plane force of the reference strains
     * (sum_q w_q (lambda_zz tr e_ref,q + C_zzzz e_ref,zz,q)); the response
     * W_b (K W_b = g_b, homogeneous constraints) of each body's unit e_zz
     * for the current matrix.
     */
    const bool                          generalized_plane_strain;
    std::vector<double>                 ezz, old_ezz;
    std::vector<dealii::Vector<double>> cell_ezz_coupling;
    std::vector<double>                 cell_ezz_stiffness, cell_ezz_reference;
    std::vector<std::array<double, 4>>  cell_ezz_thermal;
    std::vector<Vector>                 ezz_response;
    /** g_K and a_K of one cell from the Gauss-point values of its element. */
    void assemble_out_of_plane_operators(const unsigned int                c,
                                         const FEValues<dim>              &fe_values,
                                         const FEValuesExtractors::Vector &u);
    /**
     * After a linear solve for the current e_zz: the e_zz of every body that
     * makes its net out-of-plane force zero, and u moved to it (u - sum_b W_b
     * de_b, exact for the current matrix and constraints; W recomputed when
     * the matrix is new).
     */
    void balance_out_of_plane(const bool new_matrix);
    /**
     * The local (this rank's cells) net out-of-plane force per slot for u;
     * with scale, also the sum of the magnitudes of its parts per cell.
     */
    std::vector<double> local_out_of_plane_forces(const Vector        &u_ghosted,
                                                  std::vector<double> *scale = nullptr) const;

    /**
     * Work skipped when its inputs did not change: the matrix (stiffness
     * version, constraint pattern) last assembled and factorised, and the data
     * of the last converged solve (contact_data_hash(): loads, inhomogeneities,
     * gaps).
     */
    unsigned int stiffness_version = 0;
    /** The stiffness the linear solver's preconditioner was built for. */
    unsigned int      preconditioner_stiffness_version = static_cast<unsigned int>(-1);
    bool              have_matrix = false, have_factorisation = false, have_solution = false;
    bool              guess_pending    = false;
    unsigned int      guesses_accepted = 0;
    std::uint64_t     matrix_signature = 0, factorisation_signature = 0;
    std::uint64_t     solved_signature = 0;
    ContactStepReport last_report;

    std::vector<NormalCondition>         normal_conditions;
    std::map<std::string, MortarSummary> mortar_summary;
    std::vector<NormalCondition>         mortar_cache;
    const MortarConfiguration           *mortar_configuration = nullptr;
    std::vector<std::string>     contact_groups;
    /**
     * The conditions imposed by the last build_contact_constraints(), by (x DoF
     * of side k, kind), and per group the owned ones among them. setup_dofs()
     * builds once with every node active: what can be imposed at all.
     */
    std::set<std::pair<std::uint64_t, int>> imposed_conditions;
    std::map<std::string, unsigned int>     placed_per_group;
    std::map<std::string, unsigned int>     imposable_per_group; // with every node active
    unsigned int                            n_dropped_conditions = 0;

    /**
     * Body slot, component and position of every locally relevant displacement
     * DoF, and per slot the centre and size of the body (for its rotation mode)
     * and its bounding box.
     */
    struct DofInfo
    {
      unsigned int slot, component;
      Point<dim>   position;
    };
    std::unordered_map<types::global_dof_index, DofInfo> dof_info;
    std::vector<std::pair<Point<dim>, double>>           body_frame;
    std::vector<std::pair<Point<dim>, Point<dim>>>       body_box;

    double complementarity_scale = 1; // divided by 10 per cycling remedy
    double time                  = 0; // of the data: the start time or the last begin_time_step()

    /**
     * The lumped L2 projection of per-cell values onto the continuous Q1 field of
     * each body (doc/output.md): two values per cell go into the x and y
     * components of the cell's body slot; a node's value is the area-weighted
     * mean of the values of the cells of its body around it (hanging nodes
     * condensed and distributed). Returns an owned vector.
     * The displacement at the vertices of an owned cell (u[component][vertex]),
     * from the cell's DoFs: the closed-form Q1 strains of the statistics and
     * the cell-centre stresses need no FEValues.
     */
    void cell_vertex_displacement(const typename DoFHandler<dim>::active_cell_iterator &cell,
                                  std::array<std::array<double, 4>, dim>               &u) const;

    void recover_nodal_pair(const std::vector<std::array<double, 2>> &cell_values,
                            Vector                                   &nodal) const;

    /** Output, alive until the next add_output(). */
    mutable Vector                                               output_pressure, output_gap;
    mutable std::array<Vector, 4>                                output_recovered;
    mutable std::vector<dealii::Vector<double>>                  output_cell_data;
    mutable std::vector<std::unique_ptr<DataPostprocessor<dim>>> output_postprocessors;
  };
} // namespace ContactStefan

#endif
