// Postprocessor (output/postprocessor.h): the output directory, the parts, and
// the order in which they are called at each reporting point: every part
// updates itself, then the statistics row is written (step, time, each part's
// columns, the wall time), then the parts write their files.
#include <contact-stefan/output/postprocessor.h>

#include <filesystem>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <vector>

namespace ContactStefan
{
  template <int dim>
  Postprocessor<dim>::Postprocessor(const SceneContext<dim>  &scene_context,
                                    const Parameters::Output &output,
                                    const bool                adaptive)
    : context(scene_context, output, adaptive)
  {
    // The output directory must be usable before any work is done. Rank 0 checks
    // and every rank learns the verdict, so that all of them stop together.
    std::string    problem;
    const MPI_Comm comm = context.mpi_communicator;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      {
        std::error_code   error;
        const std::string directory = output.directory;
        // The directories this run makes, the deepest first: the output
        // directory and any parents that did not exist either.
        std::vector<std::string> made;
        {
          std::filesystem::path p = std::filesystem::path(directory).lexically_normal();
          if (!p.has_filename())
            p = p.parent_path();
          while (!p.empty() && !std::filesystem::exists(p, error))
            {
              made.push_back(p.string());
              p = p.parent_path();
            }
        }
        std::filesystem::create_directories(directory, error);
        const std::string probe = directory + "/.contact-stefan-write-test";
        if (error || !std::filesystem::is_directory(directory))
          problem = "cannot create the directory '" + directory + "'";
        else if (!std::ofstream(probe))
          problem = "cannot write into '" + directory + "'";
        std::filesystem::remove(probe, error);
        // One run at a time: a second run into the same directory would
        // interleave its statistics rows and VTU files with this one's.
        if (problem.empty())
          try
            {
              output_lock = std::make_unique<OutputDirectoryLock>(directory);
              // A run refused before it writes leaves no empty directory behind.
              output_lock->created(made);
            }
          catch (const std::exception &e)
            {
              problem = e.what();
            }
      }
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    if (!problem.empty())
      throw InputError("Output/Directory", problem);
  }



  template <int dim>
  void Postprocessor<dim>::attach(
    const ThermalField<dim>    *thermal,
    const MechanicalField<dim> *mechanical,
    const std::vector<std::pair<const PartInfo *, std::shared_ptr<const PartParameters>>>
      &selection)
  {
    context.thermal    = thermal;
    context.mechanical = mechanical;
    parts.clear();
    context.parts.clear();
    part_parameters.clear();
    // (A part may decline, e.g. the mesh statistics of a fixed mesh.)
    for (const auto &[info, parameters] : selection)
      if (std::unique_ptr<Part<dim>> part = info->create(context, *parameters))
        {
          context.parts.push_back(info->name);
          parts.emplace_back(info->name, std::move(part));
          part_parameters.push_back(parameters);
        }
  }



  template <int dim>
  void Postprocessor<dim>::remove_stale_output(const long last_kept_step) const
  {
    const MPI_Comm comm    = context.mpi_communicator;
    unsigned int   removed = 0;
    std::string    problem;
    if (Utilities::MPI::this_mpi_process(comm) == 0)
      try
        {
          for (const auto &[name, part] : parts)
            removed += part->remove_stale_files(last_kept_step);
        }
      catch (const std::exception &e)
        {
          problem = e.what();
        }
    problem = Utilities::MPI::broadcast(comm, problem, 0);
    if (!problem.empty())
      throw std::runtime_error(problem);
    removed = Utilities::MPI::broadcast(comm, removed, 0);
    context.pcout << "Output: '" << context.output.directory << "'";
    if (removed > 0)
      context.pcout << " (removed " << removed << " VTU/PVD files of an earlier run"
                    << (last_kept_step >= 0 ? " after the checkpoint's step" : "") << ")";
    context.pcout << std::endl;
    // What made the report: its parts (doc/architecture.md).
    std::string names;
    for (const auto &name : context.parts)
      names += (names.empty() ? "" : ", ") + name;
    context.pcout << "Report: " << names << std::endl;
  }



  template <int dim>
  void Postprocessor<dim>::start(const double             time,
                                 const ContactStepReport &initial_contact,
                                 const double             wall_time)
  {
    const EnthalpyStepReport no_thermal_step;
    const CouplingReport     no_coupling;
    const StepControlReport  no_step_control;
    report({0,
            time,
            0.,
            false,
            no_thermal_step,
            initial_contact,
            no_coupling,
            no_step_control,
            wall_time});
  }



  template <int dim>
  void Postprocessor<dim>::end_step(const unsigned int        step,
                                    const double              time,
                                    const double              time_step,
                                    const bool                last_step,
                                    const EnthalpyStepReport &thermal_report,
                                    const ContactStepReport  &contact_report,
                                    const CouplingReport     &coupling_report,
                                    const StepControlReport  &step_control_report,
                                    const double              wall_time)
  {
    report({step,
            time,
            time_step,
            last_step,
            thermal_report,
            contact_report,
            coupling_report,
            step_control_report,
            wall_time});
  }



  // The statistics table: a header (comment lines, then the column names), then
  // one line per step, appended and flushed as soon as the step is done, so
  // that an interrupted run leaves every finished step on disk and a long run
  // costs O(1) per step. Only rank 0 writes.
  template <int dim>
  void Postprocessor<dim>::report(const StepData &data)
  {
    for (const auto &[name, part] : parts)
      part->update(data);
    StatisticsRow row(data.step);
    row.count("step", "time step number (0: the initial state)", data.step);
    row.real("time", "s", "time at the end of the step", "%.10e", data.time);
    for (const auto &[name, part] : parts)
      part->add_columns(row, data);
    row.real("wall_time",
             "s",
             "wall-clock time since the run started (resumed: since the first)",
             "%.3f",
             data.wall_time);
    if (Utilities::MPI::this_mpi_process(context.mpi_communicator) == 0)
      row.append_to(context.output.directory + "/" + context.output.statistics_file);
    for (const auto &[name, part] : parts)
      part->write(data);
  }



  template <int dim>
  void Postprocessor<dim>::record_adaptation(const double relative_enthalpy_change,
                                             const bool   coarsened)
  {
    for (const auto &[name, part] : parts)
      part->record_adaptation(relative_enthalpy_change, coarsened);
  }



  template <int dim>
  void Postprocessor<dim>::record_sliding(const unsigned int step,
                                          const double       relative_enthalpy_change,
                                          const std::map<std::string, double> &slide)
  {
    for (const auto &[name, part] : parts)
      part->record_sliding(step, relative_enthalpy_change, slide);
  }



  // The run's own checks that do not stop it (its output is complete and
  // finite) but that a researcher must know of before using its numbers.
  template <int dim>
  std::vector<std::string> Postprocessor<dim>::failed_diagnostics() const
  {
    std::vector<std::string> failed;
    for (const auto &[name, part] : parts)
      part->add_failures(failed);
    return failed;
  }



  template <int dim>
  void Postprocessor<dim>::print_results(const unsigned int n_steps, const double time) const
  {
    ResultLines results;
    for (const auto &[name, part] : parts)
      part->add_results(results, n_steps, time);
    for (const auto &[name, value] : results.ordered())
      context.pcout << "RESULT " << name << " = " << std::setprecision(10) << value << std::endl;
  }



  template <int dim>
  void Postprocessor<dim>::load_states(const std::map<std::string, std::string> &states)
  {
    for (const auto &[name, part] : parts)
      {
        const auto it = states.find(name);
        if (it == states.end())
          throw std::runtime_error("the checkpoint holds no state of the part '" + name + "'");
        part->load(it->second);
      }
  }



  template class Postprocessor<2>;
} // namespace ContactStefan
