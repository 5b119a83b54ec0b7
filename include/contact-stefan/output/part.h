// The parts of a run's report. Everything a run writes besides the solver's
// own lines is made by a part: the VTU/PVD writer, the statistics of each
// field, and one part per exact solution or check. A part declares and parses
// its own parameters, adds its own columns to the statistics table and its own
// RESULT lines, and saves and loads its own checkpoint state. The registry
// (coupling/part_registry.h) lists them, name by name; the Postprocessor
// (output/postprocessor.h) calls them in that order.
//
// The model is ASPECT's postprocessor plugins: a part is the size of
// verification/hertz.cc, and adding one touches its own file and one line of
// the registry (doc/architecture.md, recipes).
#ifndef contact_stefan_part_h
#define contact_stefan_part_h

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/function.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <deal.II/distributed/tria.h>

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>

#include <contact-stefan/core/common.h>
#include <contact-stefan/core/materials.h>
#include <contact-stefan/core/parameters.h>
#include <contact-stefan/core/scene_context.h>
#include <contact-stefan/core/scene_functions.h>
#include <contact-stefan/mechanics/mechanical_field.h>
#include <contact-stefan/output/output_parameters.h>
#include <contact-stefan/thermal/thermal_field.h>

#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace ContactStefan
{
  /** What the coupling did in one time step. */
  struct CouplingReport
  {
    unsigned int iterations        = 0;          // passes of contact + enthalpy step (1: staggered)
    unsigned int reassembled_cells = 0;          // stiffness re-assembled for a new phase mixture
    double       change_u = 0, change_theta = 0; // last fixed-point changes, max norm
    // The block correction of the fixed point (coupling/coupled_block.h), where
    // the run has one: corrections and factorisations of the block in this
    // step (those by LDL^T), and the elasticity and heat solves a corrected
    // guess answered.
    bool         block_correction      = false;
    unsigned int block_corrections     = 0;
    unsigned int block_factorisations  = 0;
    unsigned int block_ldlt            = 0;
    unsigned int guesses_accepted      = 0;
    unsigned int heat_guesses_accepted = 0;
    // Material points born anew at the start of this step (solidification
    // history, doc/solidification.md; 0 without one).
    unsigned int births = 0;
  };

  /**
   * The adaptive step control's account of a step (Time stepping/Step
   * control = adaptive; core/step_control.h): the attempts redone shorter
   * before this one stood, the changes this one made (the largest of a free
   * node's temperature, K, and of a node's phase index), and whether it stood
   * only because it was at the minimum step.
   */
  struct StepControlReport
  {
    unsigned int rejected           = 0;
    double       temperature_change = 0, phase_change = 0;
    bool         at_minimum = false;
  };

  /**
   * The run as a part sees it: the scene context that the fields share
   * (core/scene_context.h: scene, materials, functions, mesh, timer, screen),
   * the Output entries, the fields (null: that physics is off; parts read them
   * and never change them) and the names of the run's parts.
   */
  template <int dim>
  struct RunContext : SceneContext<dim>
  {
    RunContext(const SceneContext<dim>  &context,
               const Parameters::Output &output,
               const bool                adaptive)
      : SceneContext<dim>(context)
      , output(output)
      , mpi_communicator(context.triangulation.get_communicator())
      , adaptive(adaptive)
    {}

    const Parameters::Output &output;
    MPI_Comm                  mpi_communicator;
    /** The mesh adapts during the run. */
    bool                        adaptive;
    const ThermalField<dim>    *thermal    = nullptr;
    const MechanicalField<dim> *mechanical = nullptr;
    /** The names of the parts this run uses, in registry order. */
    std::vector<std::string> parts;

    bool uses_part(const std::string &name) const;
  };

  /**
   * One reporting point: step 0 is the initial state (time step 0, the contact
   * step that made the initial equilibrium), then each time step.
   */
  struct StepData
  {
    unsigned int              step;
    double                    time, time_step;
    bool                      last_step;
    const EnthalpyStepReport &thermal;
    const ContactStepReport  &contact;
    const CouplingReport     &coupling;
    const StepControlReport  &step_control;
    double                    wall_time;
  };

  /**
   * One row of the statistics table: the columns this scene has, each with
   * name, unit, meaning (the header's comment lines, at step 0) and this step's
   * value as written. A real value is checked before anything is written: every
   * number of the row is the same on every rank, and no row with a NaN may
   * reach the file.
   */
  class StatisticsRow
  {
  public:
    explicit StatisticsRow(const unsigned int step);
    void count(const std::string &name, const std::string &meaning, const unsigned int value);
    void real(const std::string &name,
              const std::string &unit,
              const std::string &meaning,
              const char        *format,
              const double       value);
    /** Appends the row to the file at path, at step 0 after the header (a fresh file). */
    void append_to(const std::string &path) const;

  private:
    struct Column
    {
      std::string name, unit, meaning, value;
    };
    const unsigned int  step;
    std::vector<Column> columns;
  };

  /**
   * The RESULT lines of a run, collected and checked before any is printed:
   * researchers publish these numbers, so a non-finite one stops the run with
   * an error (exit code 2) instead of reaching the output.
   *
   * The order is fixed by the slot each line goes to, then by the order the
   * parts add them (registry order), so that a new part never moves the lines
   * of another: the thermal field's lines, the thermal checks, the mechanical
   * field's lines, the mechanical checks, the coupling, the mesh, the solver
   * calls.
   */
  class ResultLines
  {
  public:
    enum class Slot
    {
      thermal,              // thermal statistics: steps, iterations, energy, melt area
      step_control,         // step control: attempts redone, shortest and longest step
      liquid_fraction,      // check 'liquid fraction'
      thermal_consistency,  // thermal statistics: nodes with h outside H(Theta)
      interface_heat,       // interface heat: heat through each conductance interface
      temperature,          // checks 'function', 'neumann': temperature errors
      equilibrium,          // check 'equilibrium'
      fronts,               // check 'neumann': front positions
      mechanical,           // mechanical statistics: iterations, forces, energy
      stress,               // check 'stress'
      section_forces,       // mechanical statistics: the section forces at the end
      section_force_errors, // check 'section normal force'
      contact_pressure,     // check 'contact pressure'
      gaps,                 // mechanical statistics: mean gap per contact group
      mortar,               // mortar statistics: couplings and force balance
      hertz,                // check 'hertz'
      patch,                // check 'patch'
      other_checks,         // any further check, in registry order
      coupling,             // coupling statistics
      adaptation,           // mesh statistics
      solver_calls,         // solver calls
      block_correction      // coupling statistics: the block correction's counts
    };

    void add(const Slot slot, const std::string &name, const double value);
    /** The lines in their order; throws if one is not finite. */
    std::vector<std::pair<std::string, double>> ordered() const;

  private:
    std::vector<std::pair<Slot, std::pair<std::string, double>>> lines;
  };

  /**
   * A part's parsed parameters (from its own entries); a part without any uses
   * this base. A part that gives the scene its exact temperature (Exact
   * solution/Type = neumann or function) returns a factory of fresh copies.
   */
  struct PartParameters
  {
    virtual ~PartParameters() = default;
    virtual std::function<std::unique_ptr<Function<2>>()> exact_temperature() const
    {
      return {};
    }
  };

  /** A part of the report. Every member is collective unless it says not. */
  template <int dim>
  class Part
  {
  public:
    explicit Part(const RunContext<dim> &run)
      : run(run)
    {}
    virtual ~Part() = default;

    /** At a reporting point, before the statistics row is written. */
    virtual void update(const StepData &)
    {}
    /** A mesh adaptation changed the total enthalpy by this (relative) amount. */
    virtual void record_adaptation(const double, const bool)
    {}
    /**
     * Large sliding: the mortar sides were coupled again after step 'step'
     * (CoupledProblem::follow_sliding_interfaces()), which changed the total
     * enthalpy by this (relative) amount; by interface with large sliding
     * ("interface k-l"), how far the step slid the sides, in master edges
     * (the same on every rank).
     */
    virtual void
    record_sliding(const unsigned int, const double, const std::map<std::string, double> &)
    {}
    /** Its columns of the row (not collective: every value is known on every rank). */
    virtual void add_columns(StatisticsRow &, const StepData &) const
    {}
    /** After the row, e.g. the VTU files. */
    virtual void write(const StepData &)
    {}
    /** Its RESULT lines at the end of the run. */
    virtual void add_results(ResultLines &, const unsigned int, const double) const
    {}
    /**
     * Rank 0 only, before the first reporting point: removes the files of the
     * output directory that an earlier run left of this part's output (those
     * of steps after last_kept_step; -1: all) and returns how many.
     */
    virtual unsigned int remove_stale_files(const long) const
    {
      return 0;
    }
    /** Its self-checks that failed, one sentence each (not collective). */
    virtual void add_failures(std::vector<std::string> &) const
    {}
    /**
     * What it accumulated over the run, as text. Rank 0 only (the checkpoint
     * is written there), so not collective: the state must be the same on
     * every rank. load() runs on every rank.
     */
    virtual std::string save() const
    {
      return "";
    }
    virtual void load(const std::string &)
    {}

  protected:
    const RunContext<dim> &run;
  };

  /**
   * A part whose state over the run is one struct State (with a boost
   * serialize()): save() and load() archive it.
   */
  template <int dim, class State>
  class PartWithState : public Part<dim>
  {
  public:
    using Part<dim>::Part;
    std::string save() const override
    {
      std::ostringstream text;
      {
        boost::archive::text_oarchive archive(text);
        archive << state;
      }
      return text.str();
    }
    void load(const std::string &saved) override
    {
      std::istringstream            text(saved);
      boost::archive::text_iarchive archive(text);
      archive >> state;
    }

  protected:
    State state;
  };

  /**
   * A registered part: its name (as 'Exact solution/Type' or the report names
   * it), a one-paragraph description (for --print-parameters and
   * doc/architecture.md), its parameters and its factory.
   */
  struct PartInfo
  {
    std::string name, description;
    /** Chosen by 'Exact solution/Type' = name (one per run); else by its entries or the physics. */
    bool exact_solution = false;
    /** It gives the scene an exact temperature (PartParameters::exact_temperature()). */
    bool gives_temperature = false;
    /** Declares its entries (in their subsection, e.g. 'Exact solution'); may be empty. */
    std::function<void(ParameterHandler &)> declare;
    /**
     * Its parameters for this scene, or null if the scene does not use it
     * (chosen: 'Exact solution/Type' names it). The file is parsed and the
     * scene read; throws InputError naming the entry.
     */
    std::function<std::shared_ptr<const PartParameters>(ParameterHandler &,
                                                        const SceneParameters &,
                                                        const bool chosen)>
      parse;
    /** The part (2D; a 3D port adds its factory beside it). */
    std::function<std::unique_ptr<Part<2>>(const RunContext<2> &, const PartParameters &)> create;
  };

  /**
   * PartInfo::create for a part class P<2>: made from the run alone, or (with
   * its parameters' type Params) from the run and its parameters.
   */
  template <template <int> class P, class Params = void>
  auto part_factory()
  {
    return
      [](const RunContext<2> &run, const PartParameters &parameters) -> std::unique_ptr<Part<2>> {
        if constexpr (std::is_void_v<Params>)
          {
            (void)parameters;
            return std::make_unique<P<2>>(run);
          }
        else
          return std::make_unique<P<2>>(run, dynamic_cast<const Params &>(parameters));
      };
  }

  /** The largest cell extent in x over the mesh (collective). */
  template <int dim>
  double mesh_width(const parallel::distributed::Triangulation<dim> &triangulation);
} // namespace ContactStefan

#endif
