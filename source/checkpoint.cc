// Checkpoint/restart of CoupledProblem (doc/adaptivity.md).
//
// A checkpoint is a directory, Output/Directory/checkpoint, holding
//   mesh*          the distributed triangulation (p4est) with the primary state
//                  of both fields attached: h, h_old, u, u_old (written by
//                  parallel::distributed::SolutionTransfer, so a resumed run
//                  may use any number of ranks)
//   state.txt      time, step, step length, the thermal field's restart
//                  scalars (warm start, large-step mode),
//                  the wall time so far and everything the postprocessor has
//                  accumulated (boost text archive; doubles round-trip exactly)
//   statistics     the statistics file up to the checkpoint's step
// It is written into checkpoint.new and then renamed: the old checkpoint is
// first renamed to checkpoint.old, the new one into place, and the old one
// removed. A crash at any moment leaves a complete checkpoint under one of the
// two names, and resume() takes checkpoint, else checkpoint.old. (Nothing is
// fsync'd: this protects against a killed process, not against a power loss.)
//
// Everything derived (temperature, phase states, contact sets, per-cell
// operators) is recomputed on resume exactly as after a mesh change. The
// uninterrupted run does the same right after writing a checkpoint (and starts
// its solvers afresh), so a resumed run repeats the steps of the uninterrupted
// one, iteration for iteration.
#include <deal.II/base/mpi.h>

#include <deal.II/distributed/solution_transfer.h>

#include <deal.II/dofs/dof_tools.h>

#include <boost/archive/text_iarchive.hpp>
#include <boost/archive/text_oarchive.hpp>

#include <contact-stefan/coupled_problem.h>
#include <contact-stefan/mesh.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace ContactStefan
{
  namespace fs = std::filesystem;

  // The first line of a checkpoint's state.txt. Raised whenever what it
  // serialises changes (2: the linear solver statistics of the contact
  // reports), so that an older checkpoint is refused by name, not misread.
  const std::string checkpoint_format = "contact-stefan checkpoint 2";

  template <int dim>
  std::string CoupledProblem<dim>::checkpoint_directory(const std::string &suffix) const
  {
    return prm.output.directory + "/checkpoint" + suffix;
  }



  // What the attached vectors belong to: a checkpoint is only read by a scene
  // with the same fields, bodies and coarse mesh size (a different scene would
  // misread the mesh data or the vectors).
  template <int dim>
  std::string CoupledProblem<dim>::fields_fingerprint() const
  {
    std::string text = std::string(thermal ? "thermal" : "no thermal") +
                       (mechanical ? " and mechanical" : " and no mechanical") + " fields, bodies";
    for (const unsigned int b : prm.body_ids)
      text += " " + std::to_string(b);
    // FNV-1a of the parameters that determine the solution (AllParameters::
    // solution_parameters: all but Checkpoint, Output and the end time).
    std::uint64_t hash = 14695981039346656037ull;
    for (const unsigned char c : prm.solution_parameters)
      hash = (hash ^ c) * 1099511628211ull;
    char hex[17];
    std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(hash));
    return text + ", " + std::to_string(triangulation.n_cells(0)) + " coarse cells, parameters " +
           hex;
  }



  // By step count, or by wall-clock time since the last checkpoint (the
  // slowest rank's clock decides, so that all ranks agree).
  template <int dim>
  bool CoupledProblem<dim>::checkpoint_due()
  {
    const auto &c = prm.checkpoint;
    if (c.interval_steps > 0 && step_number % c.interval_steps == 0)
      return true;
    if (c.interval_minutes > 0)
      {
        const double now = Utilities::MPI::max(wall_clock.wall_time() + wall_offset,
                                               triangulation.get_communicator());
        return now - last_checkpoint_wall >= 60 * c.interval_minutes;
      }
    return false;
  }



  namespace
  {
    // Ghosted copies of a field's primary state, attached to the mesh for
    // saving by a SolutionTransfer that must live until the save.
    template <int dim>
    struct Attached
    {
      Attached(const DoFHandler<dim> &dof_handler, const std::vector<Vector *> &state)
        : transfer(dof_handler)
      {
        IndexSet relevant;
        DoFTools::extract_locally_relevant_dofs(dof_handler, relevant);
        ghosted.resize(state.size());
        std::vector<const Vector *> inputs;
        for (unsigned int i = 0; i < state.size(); ++i)
          {
            ghosted[i].reinit(dof_handler.locally_owned_dofs(),
                              relevant,
                              dof_handler.get_communicator());
            ghosted[i] = *state[i];
            inputs.push_back(&ghosted[i]);
          }
        transfer.prepare_for_serialization(inputs);
      }
      parallel::distributed::SolutionTransfer<dim, Vector> transfer;
      std::vector<Vector>                                  ghosted;
    };

    // Runs fn on rank 0; every rank learns whether it failed and why.
    template <typename Function>
    void on_root(const MPI_Comm comm, const Function &fn)
    {
      std::string problem;
      if (Utilities::MPI::this_mpi_process(comm) == 0)
        try
          {
            fn();
          }
        catch (const std::exception &e)
          {
            problem = e.what();
          }
      problem = Utilities::MPI::broadcast(comm, problem, 0);
      if (!problem.empty())
        throw std::runtime_error(problem);
    }
  } // namespace



  // A fresh run starts a fresh history: checkpoints of an earlier run in the
  // same output directory are removed (its statistics file is overwritten too),
  // so that a later --resume cannot continue the earlier run with this one's rows.
  template <int dim>
  void CoupledProblem<dim>::remove_checkpoints()
  {
    on_root(triangulation.get_communicator(), [&]() {
      for (const char *suffix : {"", ".old", ".new"})
        fs::remove_all(checkpoint_directory(suffix));
    });
  }



  template <int dim>
  void CoupledProblem<dim>::write_checkpoint()
  {
    TimerOutput::Scope t(timer, "checkpoint");
    const MPI_Comm     comm = triangulation.get_communicator();
    const std::string  next = checkpoint_directory(".new"), current = checkpoint_directory(),
                      old = checkpoint_directory(".old");
    on_root(comm, [&]() {
      fs::remove_all(next);
      fs::create_directories(next);
    });

    // The mesh with the primary state attached (thermal first, then mechanical:
    // resume() reads them in this order).
    std::unique_ptr<Attached<dim>> thermal_state, mechanical_state;
    if (thermal)
      thermal_state =
        std::make_unique<Attached<dim>>(thermal->get_dof_handler(), thermal->primary_state());
    if (mechanical)
      mechanical_state =
        std::make_unique<Attached<dim>>(mechanical->get_dof_handler(), mechanical->primary_state());
    triangulation.save(next + "/mesh");
    kill_if_asked("CONTACT_STEFAN_KILL_DURING_CHECKPOINT", step_number);

    const double wall = Utilities::MPI::max(wall_offset + wall_clock.wall_time(), comm);
    on_root(comm, [&]() {
      {
        std::ofstream                 out(next + "/state.txt");
        boost::archive::text_oarchive archive(out);
        const std::string             format  = checkpoint_format;
        const unsigned int            n_ranks = Utilities::MPI::n_mpi_processes(comm);
        std::vector<double> thermal_scalars =
          thermal ? thermal->restart_state() : std::vector<double>();
        archive << format << fields_fingerprint() << n_ranks << time << time_step << step_number
                << thermal_scalars << wall;
        archive << *postprocessor;
        out.flush();
        if (!out)
          throw std::runtime_error("cannot write '" + next + "/state.txt'");
      }
      const std::string statistics = prm.output.directory + "/" + prm.output.statistics_file;
      fs::copy_file(statistics, next + "/statistics", fs::copy_options::overwrite_existing);
      // The swap: at every moment one complete checkpoint exists.
      if (fs::exists(current))
        {
          fs::remove_all(old);
          fs::rename(current, old);
        }
      fs::rename(next, current);
      fs::remove_all(old);
    });
    last_checkpoint_wall = wall;
    // From here on the run must do what a run resumed from this checkpoint
    // does: derive the state from the primary one and start the solvers
    // afresh (else the warm-started active sets and the reused factorisations
    // would differ, and so would the iteration counts after a resume).
    after_mesh_change();
    if (thermal)
      thermal->restart_solvers();
    if (mechanical)
      mechanical->restart_solvers();
    if (prm.output.verbosity >= 1)
      pcout << "    checkpoint written at step " << step_number << " into " << current << std::endl;
  }



  template <int dim>
  void CoupledProblem<dim>::resume()
  {
    const MPI_Comm comm = triangulation.get_communicator();
    // The checkpoint, or the previous one if a crash came between the renames.
    // (decided on rank 0 alone: ranks with cached views of a shared file
    // system must not load different directories)
    std::string directory = checkpoint_directory();
    if (!fs::exists(directory + "/state.txt") &&
        fs::exists(checkpoint_directory(".old") + "/state.txt"))
      directory = checkpoint_directory(".old");
    if (!fs::exists(directory + "/state.txt"))
      directory.clear();
    directory = Utilities::MPI::broadcast(comm, directory, 0);
    if (directory.empty())
      throw InputError("Checkpoint/Resume",
                       "there is no checkpoint in '" + checkpoint_directory() +
                         "' (a run writes one when 'Checkpoint/Interval (steps)' or 'Interval "
                         "(minutes)' is set)");

    // The coarse mesh (the checkpoint holds its refinement), then the state
    // file: a wrong or damaged checkpoint is refused before the mesh is loaded.
    {
      TimerOutput::Scope t(timer, "setup: mesh");
      make_mesh(prm, triangulation, true);
    }
    std::vector<double> thermal_scalars;
    double              wall = 0;
    {
      std::ifstream in(directory + "/state.txt");
      try
        {
          boost::archive::text_iarchive archive(in);
          std::string                   format, fields;
          unsigned int                  n_ranks = 0;
          archive >> format;
          if (format.rfind("contact-stefan checkpoint ", 0) == 0 && format != checkpoint_format)
            throw std::runtime_error("written in the format '" + format +
                                     "' of another version of contact-stefan, this one reads '" +
                                     checkpoint_format + "'");
          if (format != checkpoint_format)
            throw std::runtime_error("not a contact-stefan checkpoint");
          archive >> fields;
          if (fields != fields_fingerprint())
            throw std::runtime_error("it was written by a scene with " + fields +
                                     ", this one has " + fields_fingerprint());
          archive >> n_ranks >> time >> time_step >> step_number >> thermal_scalars >> wall;
          archive >> *postprocessor;
        }
      catch (const std::exception &e)
        {
          throw InputError("Checkpoint/Resume",
                           "cannot read '" + directory + "/state.txt' (" + e.what() + ")");
        }
    }
    if (!(time < prm.time.end_time))
      throw InputError("Checkpoint/Resume",
                       "the checkpoint is at t = " + number(time) +
                         ", not before 'Time stepping/End time' = " + number(prm.time.end_time));

    {
      TimerOutput::Scope t(timer, "setup: mesh");
      triangulation.load(directory + "/mesh");
    }
    if (thermal)
      thermal->setup_dofs();
    if (mechanical)
      mechanical->setup_dofs();
    const auto restore = [&](const DoFHandler<dim>       &dof_handler,
                             const std::vector<Vector *> &state) {
      parallel::distributed::SolutionTransfer<dim, Vector> transfer(dof_handler);
      std::vector<Vector>                                  values(state.size());
      std::vector<Vector *>                                outputs;
      for (auto &v : values)
        {
          v.reinit(dof_handler.locally_owned_dofs(), comm);
          outputs.push_back(&v);
        }
      transfer.deserialize(outputs);
      for (unsigned int i = 0; i < state.size(); ++i)
        *state[i] = values[i];
    };
    // Each field is set to the checkpoint's time (its data: loads, Dirichlet
    // values, gaps; an initial state that is then overwritten), the primary
    // state is read (in the order it was attached), and everything else is
    // re-derived from it as after a mesh change.
    if (thermal)
      thermal->initialize(time);
    if (mechanical)
      mechanical->initialize(time);
    if (thermal)
      {
        restore(thermal->get_dof_handler(), thermal->primary_state());
        thermal->set_restart_state(thermal_scalars);
      }
    if (mechanical)
      restore(mechanical->get_dof_handler(), mechanical->primary_state());
    after_mesh_change();

    on_root(comm, [&]() {
      fs::copy_file(directory + "/statistics",
                    prm.output.directory + "/" + prm.output.statistics_file,
                    fs::copy_options::overwrite_existing);
    });
    wall_offset          = wall;
    last_checkpoint_wall = wall;
    pcout << "Resumed from '" << directory << "' at step " << step_number << ", t = " << time
          << std::endl;
  }



  template bool        CoupledProblem<2>::checkpoint_due();
  template void        CoupledProblem<2>::write_checkpoint();
  template void        CoupledProblem<2>::remove_checkpoints();
  template void        CoupledProblem<2>::resume();
  template std::string CoupledProblem<2>::checkpoint_directory(const std::string &) const;
  template std::string CoupledProblem<2>::fields_fingerprint() const;
} // namespace ContactStefan
