// contact-stefan: thermoelastic bodies in frictionless contact with melting and
// freezing (Nedoma & Dvorak 1995). This file only reads the command line.
#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <contact-stefan/app/command_line.h>
#include <contact-stefan/app/mpi_start.h>
#include <contact-stefan/coupling/all_parameters.h>
#include <contact-stefan/coupling/coupled_problem.h>
#include <contact-stefan/output/run_guard.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

int main(int argc, char *argv[])
{
  using namespace ContactStefan;
  // SIGTERM, SIGINT, SIGUSR1/2 stop the run between two steps (run_guard.h). They are
  // held back while MPI starts (most of a second; MPI_Init installs handlers
  // of its own, and the threads it starts inherit the blocked mask, so that
  // the signals reach this thread only), then handled; a signal that arrived
  // meanwhile is delivered then.
  // --help and --version are answered by the launcher (source/app/launcher.cc)
  // before this program is started; run directly, it answers them too, before
  // MPI starts.
  if (const std::string option = CommandLine::information_option(argc, argv); !option.empty())
    return CommandLine::answer(option, []() {
      ParameterHandler prm;
      AllParameters::declare_defaults(prm);
      prm.print_parameters(std::cout, ParameterHandler::PRM);
    });

  // --check started by itself (not by mpirun) reads and checks the file on one
  // process and needs no MPI: skipping MPI_Init took it from 0.65-0.74 s to
  // 0.26-0.27 s (benchmarks/startup.py; the rest is loading deal.II's ~200
  // shared libraries). Under mpirun every rank starts MPI as usual.
  const bool check_requested = std::any_of(argv + 1, argv + argc, [](const char *arg) {
    return std::string(arg) == "-c" || std::string(arg) == "--check";
  });
  const bool started_by_mpirun = MpiStart::started_by_launcher(MpiStart::process_environment());
  // Started by itself, this process is MPI's only rank: before MPI_Init reads
  // the environment it asks for no orted daemon and for the ob1 layer, which
  // spares the loading of interconnect drivers, and gets a session directory
  // of its own if MPI is to start (app/mpi_start.h). Under mpirun nothing is
  // changed.
  // (Stop signals are held from here until MPI_Init is done and the
  // handlers are in place, so that a stop cannot leave the session directory
  // made for MPI behind.)
  const bool mpi_starts = !check_requested || started_by_mpirun;
  StopSignals::block();
  try
    {
      MpiStart::prepare(mpi_starts);
    }
  catch (const std::invalid_argument &e)
    {
      std::cerr << "contact-stefan: error: " << e.what() << std::endl;
      return 1;
    }
  std::optional<Utilities::MPI::MPI_InitFinalize> mpi;
  if (mpi_starts)
    mpi.emplace(argc, argv, 1);
  StopSignals::install();
  StopSignals::unblock();
  const bool root = !mpi || Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;

  std::string filename;
  bool        check_only = false, resume = false;
  for (int i = 1; i < argc; ++i)
    {
      const std::string arg = argv[i];
      if (arg == "-c" || arg == "--check")
        check_only = true;
      else if (arg == "-r" || arg == "--resume")
        resume = true;
      else if (!arg.empty() && arg[0] == '-')
        {
          if (root)
            std::cerr << "contact-stefan: error: unknown option '" << arg
                      << "' (see contact-stefan --help)" << std::endl;
          return 1;
        }
      else if (filename.empty())
        filename = arg;
      else
        {
          if (root)
            std::cerr << "contact-stefan: error: more than one parameter file given" << std::endl;
          return 1;
        }
    }
  if (filename.empty())
    {
      if (root)
        std::cerr << "contact-stefan: error: no parameter file given (see contact-stefan --help)"
                  << std::endl;
      return 1;
    }

  // Stop with one line and an exit code: 1 for bad input, 2 for a failure at
  // run time. Input read before the run fails alike on every rank; a failure
  // during the run may happen on all ranks (a solver that does not converge:
  // its solve is collective) or on one rank only, while the others wait for it
  // in a collective call forever. The failing ranks find out which by a
  // barrier on a communicator of their own (it cannot be confused with the
  // run's collectives): if every rank arrives within the grace time, rank 0
  // prints the one line and all return the code; else the failure was local,
  // and its rank prints it with its number and aborts the run.
  const unsigned int n_ranks       = mpi ? Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) : 1;
  MPI_Comm           failure_comm  = MPI_COMM_NULL;
  const double       grace_seconds = 5;
  if (n_ranks > 1)
    MPI_Comm_dup(MPI_COMM_WORLD, &failure_comm);
  const auto fail = [&](const std::exception &e, const int code, const bool collective) {
    if (n_ranks > 1 && !collective)
      {
        MPI_Request request;
        MPI_Ibarrier(failure_comm, &request);
        int        all_failed = 0;
        const auto start      = std::chrono::steady_clock::now();
        while (!all_failed &&
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() <
                 grace_seconds)
          {
            MPI_Test(&request, &all_failed, MPI_STATUS_IGNORE);
            if (!all_failed)
              std::this_thread::sleep_for(std::chrono::milliseconds(5));
          }
        if (!all_failed) // (the last rank may have arrived at the deadline)
          MPI_Test(&request, &all_failed, MPI_STATUS_IGNORE);
        if (!all_failed)
          {
            std::cerr << "contact-stefan: error (rank "
                      << Utilities::MPI::this_mpi_process(MPI_COMM_WORLD)
                      << "): " << one_line(e.what()) << std::endl;
            MPI_Abort(MPI_COMM_WORLD, code);
          }
      }
    if (root)
      std::cerr << "contact-stefan: error: " << one_line(e.what()) << std::endl;
    return code;
  };

  RunRecord::begin(CommandLine::version_line(),
                   std::vector<std::string>(argv, argv + argc),
                   n_ranks,
                   MpiStart::recorded_settings(MpiStart::process_environment()));
  AllParameters parameters;
  try
    {
      parameters.read(filename);
      if (resume)
        parameters.checkpoint.resume = true;
      RunRecord::set_parameters(parameters.source_files, parameters.source_text);
    }
  catch (const std::exception &e)
    {
      // InputError, or a deal.II exception while parsing: bad input either way.
      return fail(e, 1, true);
    }
  if (check_only)
    {
      if (root)
        std::cout << filename << ": OK" << std::endl;
      return 0;
    }
  std::vector<std::string> failed_checks;
  // The provenance record (rank 0, if the run got as far as writing one) gets
  // the exit code.
  const auto finish = [&](const int code) {
    if (root)
      RunRecord::finish(code);
    return code;
  };
  try
    {
      CoupledProblem<2> problem(parameters, MPI_COMM_WORLD);
      failed_checks = problem.run();
    }
  catch (const StoppedBySignal &e)
    {
      // All ranks agreed on the stop between two steps: collective.
      if (root)
        std::cerr << "contact-stefan: " << e.what() << std::endl;
      return finish(128 + e.signal);
    }
  catch (const InputError &e)
    {
      // Every input check of the run phase is collective (all ranks throw alike).
      return finish(fail(e, 1, true));
    }
  catch (const std::exception &e)
    {
      // Run-time failures (a solver that does not converge, a singular
      // system, a non-finite result): deal.II's long texts shortened to one line.
      // (A failure on one rank only aborts in fail(): no record then.)
      if (root)
        RunRecord::finish(2);
      return fail(e, 2, false);
    }
  // A finished run whose own checks failed: its output is complete and
  // finite, but not a plain success (exit code 3, one warning line each).
  if (root)
    for (const auto &check : failed_checks)
      std::cerr << "contact-stefan: warning: " << one_line(check) << std::endl;
  return finish(failed_checks.empty() ? 0 : 3);
}
