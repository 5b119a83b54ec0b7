// contact-stefan, the program the user calls. It answers --help, --version and
// --print-parameters itself and hands every other command line unchanged to
// the solver, contact-stefan-solver in the same directory (exec: the same
// process, arguments and environment, also under mpirun).
//
// Why two programs: the solver links deal.II and, through it, about 200 shared
// libraries (MPI, Trilinos, PETSc, p4est, ...); the dynamic loader alone needs
// 0.4 s to resolve their symbols, before main() runs. This program links none
// of them and answers in a few milliseconds. The parameter text is the
// solver's own --print-parameters output, taken at build time
// (cmake/parameters_text.cmake).
#include <contact-stefan/app/command_line.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>

#include <unistd.h>

namespace ContactStefan
{
  extern const char *parameters_text; // parameters_text.cc, written at build time
}

int main(int argc, char *argv[])
{
  using namespace ContactStefan;
  if (const std::string option = CommandLine::information_option(argc, argv); !option.empty())
    return CommandLine::answer(option, []() { std::cout << parameters_text; });

  // The solver beside this program's own file (not on PATH: a build directory
  // holds the pair that belongs together).
  std::string   self(4096, '\0');
  const ssize_t length = readlink("/proc/self/exe", self.data(), self.size());
  if (length <= 0 || static_cast<std::size_t>(length) >= self.size())
    {
      std::cerr << "contact-stefan: error: cannot find this program's own file "
                   "(/proc/self/exe), so not the solver beside it"
                << std::endl;
      return 2;
    }
  self.resize(length);
  const std::string solver = self.substr(0, self.rfind('/') + 1) + "contact-stefan-solver";
  execv(solver.c_str(), argv);
  std::cerr << "contact-stefan: error: cannot start the solver '" << solver << "' ("
            << std::strerror(errno) << "; build the target contact-stefan-solver)" << std::endl;
  return 2;
}
