# Tests: checkpoint and restart (coupling).
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- checkpoint/restart (doc/adaptivity.md) -----------------------------------------
# Kill-and-resume: a run killed with SIGKILL and resumed from its last
# checkpoint must reproduce the uninterrupted run's RESULT lines, statistics and
# PVD records (tests/run_resume.sh).
function(resume_test name np np_resume variable step scene)
  add_test(NAME ${name}
    COMMAND ${T}/run_resume.sh ${BIN} ${scene} ${np} ${np_resume} ${variable} ${step} ${ARGN})
  set_tests_properties(${name} PROPERTIES PROCESSORS ${np})
endfunction()
set(RESUME_A ${ADAPTIVE_A} "SET:Checkpoint/Interval (steps)=3" "SET:Output/VTU interval=2")
# Adaptive Neumann A killed after step 8 (checkpoint at step 6, adapted mesh).
resume_test(restart/neumann-A-adaptive 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A})
resume_test(restart/neumann-A-adaptive-mpi2 2 2 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A})
# With a front margin the decision to adapt is taken from the mesh and state
# alone: the resumed run skips and adapts at the same steps.
resume_test(restart/neumann-A-front-margin 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A} "SET:Mesh refinement/Front margin=2")
# (The uninterrupted run is on 2 ranks, the resumed one on 1: as the solvers'
# work, the factorisation counts are not compared across rank counts (KLU keeps
# every factor it replaces, CHOLMOD modifies some in place); the checkpoint's
# portability is what this test is about.)
resume_test(restart/neumann-A-front-margin-mpi2-to-1 2 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A} "SET:Mesh refinement/Front margin=2")
# The truncated Newton method's path (Gauss-Seidel order, snapping decisions)
# depends on the DoF order: the thermal DoFs are numbered hierarchically, an
# order that depends on the mesh alone, not on the history of cell indices that
# a mesh reloaded from p4est does not have, so the resumed run repeats the
# iteration counts too.
resume_test(restart/neumann-A-adaptive-truncated-newton 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A} ${TRUNCATED_NEWTON})
resume_test(restart/neumann-A-adaptive-truncated-newton-mpi2 2 2 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A} ${TRUNCATED_NEWTON})
# Large steps with the active-set method: the checkpoint (step 6) is written in
# its large-step mode, which the resumed run must take up (a resumed run that
# started with the active-set method would take other iteration counts).
resume_test(restart/neumann-A-large-step-mode 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${LARGE_STEP} "SET:Checkpoint/Interval (steps)=3")
# A time-step schedule (issue 33): tau doubles at t = 0.5 and three steps must
# end at given times (steps 1-7 tau, 8 to 0.6, 9 to 0.61, 10 and 11 2 tau, 12
# to 0.9, 13 to 1). Adaptive Neumann A with a checkpoint at step 10 (its step
# 2 tau, not 'Time step') killed after step 11, resumed on 1 and 2 ranks.
set(SCHEDULE "SET:Time stepping/Time step function=if(t < 0.5, tau, 2 * tau)"
  "SET:Time stepping/Step end times=0.6, 0.61, 0.9")
resume_test(restart/neumann-A-schedule 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 11
  ${P}/neumann_A.prm ${ADAPTIVE_A} "SET:Checkpoint/Interval (steps)=5"
  "SET:Output/VTU interval=2" ${SCHEDULE})
resume_test(restart/neumann-A-schedule-1-to-2 1 2 CONTACT_STEFAN_KILL_AFTER_STEP 11
  ${P}/neumann_A.prm ${ADAPTIVE_A} "SET:Checkpoint/Interval (steps)=5"
  "SET:Output/VTU interval=2" ${SCHEDULE})
# Killed while writing the checkpoint of step 6: the one of step 3 is used.
resume_test(restart/killed-while-writing 1 1 CONTACT_STEFAN_KILL_DURING_CHECKPOINT 6
  ${P}/neumann_A.prm ${RESUME_A})
# The coupled scene with contact, adapted every 2 steps, written on 2 ranks and
# resumed on 1.
# A checkpoint of another scene is refused in one line before any work.
add_test(NAME restart/other-scene-refused
  COMMAND ${T}/resume_other_scene.sh ${BIN} ${P}/neumann_A.prm ${P}/patch_C2.prm
  "(it was written by a scene with thermal and no mechanical fields")
# The same scene with another density: refused, saying first what to do, then
# which parameter differs, with both values.
add_test(NAME restart/other-parameters-refused
  COMMAND ${T}/resume_other_scene.sh ${BIN} ${P}/neumann_A.prm ${P}/neumann_A.prm
  "run with the parameters it was written with, or start afresh (without --resume and Checkpoint/Resume = false). 1 differ: 'Materials/Body 0/Density' was '1', is '2'"
  "SET:Materials/Body 0/Density=2")
# End time moved to before the last checkpoint (step 10, t = 0.725; End time
# may change on a resume): refused saying what to do, not as a damaged file.
add_test(NAME restart/end-time-before-checkpoint-refused
  COMMAND ${T}/resume_other_scene.sh ${BIN} ${P}/neumann_A.prm ${P}/neumann_A.prm
  "set 'Time stepping/End time' after the checkpoint's time, or start afresh" "SET:Time stepping/End time=0.7")
# A checkpoint of an earlier version's format is refused by name, not misread.
add_test(NAME restart/older-format-refused
  COMMAND ${T}/resume_other_scene.sh ${BIN} ${P}/neumann_A.prm ${P}/neumann_A.prm
  "written in the format 'contact-stefan checkpoint 2' of another version" --older-format)
# A fresh run removes the checkpoints of an earlier run in its directory.
add_test(NAME restart/fresh-run-removes-checkpoints
  COMMAND ${T}/resume_other_scene.sh ${BIN} ${P}/neumann_A.prm ${P}/neumann_A.prm
  "there is no checkpoint" --fresh-run-between "SET:Checkpoint/Interval (steps)=0")
# Checkpoints by wall-clock time (every 1e-6 minutes: after every step).
resume_test(restart/by-wall-clock 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 5
  ${P}/neumann_A.prm ${ADAPTIVE_A} "SET:Checkpoint/Interval (minutes)=1e-6"
  "SET:Checkpoint/Interval (steps)=0")
# Checkpoints between adaptations (adapted every 2 steps, checkpoint every 5),
# and scenes without adaptivity, where the run before the kill holds reused
# factorisations and warm active sets: a checkpoint re-derives the state and
# restarts the solvers, so the resumed run repeats the same work.
resume_test(restart/neumann-A-between-adaptations 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${ADAPTIVE_A} "SET:Mesh refinement/Adaptive refinement interval=2"
  "SET:Checkpoint/Interval (steps)=5")
# The iterative path with loose solves on borrowed AMG hierarchies while the
# enthalpy set changes: a resumed run repeats the same solves and set-ups.
resume_test(restart/neumann-A-cg-amg 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm "SET:Solver/Linear solver=cg-amg" "SET:Checkpoint/Interval (steps)=3")
resume_test(restart/T4-1-to-2 1 2 CONTACT_STEFAN_KILL_AFTER_STEP 7
  ${P}/shrink_fit_T4.prm "SET:Checkpoint/Interval (steps)=5")
resume_test(restart/T2-plateau 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 7
  ${P}/adiabatic_compression_T2_plateau.prm "SET:Checkpoint/Interval (steps)=5")
# The verification parts' own states through a checkpoint: the stress errors
# of T3 (part 'stress'), the initial enthalpy of the equilibrium scene (part
# 'equilibrium') and the section-force errors of the stacked blocks (part
# 'section normal force', with contact pressure windows, whose sums the
# checkpoint carries in the contact report), each resumed from a checkpoint
# before its kill.
resume_test(restart/T3-stress 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 4
  ${P}/free_expansion_T3.prm "SET:Checkpoint/Interval (steps)=2")
resume_test(restart/equilibrium 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 25
  ${T}/scenes/two_body_equilibrium.prm "SET:Checkpoint/Interval (steps)=10")
resume_test(restart/section-force 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 7
  ${T}/scenes/stacked_blocks_section.prm "SET:Checkpoint/Interval (steps)=5"
  "SET:Output/Contact pressure windows=x from 0 to 1, x from 0.5 to 1")
resume_test(restart/coupled-2-to-1 2 1 CONTACT_STEFAN_KILL_AFTER_STEP 10
  ${CMAKE_SOURCE_DIR}/prm/coupled_melting_contact.prm ${ADAPTIVE_COUPLED}
  "SET:Checkpoint/Interval (steps)=4")

# Damaged, mixed and unfinished checkpoints (doc/reliability.md): refused before
# anything of them is read, in one line naming the file and the cause, with the
# output directory left as it was (tests/resume_damaged.sh; every file and
# every kind of damage: the test 'mutation-checkpoint' below).
function(damaged_test name np expected mutation)
  add_test(NAME restart/${name}
    COMMAND ${T}/resume_damaged.sh ${BIN} ${P}/neumann_A.prm ${np} ${expected} ${mutation}
            "SET:Checkpoint/Interval (steps)=3" ${ARGN})
  set_tests_properties(restart/${name} PROPERTIES PROCESSORS ${np})
endfunction()
# Damage: before, a flipped byte in p4est's forest aborted in p4est, an emptied
# data file was a SIGSEGV, a halved one resumed with a melt area of 0.
damaged_test(damaged-forest-refused 1 "checkpoint file 'out/checkpoint/mesh' is damaged"
  flip:mesh)
damaged_test(emptied-data-refused 2 "mesh_fixed.data' is damaged: it has 0 bytes" empty:mesh_fixed.data)
damaged_test(halved-data-refused 1 "mesh_fixed.data' is damaged: it has" half:mesh_fixed.data)
damaged_test(deleted-state-refused 1 "checkpoint/state.txt' is missing" delete:state.txt)
damaged_test(changed-digit-refused 1 "checkpoint/state.txt' is damaged: its checksum"
  digit:state.txt)
damaged_test(emptied-statistics-refused 1 "checkpoint/statistics' is damaged: it has 0 bytes"
  empty:statistics)
damaged_test(deleted-manifest-refused 1 "checkpoint/manifest' is missing" delete:manifest)
# One unit: the file of an earlier checkpoint of the same run, or of another run.
damaged_test(older-step-file-refused 2 "checkpoint/mesh_fixed.data' is damaged"
  older:mesh_fixed.data ${ADAPTIVE_A})
damaged_test(other-run-file-refused 1 "checkpoint/state.txt' is damaged" other:state.txt
  "OTHER:Materials/Body 0/Phase change/Latent heats=1.5")
# The values read back: a time 1 % off under a manifest that matches.
damaged_test(forged-time-refused 1 "does not hold a valid state: the time t = " forge-time)
# The hint at the previous checkpoint, where one exists.
damaged_test(damaged-with-old-refused 1 "rename 'checkpoint.old' to 'checkpoint'" old-hint:mesh)
# Only an unfinished checkpoint.new.
damaged_test(unfinished-new-refused 1 "only the unfinished" new-only)
# The content of the mesh file, not only its name.
add_test(NAME restart/mesh-file-changed-refused
  COMMAND ${T}/resume_damaged.sh ${BIN} ${T}/scenes/two_blocks_gmsh.prm 1
          "with another content of the mesh file" mesh-file:${CMAKE_CURRENT_BINARY_DIR}/two_blocks.msh
          "SET:Checkpoint/Interval (steps)=3")
