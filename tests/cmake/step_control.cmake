# Tests: adaptive time steps (Time stepping/Step control = adaptive;
# doc/time_stepping.md, core/step_control.h). The controller's decisions are
# unit/step_control; here the runs.
# Included by tests/CMakeLists.txt (BIN, T, P, M and the helper functions are
# set there or in the files included before this one).

# Neumann A with adaptive steps (temperature target 0.05 K, phase target 0.5)
# and three step end times: the first attempt (Time step 0.0625) is redone
# shorter, the steps then follow the front (0.005 to 0.053), end exactly at
# 0.6, 0.61, 0.9 and 1 (the reference's time column), and the space-time error
# is 0.0070 (constant steps of 0.0625: 0.0130), with the energy balance. On 1
# and 2 ranks against one reference.
set(ADAPTIVE_STEPS "SET:Time stepping/Step control=adaptive"
  "SET:Time stepping/Target temperature change=0.05")
set(ADAPTIVE_STEPS_A_BOUNDS ${ADAPTIVE_STEPS}
  "SET:Time stepping/Step end times=0.6, 0.61, 0.9"
  "RESULT rejected step attempts>0.5"
  "RESULT steps over the rejection factor at the minimum time step<0.5"
  "RESULT relative space-time L2 error temperature<0.0075"
  "RESULT max energy-balance residual<1e-12"
  "RESULT nodes with h outside H(Theta)<1")
scene(step_control/neumann-A 1 ${P}/neumann_A.prm neumann_A_adaptive_steps
  ${ADAPTIVE_STEPS_A_BOUNDS})
# (The 2-rank run takes the same steps to the last digit of every column, but
# 2 more enthalpy factorisations after the redone attempt: its own reference.)
scene(step_control/neumann-A-mpi2 2 ${P}/neumann_A.prm neumann_A_adaptive_steps_mpi2
  ${ADAPTIVE_STEPS_A_BOUNDS})
# The rate with adaptive steps: on a ladder that halves h, the first step and
# the temperature target together, the space-time error keeps (and exceeds)
# the rate of constant steps (measured 1.47 and 1.27 between levels 0-2, least
# squares 1.37; constant steps 1.04 and 1.24).
add_test(NAME step_control/neumann-A-rate
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/benchmarks/ladder.py ${P}/neumann_A.prm
  --levels 3 --binary ${BIN}
  --set "Time stepping/Step control=adaptive"
  --set "Time stepping/Target temperature change=0.1"
  --halve "Time stepping/Target temperature change"
  --require-rate "relative space-time L2 error temperature>=1.1")
# The undo of a rejected attempt is exact: a step undone and redone with the
# same size changes no physical column or RESULT line (tests/compare_undo.py),
# and one redone half as long equals the run whose step was half as long from
# the start (what a shorter redo changes: the warm start's extrapolation from
# the previous step's size, the step's data). On the casting (contact,
# melting, the die's wall), the mortar melting scene with a contact-dependent
# conductance on a mesh adapted every step (3 ranks), the block-corrected
# thermoelastic plate, a slab born stress-free under generalized plane strain
# (births, the out-of-plane strain), and Neumann A.
foreach(np 1 2)
  set(suffix "")
  if(np GREATER 1)
    set(suffix "-mpi${np}")
  endif()
  add_test(NAME step_control/undo-casting${suffix}
    COMMAND /usr/bin/python3 ${T}/compare_undo.py ${BIN} ${CMAKE_SOURCE_DIR}/prm/casting.prm
    --step 5 --np ${np} --set "Time stepping/End time=12" --set "Output/VTU interval=0"
    --set "Mesh refinement/Adaptive refinement interval=0"
    --set "Mesh refinement/Initial adaptive refinements=0"
    --set "Contact/Interface gap=-3e-4 * (1 - y / 0.05)")
  set_tests_properties(step_control/undo-casting${suffix} PROPERTIES PROCESSORS ${np})
endforeach()
add_test(NAME step_control/undo-mortar-conductance-adaptive-mpi3
  COMMAND /usr/bin/python3 ${T}/compare_undo.py ${BIN} ${T}/scenes/mortar_melting.prm
  --step 6 --np 3 --set "Output/VTU interval=0"
  --set "Geometry/Mesh file=${M}/mortar_adaptive.msh"
  --set "Contact/Interface 1-2/Discretisation=mortar"
  --set "Contact/Interface 1-2/Mortar boundaries=14, 15"
  --set "Mesh refinement/Initial global refinements=1"
  --set "Mesh refinement/Adaptive refinement interval=1"
  --set "Mesh refinement/Maximum level=3"
  --set "Mesh refinement/Refine fraction=0.3"
  --set "Mesh refinement/Coarsen fraction=0.1"
  ${MORTAR_CONDUCTANCE_LAW})
set_tests_properties(step_control/undo-mortar-conductance-adaptive-mpi3 PROPERTIES PROCESSORS 3)
add_test(NAME step_control/undo-block-correction
  COMMAND /usr/bin/python3 ${T}/compare_undo.py ${BIN} ${T}/scenes/thermoelastic_block_correction.prm
  --step 3 --set "Output/VTU interval=0")
foreach(factor 1 0.5)
  set(suffix "")
  if(NOT factor EQUAL 1)
    set(suffix "-shorter")
  endif()
  add_test(NAME step_control/undo-birth-gps${suffix}
    COMMAND /usr/bin/python3 ${T}/compare_undo.py ${BIN} ${T}/scenes/birth_freezing_slab_gps.prm
    --step 3 --factor ${factor} --set "Time stepping/Time step function="
    --set "Output/VTU interval=0")
endforeach()
# The solvers' work too (--work: both runs start their solvers afresh after
# step 4 by a checkpoint, as the undo does): step 4 shortened to a quarter, the
# attempt of step 5 (a whole step) undone and redone half as long. Every
# iteration count and factorisation of the steps that stand must agree: an
# undo that forgot the thermal field's restart values (the warm start's
# previous step size) fails here and nowhere else.
foreach(np 1 2)
  set(suffix "")
  if(np GREATER 1)
    set(suffix "-mpi${np}")
  endif()
  add_test(NAME step_control/undo-casting-shorter-work${suffix}
    COMMAND /usr/bin/python3 ${T}/compare_undo.py ${BIN} ${CMAKE_SOURCE_DIR}/prm/casting.prm
    --step 5 --factor 0.5 --previous 0.25 --work --np ${np}
    --set "Time stepping/End time=12" --set "Output/VTU interval=0"
    --set "Mesh refinement/Adaptive refinement interval=0"
    --set "Mesh refinement/Initial adaptive refinements=0"
    --set "Contact/Interface gap=-3e-4 * (1 - y / 0.05)")
  set_tests_properties(step_control/undo-casting-shorter-work${suffix} PROPERTIES PROCESSORS ${np})
endforeach()
add_test(NAME step_control/undo-neumann-A-shorter
  COMMAND /usr/bin/python3 ${T}/compare_undo.py ${BIN} ${P}/neumann_A.prm --step 4 --factor 0.5)
# Killed after step 8 and resumed from the checkpoint of step 6 (its proposed
# next step and the rejected attempt of step 1 are in it), adaptive mesh, on 1
# and on 2 ranks.
resume_test(restart/neumann-A-adaptive-steps 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A} ${ADAPTIVE_STEPS})
resume_test(restart/neumann-A-adaptive-steps-mpi2 2 2 CONTACT_STEFAN_KILL_AFTER_STEP 8
  ${P}/neumann_A.prm ${RESUME_A} ${ADAPTIVE_STEPS})
# A step whose contact step does not converge within 'Contact/Max iterations'
# is redone a quarter as long: the subduction scene's first attempt (6e11 s)
# needs more than 3 contact iterations, so does the redo of 1.5e11 s; the one
# of 3.75e10 s converges, and the run goes on (6 steps to 1.2e12 s, at most 3
# contact iterations, energy balance). Both bodies start from the wedge's
# smooth geotherm, stress-free: with the scene's own data, which jump at the
# interface, the state at t0 already carries the thermal stress of the
# interface nodes' mixed temperature (doc/coupling.md §2), and its contact
# solve at t0, which no shorter step can redo, needs 6 iterations.
scene(step_control/subduction-contact-failure-redone 1 ${CMAKE_SOURCE_DIR}/prm/subduction.prm
  subduction_contact_failure_redone
  ${SUBDUCTION_STRAIGHT} # (tests/cmake/scenes.cmake)
  # (the base as it was: 1400 degC under the wedge from the foot on)
  "SET:Boundary conditions/Thermal boundary 2/Value=if(x < 273205.0807568877, 1350 * sqrt(1 - exp(-((min(-y, -(x - 100000) * 0.5 - y * 0.8660254037844386)) / 68800)^2 * (4 / pi + 0.147 * ((min(-y, -(x - 100000) * 0.5 - y * 0.8660254037844386)) / 68800)^2) / (1 + 0.147 * ((min(-y, -(x - 100000) * 0.5 - y * 0.8660254037844386)) / 68800)^2))), 1400)"
  "SET:Output/VTU interval=0"
  "SET:Coupling/Reference temperature=1100 * (-y) / 100000"
  "SET:Initial conditions/Function=1100 * (-y) / 100000"
  "SET:Time stepping/Step control=adaptive"
  "SET:Time stepping/Target temperature change=1e9"
  "SET:Time stepping/Target phase change=1e9"
  "SET:Contact/Max iterations=3"
  "SET:Time stepping/End time=1.2e12"
  "SET:Time stepping/Time step=1e12"
  "RESULT rejected step attempts>1.5"
  "RESULT max contact iterations<3.5"
  "RESULT max energy-balance residual<1e-8")
