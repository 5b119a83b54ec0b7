// The command line's fixed texts, shared by the launcher (source/app/launcher.cc,
// the program `contact-stefan`) and the solver (source/app/main.cc,
// `contact-stefan-solver`): the usage, the version line, and which options are
// answered without starting the solver.
#ifndef contact_stefan_command_line_h
#define contact_stefan_command_line_h

#include <cstdlib>
#include <iostream>
#include <string>

namespace ContactStefan
{
  extern const char *build_commit; // build_info.cc, written at build time

  namespace CommandLine
  {
    inline const char *usage =
      "Usage: contact-stefan [options] scene.prm\n"
      "       mpirun -np N contact-stefan scene.prm\n"
      "\n"
      "Runs the scene described by the parameter file scene.prm (deal.II\n"
      "ParameterHandler format; see prm/ for examples and doc/parameters.prm for\n"
      "every parameter with its default and documentation).\n"
      "\n"
      "Options:\n"
      "  -h, --help                 this text\n"
      "  -V, --version              the commit this program was built from, its\n"
      "                             compiler, build type and deal.II version\n"
      "  -p, --print-parameters     print every parameter with its default and\n"
      "                             documentation, in .prm format, and exit\n"
      "  -c, --check                read and check scene.prm, then exit\n"
      "  -r, --resume               continue from the checkpoint in the scene's\n"
      "                             output directory (Checkpoint/Resume = true)\n"
      "\n"
      "A run writes VTU/PVD files and a statistics table into 'Output/Directory';\n"
      "runs with an exact solution end with 'RESULT <name> = <value>' lines; a\n"
      "record of what made the run (version, command line, ranks, the parameter\n"
      "text as read, start and end time, exit code) goes to provenance.json there.\n"
      "Errors in the input stop the run before any work with one line naming the\n"
      "parameter and the reason.\n"
      "\n"
      "Exit codes: 0 success; 1 bad input; 2 a failure at run time; 3 finished,\n"
      "but a self-check failed (named on stderr); 128 + N stopped by signal N\n"
      "(SIGTERM 143, SIGINT 130, SIGUSR1 138) between two steps, output complete\n"
      "up to there (under mpirun send SIGUSR1: mpirun kills on SIGTERM).\n";


    /**
     * "contact-stefan <commit> (<compiler>, <build type>, deal.II <version>)";
     * the macros are compile definitions of both programs (CMakeLists.txt).
     */
    inline std::string version_line()
    {
      return std::string("contact-stefan ") + build_commit + " (" + CONTACT_STEFAN_COMPILER + ", " +
             CONTACT_STEFAN_BUILD_TYPE + " build, deal.II " + CONTACT_STEFAN_DEAL_II_VERSION + ")";
    }

    /**
     * --help, --version and --print-parameters need neither MPI nor the solver
     * libraries (whose loading alone takes 0.4 s): the first of them on the
     * command line is answered at once.
     */
    inline std::string information_option(const int argc, char *argv[])
    {
      for (int i = 1; i < argc; ++i)
        {
          const std::string arg = argv[i];
          if (arg == "-h" || arg == "--help" || arg == "-V" || arg == "--version" || arg == "-p" ||
              arg == "--print-parameters")
            return arg;
        }
      return "";
    }

    /** Under mpirun only the first rank answers (the launchers' rank variables). */
    inline bool first_rank()
    {
      for (const char *variable : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
        if (const char *value = std::getenv(variable))
          if (std::string(value) != "0")
            return false;
      return true;
    }

    /**
     * Answers an information option (on the first rank only); the parameter
     * text comes from print_parameters(). The exit code.
     */
    template <typename PrintParameters>
    int answer(const std::string &option, const PrintParameters &print_parameters)
    {
      if (!first_rank())
        return 0;
      if (option == "-h" || option == "--help")
        std::cout << usage;
      else if (option == "-V" || option == "--version")
        std::cout << version_line() << std::endl;
      else
        print_parameters();
      return std::cout.flush() ? 0 : 1;
    }
  } // namespace CommandLine
} // namespace ContactStefan

#endif
