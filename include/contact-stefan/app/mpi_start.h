// How a run starts MPI when it is a process of its own, not started by mpirun.
//
// Why: Open MPI's MPI_Init opens every component of every framework it might
// use and keeps the best: TCP and shared-memory transports, the PSM, PSM2 and
// OFI drivers of cluster interconnects, a dozen collective algorithms, and
// hwloc's OpenCL and OpenGL plugins. A serial run uses none of them: its only
// rank talks to itself. Loading them costs a third of a second per run, in a
// code where a test or a small scene takes about that long in all (the tiny
// scene of benchmarks/startup.py: a median of 0.72 s against 0.45 s, ten runs
// each by hand on the 2-core development VM, 2026-11-28). A process started by
// itself therefore names the components it needs, the "self" transport and
// the plain collectives, before MPI_Init reads its environment.
//
// Rules: under a launcher (mpirun, mpiexec, srun) nothing is set, because the
// launcher and the cluster know the transport; a variable the user set stays
// as it is; CONTACT_STEFAN_SERIAL_MPI=plain leaves Open MPI's own defaults.
// Other MPI implementations ignore the OMPI_MCA_ variables. The provenance
// record (provenance.json, "mpi_start") lists which of these variables a run
// started with, whoever set them.
#ifndef contact_stefan_mpi_start_h
#define contact_stefan_mpi_start_h

#include <cstdlib>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

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
        // The only rank sends to itself: the "self" transport, the ob1
        // point-to-point layer over it (no cluster interconnect drivers).
        {"OMPI_MCA_btl", "self"},
        {"OMPI_MCA_pml", "ob1"},
        // Collectives on one rank ("self"), with the blocking and nonblocking
        // fallbacks deal.II's and p4est's calls can reach.
        {"OMPI_MCA_coll", "self,basic,libnbc"},
        // The run-time's own frameworks: the one component a singleton uses
        // of each instead of all of them opened and queried. (Not the
        // "schizo" framework: a singleton with only its "ompi" component
        // fails in MPI_Init.)
        {"OMPI_MCA_state", "app"},
        {"OMPI_MCA_errmgr", "default_app"},
        {"OMPI_MCA_reachable", "weighted"},
        {"OMPI_MCA_shmem", "mmap"},
        // hwloc's plugins for OpenCL and OpenGL devices (it looks for GPUs).
        {"HWLOC_COMPONENTS", "-opencl,-gl"}};
      return settings;
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
     * serial_settings() whose variable is not set yet. A value of the switch
     * other than "fast" (the default) or "plain" is refused with one line
     * (std::invalid_argument).
     */
    inline std::vector<Setting> settings_to_make(const Lookup &lookup)
    {
      const char       *choice_value = lookup(switch_variable());
      const std::string choice       = choice_value ? choice_value : "fast";
      if (choice != "fast" && choice != "plain")
        throw std::invalid_argument(std::string(switch_variable()) + " is '" + choice +
                                    "'; it must be 'fast' (the default: a serial run loads "
                                    "only the MPI components it uses) or 'plain' (Open MPI's "
                                    "own defaults)");
      std::vector<Setting> to_make;
      if (choice == "plain" || started_by_launcher(lookup))
        return to_make;
      for (const auto &setting : serial_settings())
        if (lookup(setting.first.c_str()) == nullptr)
          to_make.push_back(setting);
      return to_make;
    }

    /**
     * Makes the settings in this process's environment (before MPI_Init).
     * Throws std::invalid_argument for a bad switch value.
     */
    inline void prepare()
    {
      for (const auto &[name, value] :
           settings_to_make([](const char *variable) { return std::getenv(variable); }))
        setenv(name.c_str(), value.c_str(), /*overwrite=*/0);
    }

    /**
     * For the provenance record: the variables of serial_settings() and the
     * switch that are set, with their values, whoever set them (this program,
     * the user or mpirun, which passes the user's OMPI_MCA_ variables on).
     */
    inline std::vector<Setting> recorded_settings(const Lookup &lookup)
    {
      std::vector<Setting> recorded;
      for (const auto &setting : serial_settings())
        if (const char *value = lookup(setting.first.c_str()))
          recorded.emplace_back(setting.first, value);
      if (const char *value = lookup(switch_variable()))
        recorded.emplace_back(switch_variable(), value);
      return recorded;
    }
  } // namespace MpiStart
} // namespace ContactStefan

#endif
