// Postprocessor: everything a run reports, made by its parts (output/part.h):
// the VTU/PVD files, the per-step statistics table, the errors against exact
// solutions and the RESULT lines that end a run. It owns the output directory
// (locked for the run's lifetime), the context the parts read, and the parts;
// it calls them in registry order at every reporting point, and it never
// changes the fields.
#ifndef contact_stefan_postprocessor_h
#define contact_stefan_postprocessor_h

#include <boost/serialization/map.hpp>
#include <boost/serialization/split_member.hpp>
#include <boost/serialization/string.hpp>

#include <contact-stefan/output/part.h>
#include <contact-stefan/output/run_guard.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace ContactStefan
{
  template <int dim>
  class Postprocessor
  {
  public:
    /**
     * Creates the output directory and checks that it is writable (an
     * InputError naming Output/Directory otherwise), before any work is done.
     * adaptive: the mesh adapts during the run.
     */
    Postprocessor(const SceneContext<dim>  &context,
                  const Parameters::Output &output,
                  const bool                adaptive);

    /**
     * The fields to report on (either may be null: that physics is off) and
     * the parts the scene uses (coupling/part_registry.h), created here in
     * that order.
     */
    void attach(
      const ThermalField<dim>    *thermal,
      const MechanicalField<dim> *mechanical,
      const std::vector<std::pair<const PartInfo *, std::shared_ptr<const PartParameters>>> &parts);
    /** The names of the parts, in order. */
    const std::vector<std::string> &part_names() const
    {
      return context.parts;
    }

    /**
     * At the start time: statistics row 0 (with the contact step that made
     * the initial equilibrium), VTU 0.
     */
    void start(const double time, const ContactStepReport &initial_contact, const double wall_time);
    /** After a time step. */
    void end_step(const unsigned int        step,
                  const double              time,
                  const double              time_step,
                  const bool                last_step,
                  const EnthalpyStepReport &thermal_report,
                  const ContactStepReport  &contact_report,
                  const CouplingReport     &coupling_report,
                  const StepControlReport  &step_control_report,
                  const double              wall_time);
    /**
     * A mesh adaptation between two steps changed the total enthalpy by this
     * (relative) amount; coarsened: it coarsened cells (else refinement only).
     */
    void record_adaptation(const double relative_enthalpy_change, const bool coarsened);
    /**
     * The large-sliding mortar sides were coupled again before a step, which
     * changed the total enthalpy by this (relative) amount; slide: by
     * interface, how far the step before slid them (in master edges).
     */
    void record_sliding(const unsigned int                   step,
                        const double                         relative_enthalpy_change,
                        const std::map<std::string, double> &slide);
    /** The RESULT lines. */
    void print_results(const unsigned int n_steps, const double time) const;
    /** The self-checks the run failed, one sentence each (empty: none failed). */
    std::vector<std::string> failed_diagnostics() const;
    /**
     * Removes the files of the output directory that this run does not own
     * (those of steps after last_kept_step; -1: all) and says so. Collective.
     */
    void remove_stale_output(const long last_kept_step) const;

    /**
     * What the parts accumulated over the run, each part's state by its name,
     * for checkpoints: the same on every rank.
     */
    template <class Archive>
    void save(Archive &ar, const unsigned int) const
    {
      std::map<std::string, std::string> states;
      for (const auto &[name, part] : parts)
        states[name] = part->save();
      ar &states;
    }
    template <class Archive>
    void load(Archive &ar, const unsigned int)
    {
      std::map<std::string, std::string> states;
      ar                                &states;
      load_states(states);
    }
    BOOST_SERIALIZATION_SPLIT_MEMBER()

  private:
    void report(const StepData &data);
    void load_states(const std::map<std::string, std::string> &states);

    RunContext<dim>                                                 context;
    std::vector<std::pair<std::string, std::unique_ptr<Part<dim>>>> parts;
    // The parts' parameters, which the parts refer to: alive as long as they.
    std::vector<std::shared_ptr<const PartParameters>> part_parameters;
    /** Rank 0 holds the output directory's lock for the run's lifetime. */
    std::unique_ptr<OutputDirectoryLock> output_lock;
  };
} // namespace ContactStefan

#endif
