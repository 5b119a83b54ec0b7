// Unit test of how a run starts MPI (app/mpi_start.h): a process started by
// itself gets the serial settings (no daemon, the ob1 layer); under a launcher, with the switch
// at 'plain', or for a variable the user set, nothing is changed; an isolated
// singleton gets a session directory of its own; a bad switch
// value is refused in one line that names the variable; the provenance record
// lists what was set. Prints deterministic lines; returns 1 if any check fails.
#include <contact-stefan/app/mpi_start.h>

#include <map>
#include <stdexcept>
#include <string>

#include "unit_test_tools.h"

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
  // A fixed identity, so that the printed lines do not depend on the process.
  const MpiStart::Process process{1000, 4242};
  const auto              settings = [&](const std::map<std::string, std::string> &variables) {
    return MpiStart::settings_to_make(environment(variables), process);
  };
  const std::string session = MpiStart::session_directory_variable();

  // Started by itself: every setting (no daemon, the ob1 layer) and the
  // isolated singleton's own session directory.
  const auto alone = settings({});
  check(alone.size() == all.size() + 1, "alone: every serial setting and the session directory");
  check(value_in(alone, "OMPI_MCA_pml") == "ob1", "alone: the ob1 layer");
  check(value_in(alone, "OMPI_MCA_ess_singleton_isolated") == "1", "alone: no orted daemon");
  check(value_in(alone, session) == "/tmp/contact-stefan-mpi.1000/4242",
        "alone: a session directory named by user and process");
  for (const auto &[name, value] : alone)
    std::printf("  %s=%s\n", name.c_str(), value.c_str());

  // Two processes: two session directories (Open MPI would give both
  // jf.0/1, which the first to finish removes under the other).
  check(value_in(MpiStart::settings_to_make(environment({}), {1000, 4243}), session) !=
          value_in(alone, session),
        "another process: another session directory");
  // Where Open MPI puts its own: orte_tmpdir_base, else TMPDIR, TEMP, TMP.
  check(value_in(settings({{"TMPDIR", "/scratch/me/"}, {"TMP", "/var/tmp"}}), session) ==
          "/scratch/me/contact-stefan-mpi.1000/4242",
        "TMPDIR before TMP, its trailing slash dropped");
  check(value_in(settings({{"TMPDIR", ""}, {"TMP", "/var/tmp"}}), session) ==
          "/var/tmp/contact-stefan-mpi.1000/4242",
        "an empty TMPDIR is passed over");
  check(value_in(settings({{"OMPI_MCA_orte_tmpdir_base", "/fast"}, {"TMPDIR", "/scratch"}}),
                 session) == "/fast/contact-stefan-mpi.1000/4242",
        "Open MPI's orte_tmpdir_base first");
  check(value_in(settings({{session, "/mine"}}), session) == "(not set)",
        "user's session directory: not overwritten");
  for (const char *isolated : {"1", "true", "YES"})
    check(value_in(settings({{"OMPI_MCA_ess_singleton_isolated", isolated}}), session) !=
            "(not set)",
          std::string("user's isolated singleton (") + isolated + "): its own session directory");
  for (const char *not_isolated : {"0", "False", "no"})
    check(value_in(settings({{"OMPI_MCA_ess_singleton_isolated", not_isolated}}), session) ==
            "(not set)",
          std::string("user's singleton with a daemon (") + not_isolated +
            "): no session directory set");

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
  const auto user = settings({{"OMPI_MCA_ess_singleton_isolated", "0"}});
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
    check(settings({{"CONTACT_STEFAN_SERIAL_MPI", value}}).size() == all.size() + 1,
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
