# Tests: what protects a run and its output: mutations, the directory lock, signals.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- mutation test: over 500 mutations of the project's own scenes (deleted lines,
# wrong types, NaN/Inf/overflow, broken and later non-finite functions, garbage
# meshes, unusable output paths, huge refinements, endless time stepping) must each
# be refused with one line (exit 1 or 2) or run with finite output: no signal, no
# hang (30 s per case), no NaN with exit 0. The suite runs half of them, a half
# that alternates with the UTC day (--sample 2; the first line of the test's
# output names today's offset; '--sample 1' runs all 641, about 3.5 minutes on
# 2 cores): most of a case's cost is the solver's start-up, not the mutation.
add_test(NAME mutation
  COMMAND /usr/bin/python3 ${T}/mutation_test.py --binary ${BIN} --source-dir ${CMAKE_SOURCE_DIR}
          --cmake ${CMAKE_COMMAND} --jobs 2 --timeout 30 --sample 2)
set_tests_properties(mutation PROPERTIES PROCESSORS 2 TIMEOUT 900)
# Checkpoints damaged every way (tests/mutation_checkpoint.py): each file of a
# checkpoint written on 1 and on 2 ranks emptied, halved, deleted, a byte
# flipped, a digit changed, swapped with the file of an older checkpoint and of
# another run; values forged under a matching manifest; the mesh file changed;
# checkpoint.new alone. About 80 s on 2 cores.
add_test(NAME mutation-checkpoint
  COMMAND /usr/bin/python3 ${T}/mutation_checkpoint.py --binary ${BIN}
          --source-dir ${CMAKE_SOURCE_DIR} --mesh ${CMAKE_CURRENT_BINARY_DIR}/two_blocks.msh)
set_tests_properties(mutation-checkpoint PROPERTIES PROCESSORS 2 TIMEOUT 600)

# --- what protects a run's output: the output directory's lock, an earlier run's
# VTU files, a stop signal between steps (tests/run_guard.sh); a run stopped by
# SIGTERM on a checkpoint step resumes to the uninterrupted run's results, also
# its iteration counts (guard/term: a checkpoint the stop writes between two due
# ones resumes to the same solution; the counts differ, since the uninterrupted
# run did not restart its solvers there).
foreach(case lock stale term)
  add_test(NAME guard/${case}
    COMMAND ${T}/run_guard.sh ${BIN} ${T}/scenes/column_heat_then_cool.prm ${case})
endforeach()
resume_test(restart/column-sigterm 1 1 CONTACT_STEFAN_TERM_AFTER_STEP 8
  ${T}/scenes/column_heat_then_cool.prm "SET:Checkpoint/Interval (steps)=4"
  "SET:Output/VTU interval=2")
resume_test(restart/column-sigterm-mpi2 2 1 CONTACT_STEFAN_TERM_AFTER_STEP 9
  ${T}/scenes/column_heat_then_cool.prm "SET:Checkpoint/Interval (steps)=3"
  "SET:Output/VTU interval=2")

# --- signals and rival runs against a run's output (tests/mutation_guard.py):
# SIGTERM/SIGINT at fixed fractions of a 180-step run with VTU output and
# checkpoints (1 and 2 ranks), then --resume; two runs into one directory.
add_test(NAME mutation-guard
  COMMAND /usr/bin/python3 ${T}/mutation_guard.py --binary ${BIN} --source-dir ${CMAKE_SOURCE_DIR})
set_tests_properties(mutation-guard PROPERTIES PROCESSORS 2 TIMEOUT 600)
