// Unit test of how a run starts MPI (app/mpi_start.h): a process started by
// itself gets the serial settings (no daemon, the ob1 layer); under a launcher, with the switch
// at 'plain', or for a variable the user set, nothing is changed; a serial
// run gets a session directory of its own, made by mkdtemp in a parent closed
// to others; a bad switch
// value is refused in one line that names the variable; the provenance record
// lists what was set. Prints deterministic lines; returns 1 if any check fails.
#include <contact-stefan/app/mpi_start.h>

#include <cstdlib>
#include <map>
#include <stdexcept>
#include <string>

#include "unit_test_tools.h"

#include <sys/stat.h>
#include <unistd.h>

using namespace ContactStefan;
using UnitTest::check;

namespace
{
  // An environment of its own for each case (the process's is not touched).
  MpiStart::Lookup environment(const std::map<std::string, std::string> &variables)
  {
    return [variables](const char *name) -> const char * {
      const auto found = variables.find(name);
      return found == variables.end() ? nullptr : found->second.c_str();
    };
  }

  std::string value_in(const std::vector<MpiStart::Setting> &settings, const std::string &name)
  {
    for (const auto &[n, v] : settings)
      if (n == name)
        return v;
    return "(not set)";
  }
} // namespace

int main()
{
  const auto all = MpiStart::serial_settings();

  // Started by itself: every setting (no daemon, the ob1 layer).
  const auto alone = MpiStart::settings_to_make(environment({}));
  check(alone.size() == all.size(), "alone: every serial setting is made");
  check(value_in(alone, "OMPI_MCA_pml") == "ob1", "alone: the ob1 layer");
  check(value_in(alone, "OMPI_MCA_ess_singleton_isolated") == "1", "alone: no orted daemon");
  for (const auto &[name, value] : alone)
    std::printf("  %s=%s\n", name.c_str(), value.c_str());

  // The session directory: wanted by a fast serial start whose user set none.
  const std::string session = MpiStart::session_directory_variable();
  check(MpiStart::wants_session_directory(environment({})), "alone: a session directory");
  check(MpiStart::wants_session_directory(environment({{"OMPI_MCA_ess_singleton_isolated", "0"}})),
        "a singleton with a daemon: a session directory too (it shares it with its daemon)");
  check(!MpiStart::wants_session_directory(environment({{session, "/mine"}})),
        "the user's session directory: none made");
  check(!MpiStart::wants_session_directory(environment({{"CONTACT_STEFAN_SERIAL_MPI", "plain"}})),
        "switch 'plain': none made");
  check(!MpiStart::wants_session_directory(environment({{"OMPI_COMM_WORLD_SIZE", "2"}})),
        "under a launcher: none made");
  // Where: OMPI_MCA_orte_tmpdir_base, else the first non-empty of TMPDIR,
  // TEMP, TMP, else /tmp.
  check(MpiStart::session_base(environment({})) == "/tmp", "base: /tmp by default");
  check(MpiStart::session_base(environment({{"TEMP", "/t1"}, {"TMP", "/t2"}})) == "/t1",
        "base: TEMP before TMP");
  check(MpiStart::session_base(environment({{"TMPDIR", "/scratch/me//"}, {"TMP", "/t2"}})) ==
          "/scratch/me",
        "base: TMPDIR before TMP, trailing slashes dropped");
  check(MpiStart::session_base(environment({{"TMPDIR", ""}, {"TMP", "/t2"}})) == "/t2",
        "base: an empty TMPDIR passed over");
  check(MpiStart::session_base(
          environment({{"OMPI_MCA_orte_tmpdir_base", "/fast"}, {"TMPDIR", "/scratch"}})) == "/fast",
        "base: Open MPI's orte_tmpdir_base first");
  check(MpiStart::session_base(environment({{"TMPDIR", "///"}})) == "/" &&
          MpiStart::in_directory("/", "x") == "/x",
        "base: '/' without a doubled slash");

  // Made for real in a scratch directory: mode 0700, a new name each time, in
  // the parent while it is this user's and closed to others, beside it otherwise.
  {
    const char *tmpdir = std::getenv("TMPDIR");
    std::string scratch =
      std::string(tmpdir && *tmpdir ? tmpdir : "/tmp") + "/unit_mpi_start.XXXXXX";
    check(mkdtemp(scratch.data()) != nullptr, "scratch directory");
    const std::string base   = scratch;
    const auto        uid    = static_cast<unsigned long>(getuid());
    const std::string parent = base + "/contact-stefan-mpi." + std::to_string(uid);
    const auto        mode   = [](const std::string &path) {
      struct stat status;
      return lstat(path.c_str(), &status) == 0 && S_ISDIR(status.st_mode) ?
                        int(status.st_mode & 07777) :
                        -1;
    };
    const std::string first  = MpiStart::make_session_directory(base, uid, "node", 42);
    const std::string second = MpiStart::make_session_directory(base, uid, "node", 42);
    check(first.rfind(parent + "/node.42.", 0) == 0 && mode(first) == 0700,
          "made in the parent as <host>.<pid>.XXXXXX, mode 0700");
    check(mode(parent) == 0700, "the parent made, mode 0700");
    check(!second.empty() && second != first && mode(second) == 0700,
          "the same host and process id again: another directory");
    chmod(parent.c_str(), 0770);
    const std::string open_parent = MpiStart::make_session_directory(base, uid, "node", 42);
    check(open_parent.rfind(base + "/contact-stefan-mpi." + std::to_string(uid) + ".node.42.", 0) ==
              0 &&
            mode(open_parent) == 0700,
          "a group-writable parent: passed over for the base");
    chmod(parent.c_str(), 0700);
    const std::string moved = parent + ".moved";
    rename(parent.c_str(), moved.c_str());
    check(symlink(moved.c_str(), parent.c_str()) == 0, "a symlink in the parent's place");
    const std::string linked = MpiStart::make_session_directory(base, uid, "node", 42);
    check(linked.rfind(parent + ".node.42.", 0) == 0, "a symlinked parent: passed over");
    check(MpiStart::make_session_directory(base + "/missing/deeper", uid, "node", 42).empty(),
          "a base that does not exist: none made");
    check(std::system(("rm -rf '" + base + "'").c_str()) == 0, "scratch directory removed");
  }
  // Under each launcher: nothing, whatever else is set; the switch is not read.
  for (const char *rank_variable : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    check(MpiStart::settings_to_make(environment({{rank_variable, "2"}})).empty(),
          std::string("under a launcher (") + rank_variable + "): nothing is made");
  check(MpiStart::settings_to_make(
          environment({{"CONTACT_STEFAN_SERIAL_MPI", "off"}, {"PMIX_RANK", "1"}}))
          .empty(),
        "under a launcher a bad switch value is not read, not refused");
  check(!MpiStart::started_by_launcher(environment({{"OMPI_MCA_btl", "tcp,self"}})),
        "a user's MCA variable does not mean a launcher");

  // A variable the user set stays; the others are still made. A singleton
  // the user wants not isolated must still start: nothing made here may need
  // an isolated one (the run-time's state and error managers would, and were
  // shown failing in MPI_Init by a reviewer; they are not in the list).
  const auto user =
    MpiStart::settings_to_make(environment({{"OMPI_MCA_ess_singleton_isolated", "0"}}));
  check(user.size() == all.size() - 1, "user's singleton: the others are made");
  check(value_in(user, "OMPI_MCA_ess_singleton_isolated") == "(not set)",
        "user's singleton: not overwritten");
  for (const auto &[name, value] : all)
    check(name == "OMPI_MCA_ess_singleton_isolated" || name == "OMPI_MCA_pml",
          name + ": known to start a singleton that is not isolated");
  const auto user_pml = MpiStart::settings_to_make(environment({{"OMPI_MCA_pml", "ucx"}}));
  check(value_in(user_pml, "OMPI_MCA_pml") == "(not set)", "user's pml: not overwritten");

  // The switch.
  check(MpiStart::settings_to_make(environment({{"CONTACT_STEFAN_SERIAL_MPI", "plain"}})).empty(),
        "switch 'plain': nothing is made");
  for (const char *value : {"fast", ""})
    check(MpiStart::settings_to_make(environment({{"CONTACT_STEFAN_SERIAL_MPI", value}})).size() ==
            all.size(),
          std::string("switch '") + value + "': every setting");
  bool refused = false;
  try
    {
      MpiStart::settings_to_make(environment({{"CONTACT_STEFAN_SERIAL_MPI", "off"}}));
    }
  catch (const std::invalid_argument &e)
    {
      const std::string text = e.what();
      refused                = text.find("CONTACT_STEFAN_SERIAL_MPI is 'off'") == 0 &&
                text.find('\n') == std::string::npos;
      std::printf("  refused: %s\n", e.what());
    }
  check(refused, "switch 'off': refused in one line naming the variable and the value");
  refused = false;
  try
    {
      MpiStart::settings_to_make(environment({{"CONTACT_STEFAN_SERIAL_MPI", "a\nb"}}));
    }
  catch (const std::invalid_argument &e)
    {
      refused = std::string(e.what()).find("is 'a?b'") != std::string::npos;
    }
  check(refused, "a newline in the value: refused in one line, shown as '?'");
  refused = false;
  try
    {
      MpiStart::settings_to_make(
        environment({{"CONTACT_STEFAN_SERIAL_MPI", "caf\xe9" + std::string(60, 'x')}}));
    }
  catch (const std::invalid_argument &e)
    {
      refused =
        std::string(e.what()).find("is 'caf?" + std::string(36, 'x') + "';") != std::string::npos;
    }
  check(refused, "a Latin-1 byte shown as '?', the value cut at 40 characters");

  // The record: what is set among the settings and the switch, nothing else.
  const auto recorded =
    MpiStart::recorded_settings(environment({{"OMPI_MCA_pml", "ob1"},
                                             {"OMPI_MCA_orte_hnp_uri", "x"},
                                             {session, "/tmp/s"},
                                             {"CONTACT_STEFAN_SERIAL_MPI", "fast"}}));
  check(recorded.size() == 3 && value_in(recorded, "OMPI_MCA_pml") == "ob1" &&
          value_in(recorded, session) == "/tmp/s" &&
          value_in(recorded, "CONTACT_STEFAN_SERIAL_MPI") == "fast",
        "record: the set settings and the switch, not mpirun's own variables");

  return UnitTest::finish();
}
