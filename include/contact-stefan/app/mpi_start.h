// How a run starts MPI when it is a process of its own, not started by mpirun.
//
// Why: started by itself, an Open MPI process becomes a "singleton". Its
// MPI_Init forks a daemon (orted) that would serve MPI_Comm_spawn, and it
// chooses its point-to-point layer by loading every candidate, including the
// cm layer with the drivers of PSM and PSM2 interconnects (libpsm2,
// libpsm_infinipath) that a workstation does not have. A serial run of this
// program needs neither: it asks for an isolated singleton (no daemon) and the
// ob1 layer. A bare MPI_Init and MPI_Finalize took 0.042 s instead of 0.374 s
// with Open MPI's defaults and 0.248 s with the isolated singleton alone
// (medians of 15 alternating runs by a reviewer on the 2-core development VM,
// 2026-11-28). Limiting the other frameworks' components as well (transports,
// collectives, the run-time's frameworks, hwloc's plugins) gave 0.036 s, less
// than the machine's noise in a whole run, and two of them (the run-time's
// state and error managers) break a singleton that is not isolated: not done.
//
// A serial run needs a session directory of its own. Open MPI names every
// isolated singleton alike (job family 0, job 1), so all of them share the
// session directory <tmp>/ompi.<host>.<uid>/jf.0/1, and each removes it at
// MPI_Finalize when it finds it empty. Open MPI's shared-file-pointer
// component puts a file there at every MPI_File_open (a checkpoint's mesh
// files), so a serial run that wrote a checkpoint after another serial run had
// ended found the directory gone: "unable to open file for mmap", and a failed
// run (p4est aborted) when the directory vanished between the component's
// query and its open -- 1 of 18 and 3 of 90 runs, 6 at a time, each with a
// checkpoint per step (2026-11-29), and one CI run of the test suite. Hence a
// job-family directory per run (OMPI_MCA_orte_jobfam_session_dir), made before
// MPI_Init by mkdtemp as <tmp>/contact-stefan-mpi.<uid>/<host>.<pid>.XXXXXX
// (mode 0700, a name no other run can take, on a shared file system too) and
// removed by Open MPI at MPI_Finalize like its own; a run killed by SIGKILL
// leaves it behind with Open MPI's job directories in it, as Open MPI's own
// are left (the gap between the parent's check and mkdtemp matters only where
// <tmp> is writable by others and not sticky, as for Open MPI's own).
// The parent is used only if it is a directory of this user closed to others
// (not a symlink, not group- or world-writable); else the directory is made
// in <tmp> itself, as contact-stefan-mpi.<uid>.<host>.<pid>.XXXXXX. <tmp> is
// the environment's OMPI_MCA_orte_tmpdir_base, else the first non-empty of
// TMPDIR, TEMP and TMP, else /tmp (Open MPI's order; unlike Open MPI, an empty
// variable is passed over and its parameter files are not read). If no
// directory can be made, a warning says so and Open MPI's default stands. Made
// only with Open MPI before 5 (ORTE's variable) and when MPI starts (not for
// --check). One name stays shared: the semaphore /dev/shm/sem.OMPIO_<file
// name> that the same component opens and unlinks within each MPI_File_open
// (harmless between runs of one user).
// With CONTACT_STEFAN_SERIAL_MPI=plain no directory is made: a singleton with
// its daemon has a job family of its own.
//
// Rules: under a launcher (mpirun, mpiexec, or srun with PMI-2 or PMIx)
// nothing is set and the switch below is not read, because the launcher and
// the cluster know the transport; a variable set in the environment stays as
// it is (the values set here override Open MPI's parameter files, as any
// environment variable does); CONTACT_STEFAN_SERIAL_MPI=plain sets nothing.
// Other MPI implementations ignore the OMPI_MCA_ variables. The provenance
// record (provenance.json, "mpi_start") lists which of these variables were
// set when a run started, whoever set them.
#ifndef contact_stefan_mpi_start_h
#define contact_stefan_mpi_start_h

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <mpi.h>
#include <sys/stat.h>
#include <unistd.h>

namespace ContactStefan
{
  namespace MpiStart
  {
    /** A variable name and the value it gets. */
    using Setting = std::pair<std::string, std::string>;

    /** Looks a variable up: its value, or nullptr if it is not set. */
    using Lookup = std::function<const char *(const char *)>;

    /**
     * What a process that is its own only rank sets, each with its reason.
     * The component names are those of Open MPI 4.1 (Debian 12).
     */
    inline const std::vector<Setting> &serial_settings()
    {
      static const std::vector<Setting> settings = {
        // No daemon (orted) for MPI_Comm_spawn, which this program never calls.
        {"OMPI_MCA_ess_singleton_isolated", "1"},
        // The ob1 point-to-point layer, without the selection among all of
        // them: that selection loads the cm layer and its drivers for PSM and
        // PSM2 interconnects (libpsm2, libpsm_infinipath) only to find no such
        // hardware. ob1 is part of every Open MPI build.
        {"OMPI_MCA_pml", "ob1"}};
      return settings;
    }

    /** This process's environment, as a Lookup. */
    inline Lookup process_environment()
    {
      return [](const char *variable) -> const char * { return std::getenv(variable); };
    }

    /**
     * Whether the MPI this program is built with is Open MPI before 5: only
     * it uses (and removes) the session directory made below.
     */
    // (Open MPI 5 has no ORTE: it would ignore the directory and leave it.)
#if defined(OPEN_MPI) && OMPI_MAJOR_VERSION < 5
    constexpr bool built_with_open_mpi = true;
#else
    constexpr bool built_with_open_mpi = false;
#endif

    /** The variable of a serial run's own session directory. */
    inline const char *session_directory_variable()
    {
      return "OMPI_MCA_orte_jobfam_session_dir";
    }

    /**
     * Where a serial run's session directory goes (see the top of this
     * file): the environment's OMPI_MCA_orte_tmpdir_base, else the first
     * non-empty of TMPDIR, TEMP and TMP, else /tmp; without trailing slashes
     * ("/" stays "/").
     */
    inline std::string session_base(const Lookup &lookup)
    {
      std::string base = "/tmp";
      for (const char *variable : {"OMPI_MCA_orte_tmpdir_base", "TMPDIR", "TEMP", "TMP"})
        if (const char *value = lookup(variable); value && *value)
          {
            base = value;
            break;
          }
      while (base.size() > 1 && base.back() == '/')
        base.pop_back();
      return base;
    }

    /** A file name in a directory ("/" without a doubled slash). */
    inline std::string in_directory(const std::string &directory, const std::string &name)
    {
      return directory == "/" ? "/" + name : directory + "/" + name;
    }

    /**
     * Makes a fresh session directory by mkdtemp (mode 0700):
     * <base>/contact-stefan-mpi.<uid>/<host>.<pid>.XXXXXX, the parent made
     * (mode 0700) if it is missing; if the parent is not a directory of
     * user_id closed to others (a symlink, another owner, group- or
     * world-writable) or nothing can be made in it,
     * <base>/contact-stefan-mpi.<uid>.<host>.<pid>.XXXXXX. Returns its path,
     * or "" if none could be made (errno says why).
     */
    inline std::string make_session_directory(const std::string  &base,
                                              const unsigned long user_id,
                                              const std::string  &host,
                                              const long          process_id)
    {
      const std::string name   = "contact-stefan-mpi." + std::to_string(user_id);
      const std::string parent = in_directory(base, name);
      const std::string leaf   = host + "." + std::to_string(process_id) + ".XXXXXX";
      (void)mkdir(parent.c_str(), S_IRWXU);
      struct stat status;
      const bool  usable = lstat(parent.c_str(), &status) == 0 && S_ISDIR(status.st_mode) &&
                          status.st_uid == user_id && (status.st_mode & (S_IRWXG | S_IRWXO)) == 0;
      if (usable)
        {
          std::string path = in_directory(parent, leaf);
          if (mkdtemp(path.data()) != nullptr)
            return path;
        }
      std::string path = in_directory(base, name + "." + leaf);
      return mkdtemp(path.data()) != nullptr ? path : std::string();
    }

    /** This machine's name up to its first dot ("host" if it has none). */
    inline std::string short_host_name()
    {
      char name[256] = {};
      if (gethostname(name, sizeof(name) - 1) != 0 || name[0] == 0)
        return "host";
      std::string host = name;
      host             = host.substr(0, host.find('.'));
      for (char &c : host)
        if (c == '/')
          c = '_';
      return host;
    }

    /** The variable that switches the serial settings off. */
    inline const char *switch_variable()
    {
      return "CONTACT_STEFAN_SERIAL_MPI";
    }

    /**
     * Whether a launcher started this process: the rank variables of Open MPI's
     * mpirun, of MPICH's and Slurm's PMI and of PMIx.
     */
    inline bool started_by_launcher(const Lookup &lookup)
    {
      for (const char *variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
        if (lookup(variable) != nullptr)
          return true;
      return false;
    }

    /**
     * Whether this process is a serial run with the switch at "fast" (the
     * default, also when empty): no launcher, and the switch not "plain".
     * Without a launcher, a value of the switch other than "fast" or "plain"
     * is refused with one line (std::invalid_argument).
     */
    inline bool fast_serial_start(const Lookup &lookup)
    {
      if (started_by_launcher(lookup))
        return false;
      const char       *choice_value = lookup(switch_variable());
      const std::string choice       = choice_value && *choice_value ? choice_value : "fast";
      if (choice != "fast" && choice != "plain")
        {
          // The value as printable ASCII (one line whatever it holds).
          std::string shown;
          for (const unsigned char c : choice.substr(0, 40))
            shown += c >= 0x20 && c < 0x7f ? char(c) : '?';
          throw std::invalid_argument(std::string(switch_variable()) + " is '" + shown +
                                      "'; it must be 'fast' (the default: a serial run starts "
                                      "MPI without a daemon and with the ob1 layer) or "
                                      "'plain' (Open MPI's own defaults)");
        }
      return choice == "fast";
    }

    /**
     * The settings this process should make before MPI_Init: none under a
     * launcher or with CONTACT_STEFAN_SERIAL_MPI=plain; else those of
     * serial_settings() whose variable is not set yet. (The session
     * directory is not among them: prepare() makes it.) A bad switch value
     * is refused as by fast_serial_start().
     */
    inline std::vector<Setting> settings_to_make(const Lookup &lookup)
    {
      std::vector<Setting> to_make;
      if (!fast_serial_start(lookup))
        return to_make;
      for (const auto &setting : serial_settings())
        if (lookup(setting.first.c_str()) == nullptr)
          to_make.push_back(setting);
      return to_make;
    }

    /** Whether prepare() makes a session directory: a fast serial start whose user set none. */
    inline bool wants_session_directory(const Lookup &lookup)
    {
      return fast_serial_start(lookup) && lookup(session_directory_variable()) == nullptr;
    }

    /**
     * Makes the settings in this process's environment (before MPI_Init) and,
     * with Open MPI before 5, if MPI is to start (mpi_starts) and
     * wants_session_directory(), the run's session directory; if none can be
     * made, says so in one line on standard error and goes on with Open
     * MPI's default. Throws std::invalid_argument for a bad switch value.
     */
    inline void prepare(const bool mpi_starts)
    {
      const Lookup environment = process_environment();
      for (const auto &[name, value] : settings_to_make(environment))
        setenv(name.c_str(), value.c_str(), /*overwrite=*/0);
      if (built_with_open_mpi && mpi_starts && wants_session_directory(environment))
        {
          const std::string base = session_base(environment);
          const std::string directory =
            make_session_directory(base, getuid(), short_host_name(), static_cast<long>(getpid()));
          const int         why       = errno;
          if (!directory.empty())
            setenv(session_directory_variable(), directory.c_str(), /*overwrite=*/0);
          else
            std::fprintf(stderr,
                         "contact-stefan: warning: no session directory for Open MPI could be "
                         "made in '%s' (%s); serial runs at the same time may fail when they "
                         "write checkpoints (set TMPDIR to a writable directory)\n",
                         base.c_str(),
                         std::strerror(why));
        }
    }

    /**
     * For the provenance record: the variables of serial_settings(), the
     * session directory's and the switch that are set, with their values,
     * whoever set them (this program, the user or mpirun, which passes the
     * user's OMPI_MCA_ variables on).
     */
    inline std::vector<Setting> recorded_settings(const Lookup &lookup)
    {
      std::vector<Setting> recorded;
      for (const auto &setting : serial_settings())
        if (const char *value = lookup(setting.first.c_str()))
          recorded.emplace_back(setting.first, value);
      if (const char *value = lookup(session_directory_variable()))
        recorded.emplace_back(session_directory_variable(), value);
      if (const char *value = lookup(switch_variable()))
        recorded.emplace_back(switch_variable(), value);
      return recorded;
    }
  } // namespace MpiStart
} // namespace ContactStefan

#endif
