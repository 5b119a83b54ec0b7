#!/bin/bash
# The provenance record of a run (ctest cli/provenance):
#   check_provenance.sh BINARY SCENE.prm
# Runs the scene with checkpoints every step, stopped by SIGTERM after step 2
# (the test hook CONTACT_STEFAN_TERM_AFTER_STEP), then resumes it; checks that
# Output/Directory/provenance.json is valid JSON naming the version, the command
# line, the rank count, the MPI start settings, the parameter text as read, the times and the exit code
# of each run, the resumed one keeping the stopped one's record.
set -u
binary=$1 scene=$2
# The MPI start settings checked below are the program's own, not the caller's.
unset OMPI_MCA_pml OMPI_MCA_ess_singleton_isolated OMPI_MCA_orte_jobfam_session_dir \
  OMPI_MCA_orte_tmpdir_base CONTACT_STEFAN_SERIAL_MPI
here=$(cd "$(dirname "$0")" && pwd)
work=$(mktemp -d "$PWD/provenance.XXXXXX") && cd "$work" || exit 1
passed=0
# Its own Open MPI session directory: the resumed run (switch at 'plain') is a
# singleton with a daemon, which must not share one with parallel ctest runs.
TMPDIR=$(mktemp -d) && export TMPDIR
trap 'rm -rf "$TMPDIR"; [ "$passed" = 1 ] && rm -rf "$work"' EXIT
# The runs work in a directory whose name is not UTF-8 (Latin-1 e-acute): the
# record must still be valid JSON, with U+FFFD for the byte.
mkdir "$work/latin1-"$'\xe9' && cd "$work/latin1-"$'\xe9' || exit 1
cp "$scene" scene.prm
"$here/apply_settings.sh" scene.prm "SET:Checkpoint/Interval (steps)=1" \
  "SET:Output/Directory=out" > /dev/null || exit 1
CONTACT_STEFAN_TERM_AFTER_STEP=2 "$binary" scene.prm > first.txt 2>&1
echo "first run: exit code $?"
# The resumed run leaves Open MPI's own start-up defaults (app/mpi_start.h).
CONTACT_STEFAN_SERIAL_MPI=plain "$binary" --resume scene.prm > second.txt 2>&1
echo "resumed run: exit code $?"
version=$("$binary" --version)
/usr/bin/python3 - "$version" "$TMPDIR" "$(id -u)" <<'PYTHON' && passed=1
import json, re, sys
version, tmpdir, uid = sys.argv[1:4]
record = json.load(open("out/provenance.json"))
scene = open("scene.prm").read()
problems = []
def check(condition, what):
    if not condition:
        problems.append(what)
for name, run, code, status, resumed in (("resumed", record, 0, "finished", True),
                                         ("stopped", record.get("previous", {}), 143,
                                          "stopped by a signal", False)):
    check(run.get("program") == version, "%s: program %r is not --version's %r"
          % (name, run.get("program"), version))
    check(run.get("exit_code") == code, "%s: exit code %r" % (name, run.get("exit_code")))
    check(run.get("status") == status, "%s: status %r" % (name, run.get("status")))
    check(run.get("resumed") == resumed, "%s: resumed %r" % (name, run.get("resumed")))
    check(run.get("mpi_ranks") == 1, "%s: ranks %r" % (name, run.get("mpi_ranks")))
    # The MPI start settings: the serial ones (the stopped run), none with the
    # switch at 'plain' (the resumed run).
    start = run.get("mpi_start", {})
    if resumed:
        check(start == {"CONTACT_STEFAN_SERIAL_MPI": "plain"}, "%s: mpi_start %r" % (name, start))
    else:
        # (the run's own session directory, <host>.<pid>.XXXXXX made by
        # mkdtemp in the TMPDIR set above)
        session = start.pop("OMPI_MCA_orte_jobfam_session_dir", "")
        check(re.fullmatch(re.escape(tmpdir) + r"/contact-stefan-mpi\.%s/[^/]+\.[0-9]+\.\w{6}" % uid,
                           session),
              "%s: session directory %r" % (name, session))
        check(start == {"OMPI_MCA_ess_singleton_isolated": "1", "OMPI_MCA_pml": "ob1"},
              "%s: mpi_start %r" % (name, start))
    check(run.get("parameters") == scene, "%s: the parameter text differs" % name)
    check(run.get("parameter_files") == ["scene.prm"], "%s: files %r"
          % (name, run.get("parameter_files")))
    check(str(run.get("started", "")).endswith("Z") and
          str(run.get("finished", "")) >= str(run.get("started", "")),
          "%s: times %r .. %r" % (name, run.get("started"), run.get("finished")))
    check(str(run.get("working_directory", "")).endswith("/latin1-\ufffd"),
          "%s: working directory %r" % (name, run.get("working_directory")))
    check(run.get("command_line", [None])[-1] == "scene.prm", "%s: command line %r"
          % (name, run.get("command_line")))
for p in problems:
    print("FAIL " + p)
print("provenance: %d checks failed" % len(problems))
sys.exit(1 if problems else 0)
PYTHON
# Both runs ended: Open MPI removed the first one's session directory (only
# its parent, made by the program, stays).
parent="$TMPDIR/contact-stefan-mpi.$(id -u)"
if [ -n "$(ls -A "$parent" 2> /dev/null)" ]; then
  echo "FAIL session directories left behind: $(ls -A "$parent")"; passed=0
fi
[ "$passed" = 1 ]
