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
// An isolated singleton needs a session directory of its own. Open MPI names
// every isolated singleton alike (job family 0, job 1), so all of them share
// the session directory <tmp>/ompi.<host>.<uid>/jf.0/1, and each removes it at
// MPI_Finalize when it finds it empty. Open MPI's shared-file-pointer
// component puts a file there at every MPI_File_open (a checkpoint's mesh
// files), so a serial run that wrote a checkpoint after another serial run had
// ended found the directory gone: "unable to open file for mmap", and a failed
// run (p4est aborted) when the directory vanished between the component's
// query and its open -- 1 of 18 and 3 of 90 runs, 6 at a time, each with a
// checkpoint per step (2026-11-29), and one CI run of the test suite. Hence
// the run's own job-family directory, <tmp>/contact-stefan-mpi.<uid>/<pid>,
// which Open MPI creates and removes at MPI_Finalize like its own (a run
// killed by SIGKILL leaves it behind, empty or with one stale file, as Open
// MPI's own directories are left). <tmp> is Open MPI's choice: the parameter
// orte_tmpdir_base, else TMPDIR, TEMP, TMP, else /tmp.
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

#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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

    /** The variable of an isolated singleton's own session directory. */
    inline const char *session_directory_variable()
    {
      return "OMPI_MCA_orte_jobfam_session_dir";
    }

    /** A process's identity, for its session directory. */
    struct Process
    {
      unsigned long user_id;
      long          process_id;
    };

    /** This process's identity. */
    inline Process this_process()
    {
      return {static_cast<unsigned long>(getuid()), static_cast<long>(getpid())};
    }

    /**
     * The session directory of an isolated singleton (see the top of this
     * file): <tmp>/contact-stefan-mpi.<uid>/<pid>, <tmp> as Open MPI chooses
     * it.
     */
    inline std::string session_directory(const Lookup &lookup, const Process &process)
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
      return base + "/contact-stefan-mpi." + std::to_string(process.user_id) + "/" +
             std::to_string(process.process_id);
    }

    /**
     * Whether a singleton started with these settings may be isolated: unless
     * the user set the variable to a false value (0, false, no in any case).
     * (A session directory of its own does no harm to a singleton with a
     * daemon, which shares it with its daemon only.)
     */
    inline bool isolated_singleton(const Lookup &lookup)
    {
      const char *value = lookup("OMPI_MCA_ess_singleton_isolated");
      if (value == nullptr)
        return true;
      std::string lower;
      for (const char *c = value; *c; ++c)
        lower += (*c >= 'A' && *c <= 'Z') ? char(*c - 'A' + 'a') : *c;
      return lower != "0" && lower != "false" && lower != "no";
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
     * The settings this process should make before MPI_Init: none under a
     * launcher or with CONTACT_STEFAN_SERIAL_MPI=plain; else those of
     * serial_settings() whose variable is not set yet, and, when the
     * singleton is isolated (by these settings or by the user), its own
     * session directory unless the user set one. Without a launcher, a value
     * of the switch other than "fast" (the default, also when empty) or
     * "plain" is refused with one line (std::invalid_argument).
     */
    inline std::vector<Setting> settings_to_make(const Lookup  &lookup,
                                                 const Process &process = this_process())
    {
      std::vector<Setting> to_make;
      if (started_by_launcher(lookup))
        return to_make;
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
      if (choice == "plain")
        return to_make;
      for (const auto &setting : serial_settings())
        if (lookup(setting.first.c_str()) == nullptr)
          to_make.push_back(setting);
      if (isolated_singleton(lookup) && lookup(session_directory_variable()) == nullptr)
        to_make.emplace_back(session_directory_variable(), session_directory(lookup, process));
      return to_make;
    }

    /**
     * Makes the settings in this process's environment (before MPI_Init).
     * Throws std::invalid_argument for a bad switch value.
     */
    inline void prepare()
    {
      for (const auto &[name, value] : settings_to_make(process_environment()))
        setenv(name.c_str(), value.c_str(), /*overwrite=*/0);
    }

    /**
     * For the provenance record: the variables of serial_settings(), the
     * session directory's and the switch that are set, with their values, whoever set them (this
     * program, the user or mpirun, which passes the user's OMPI_MCA_ variables on).
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
