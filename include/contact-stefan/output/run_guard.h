// What protects a run's output from other runs and from signals
// (doc/reliability.md, "Output directories and signals"):
//
//  * OutputDirectoryLock: one run at a time writes into an output directory.
//    The lock is an advisory flock() on the directory itself (no file is
//    written, so a run refused for bad input leaves the directory as it was,
//    or removes it if it made it and wrote nothing into it);
//    a refused run names the holder's process id from the kernel's lock table.
//    The kernel drops the lock with the process, so a killed run never leaves
//    a stale lock behind.
//  * remove_stale_output(): the VTU/PVTU/PVD files in an output directory that
//    the starting run does not own (an earlier run's, also pieces '*.k.vtu'
//    written on more ranks) are removed before the first is written.
//  * StopSignals: SIGTERM, SIGINT, SIGUSR1 and SIGUSR2 only set a flag; the
//    time loop looks at it between steps (all ranks agree), ends with its
//    output complete (a checkpoint if checkpoints are on) and exits with
//    128 + the signal's number. A second signal ends the process at once.
//    (Open MPI's mpirun forwards SIGUSR1/2 to the ranks and waits; SIGTERM it
//    follows with SIGKILL after a second: the way to stop a run under mpirun
//    is SIGUSR1.)
#ifndef contact_stefan_run_guard_h
#define contact_stefan_run_guard_h

#include <deal.II/base/mpi.h>

#include <csignal>
#include <stdexcept>
#include <string>
#include <vector>

namespace ContactStefan
{
  class OutputDirectoryLock
  {
  public:
    /**
     * Takes the lock or throws a runtime_error naming the directory and the
     * process that holds it. Not collective (rank 0).
     */
    explicit OutputDirectoryLock(const std::string &directory);
    /**
     * Releases the lock; the directories the run made (created()) and left
     * empty, because it was refused before writing anything, are removed.
     */
    ~OutputDirectoryLock();
    /**
     * The directories the run made, the deepest first: the output directory
     * (if it did not exist before) and the parents it made with it.
     */
    void created(const std::vector<std::string> &directories)
    {
      made = directories;
    }
    OutputDirectoryLock(const OutputDirectoryLock &)            = delete;
    OutputDirectoryLock &operator=(const OutputDirectoryLock &) = delete;

  private:
    std::string              directory;
    int                      descriptor = -1;
    std::vector<std::string> made;
  };

  /**
   * Removes 'solution.pvd' and every 'solution_NNNNN.vtu', 'solution_NNNNN.k.vtu'
   * and 'solution_NNNNN.pvtu' of 'directory' whose step NNNNN is larger than
   * last_kept_step (a fresh run: -1, everything; a resumed one: the
   * checkpoint's step, whose earlier files are its own). Returns the number
   * of files removed. Not collective (rank 0).
   */
  unsigned int remove_stale_output(const std::string &directory, const long last_kept_step);

  /**
   * Writes text to path through a temporary file in the same directory and a
   * rename, so that path always holds either the old or the new whole text.
   */
  void write_file_atomically(const std::string &path, const std::string &text);

  // What made a run, kept in 'provenance.json' in its output directory (rank 0;
  // doc/output.md): the program's version line, the command line, the number
  // of ranks, the MPI start settings it ran with (app/mpi_start.h), the
  // parameter files and the parameter text as read (includes expanded), the
  // start time, and, when it ends, the end time and the exit code. Written
  // when the run has its output directory (a run refused for bad input before
  // that writes none) and again at the end; a resumed run keeps the record of
  // the run it continues under "previous".
  namespace RunRecord
  {
    void begin(const std::string                                      &version_line,
               const std::vector<std::string>                         &command_line,
               const unsigned int                                      n_ranks,
               const std::vector<std::pair<std::string, std::string>> &mpi_start);
    /** The parameters as read: the files and the expanded text. */
    void set_parameters(const std::vector<std::string> &files, const std::string &text);
    /** The run owns `directory` now: write the record (status "running"). */
    void write(const std::string &directory, const bool resumed);
    /** The run ends with this exit code: rewrite the record, if written. */
    void finish(const int exit_code);
  } // namespace RunRecord

  /**
   * Thrown between two time steps when a stop signal arrived; the output is
   * complete up to that step. main() exits with 128 + signal.
   */
  class StoppedBySignal : public std::runtime_error
  {
  public:
    StoppedBySignal(const int signal, const std::string &message)
      : std::runtime_error(message)
      , signal(signal)
    {}
    const int signal;
  };

  /**
   * Fault injection for the restart and signal tests: if the environment
   * variable holds this step number, the process sends itself the signal
   * (SIGKILL: uncatchable, as an external kill -9). Unset in normal runs.
   */
  void kill_if_asked(const char *variable, const unsigned int step, const int signal = SIGKILL);

  namespace StopSignals
  {
    /** Holds the stop signals back in this thread (and the threads it starts). */
    void block();
    /** Installs the handlers of the stop signals. */
    void install();
    /** Lets the stop signals through again (one that arrived meanwhile now). */
    void unblock();
    /** The signal received so far on this rank (0: none). */
    int received();
    /** Collective: the signal any rank received (0: none), the same on all ranks. */
    int received_by_any(const MPI_Comm comm);
    /** "SIGTERM", "SIGINT", "SIGUSR1", "SIGUSR2", or the number. */
    std::string name(const int signal);
  } // namespace StopSignals
} // namespace ContactStefan

#endif
