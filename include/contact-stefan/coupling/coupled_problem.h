// CoupledProblem: the mesh, the time loop of the Nedoma-Dvorak scheme, and one
// field per physics (doc/architecture.md).
//
// It owns the triangulation that both fields share, the time state, the
// materials and parsed functions of the scene, the thermal and the mechanical
// field (each null when its physics is off: a scene without mechanics has no
// displacement DoFs at all, and nothing branches on it inside the fields) and
// the postprocessor. One time step reads as the method (doc/model.md §2):
// begin the step in both fields, the contact step, the enthalpy step, report.
// Everything is distributed (p4est triangulation, Trilinos linear algebra), so
// `mpirun -np N` runs the same scene; results do not depend on N beyond the
// linear solver tolerance.
#ifndef contact_stefan_coupled_problem_h
#define contact_stefan_coupled_problem_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/scene_functions.h>
#include <contact-stefan/coupling/all_parameters.h>
#include <contact-stefan/coupling/coupled_block.h>
#include <contact-stefan/mechanics/mechanical_field.h>
#include <contact-stefan/mesh/mesh_adaptation.h>
#include <contact-stefan/output/postprocessor.h>
#include <contact-stefan/output/run_guard.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <memory>
#include <string>
#include <vector>

namespace ContactStefan
{

  template <int dim>
  class CoupledProblem
  {
  public:
    CoupledProblem(const AllParameters &parameters, const MPI_Comm mpi_communicator);
    /**
     * Runs the scene; returns the self-checks that failed (a run that fails
     * one ends with exit code 3, see main.cc).
     */
    std::vector<std::string> run();

  private:
    /**
     * One time step of both fields: staggered (contact step with Theta^k, then
     * the enthalpy step with u^(k+1)) or with fixed-point iterations.
     */
    void coupled_step(EnthalpyStepReport &thermal_report,
                      ContactStepReport  &contact_report,
                      CouplingReport     &coupling_report);
    /**
     * One time step with its size (time_step.cc, doc/time_stepping.md): the
     * schedule's, or the adaptive step control's, whose attempts are undone
     * and redone shorter from the state kept at the step's start until one
     * stands. Returns whether the step ends the run.
     */
    bool   take_time_step(EnthalpyStepReport &thermal_report,
                          ContactStepReport  &contact_report,
                          CouplingReport     &coupling_report,
                          StepControlReport  &control_report);
    bool   run_finished() const;
    std::string adaptive_state_problem() const;
    double adaptive_step_end(bool &shortened);
    /** What a step's attempt is undone to: what a checkpoint holds of the fields. */
    struct StepStart
    {
      std::vector<Vector> thermal_state, mechanical_state;
      std::vector<double> thermal_scalars, mechanical_scalars;
      double              time = 0, time_step = 0;
      unsigned int        step_number = 0;
    };
    void save_step_start(StepStart &start);
    void restore_step_start(const StepStart &start);
    /**
     * Set-up and initial state on the current mesh: DoFs, initial enthalpy and
     * displacement, the initial exchange between the fields and the initial
     * equilibrium (a contact step at t0).
     */
    ContactStepReport set_initial_state();
    /**
     * Mesh adaptation (doc/adaptivity.md). mark_for_adaptation() sets the
     * flags from the indicators and features of the current state and makes
     * them conforming at the interfaces; execute_with_transfer() refines and
     * carries the primary state of both fields over (transfer = false: the
     * initial adaptation, whose state is set afresh); repairs follow while
     * p4est's balance refined one side of an interface only.
     */
    AdaptationReport mark_for_adaptation();
    bool             features_inside_refined_zone();
    void feature_points(std::vector<Point<dim>> &fronts, std::vector<Point<dim>> &contacts) const;
    void             execute_with_transfer(const bool transfer);
    void             execute_and_repair(const bool transfer);
    void             adapt_initial_mesh(ContactStepReport &initial_contact);
    void             adapt_mesh();
    /**
     * After the primary state arrived on a new mesh: the derived state of
     * both fields and the data they exchange.
     */
    void after_mesh_change();
    /**
     * Large sliding (Contact/Interface k-l/Mortar sliding = large,
     * doc/contact.md): after every step (and before the first step of a
     * mesh set up on the mesh), the mortar sides are coupled again where the
     * displacement u has moved them, by couple_where_displaced(); then the
     * derived state is re-derived as after a mesh change. With record, the
     * change of the total enthalpy goes to the report.
     */
    void follow_sliding_interfaces(const bool record);
    /**
     * The mesh and the DoFs stay; both fields are set up again in the
     * configuration of u (their constraints and sparsity follow the new
     * pairing) and keep their primary state. Invariant between steps: the
     * coupling is that of the displacement the fields hold, so that a
     * checkpoint's u gives a resumed run the same coupling.
     */
    void couple_where_displaced();
    bool large_sliding() const
    {
      return mechanical && mechanical->large_sliding();
    }
    /** The configuration both fields couple large-sliding sides in (empty: the mesh). */
    MortarConfiguration sliding_configuration;
    /** Whether the current coupling is that of the current u (false after a set-up on the mesh). */
    bool coupled_where_displaced = false;
    /**
     * Checkpoint/restart (checkpoint.cc, doc/adaptivity.md): the mesh, the
     * primary state of both fields, the time state, the postprocessor's
     * accumulated results and the statistics file, written atomically into
     * Output/Directory/checkpoint with a manifest of their sizes and
     * checksums; resume() checks the manifest before anything is read, then
     * builds the coarse mesh and loads all of it (on any number of ranks).
     */
    bool        checkpoint_due();
    void        write_checkpoint();
    void        remove_checkpoints();
    void        resume();
    /**
     * The steps of resume(), all collective: the checkpoint found and checked
     * whole (its directory, its manifest's id and step); the state file read
     * (the time state and the postprocessor's results; the point's other
     * values) and checked; the forest loaded with the fields' primary state.
     */
    struct RestartPoint
    {
      std::string         directory, id;
      unsigned int        step = 0;
      std::vector<double> thermal_scalars, mechanical_scalars;
      double              wall    = 0;
      unsigned int        n_ranks = 0;
    };
    RestartPoint find_checkpoint() const;
    void         read_state_file(RestartPoint &point);
    void         check_restored_state(const RestartPoint &point) const;
    void         load_mesh_and_primary_state(const RestartPoint &point);
    std::string checkpoint_directory(const std::string &suffix = "") const;
    std::string fields_fingerprint() const;
    /**
     * The checksum of Geometry/Mesh file's content ("none" without one),
     * taken once at the start of the run into mesh_file_content.
     */
    std::string mesh_file_checksum() const;
    std::string mesh_file_content;
    /** The data each field hands the other (doc/coupling.md). */
    void exchange_temperature();
    /** Births after a step (doc/solidification.md); returns how many. */
    unsigned int update_births();
    void exchange_thermoelastic_work();
    void         exchange_contact_state();
    /** A conductance interface reads the contact step's gap or pressure. */
    bool contact_feedback() const
    {
      return thermal && mechanical && thermal->conductance_depends_on_contact();
    }
    /** Interfaces whose two sides' nodes are paired (contact, ties, conductances). */
    bool interfaces_paired() const
    {
      return mechanical || (thermal && thermal->has_conductance_interfaces());
    }
    /** A one-line summary of what the scene couples and what it skips. */
    std::string describe_coupling() const;
    void        print_step_line(const EnthalpyStepReport &thermal_report,
                                const ContactStepReport  &contact_report,
                                const CouplingReport     &coupling_report) const;

    const AllParameters &prm;
    ConditionalOStream   pcout;
    TimerOutput          timer;
    Timer                wall_clock;

    parallel::distributed::Triangulation<dim> triangulation;
    /** The diagonal of the domain's bounding box (-1: not computed yet). */
    double                                diameter = -1;
    double                                domain_diameter();
    const Materials                       materials;
    /**
     * Every function of the scene, with the exact temperature a verification
     * part gives (coupling/part_registry.h).
     */
    SceneFunctions<dim> functions;
    /** What the fields and the parts of the report share (core/scene_context.h). */
    const SceneContext<dim>               context;
    std::unique_ptr<Postprocessor<dim>>   postprocessor;
    std::unique_ptr<ThermalField<dim>>    thermal;    // null: Physics/Thermal = false
    std::unique_ptr<MechanicalField<dim>> mechanical; // null: Physics/Mechanics = false
    /**
     * The block correction of the fixed point (null where it does not apply:
     * block_not_applicable says why).
     */
    std::unique_ptr<CoupledBlock<dim>> block;
    std::string                        block_not_applicable;

    double       time, time_step = 0;
    unsigned int step_number = 0;
    /**
     * Adaptive steps: the size the controller proposes for the next step
     * (checkpointed; before the first step, Time stepping/Time step).
     */
    double proposed_time_step = 0;
    /** Wall time of the run before a resume, and at the last checkpoint. */
    double wall_offset = 0, last_checkpoint_wall = 0;
  };
} // namespace ContactStefan

#endif
