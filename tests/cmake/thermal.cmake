# Tests: the enthalpy step: scene regressions and large time steps.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- scene regressions ----------------------------------------------------------
function(scene name np scene reference)
  add_test(NAME ${name}
    COMMAND ${T}/run_scene.sh ${BIN} ${scene} ${T}/references/${reference}.output ${np} ${ARGN})
  set_tests_properties(${name} PROPERTIES PROCESSORS ${np})
endfunction()

# A variant on KLU (several ranks, or 'Direct solver type' = Amesos_Klu) that
# shares its reference with the serial CHOLMOD run: KLU keeps every factor it
# replaces for recall, CHOLMOD modifies some in place (doc/algorithms.md §4),
# so the two count factorisations differently. The variant leaves the count
# out of the comparison and checks its own, n.
function(klu_factorisations var n)
  math(EXPR below "${n} - 1")
  set(${var} "IGNORE:RESULT enthalpy matrix factorisations"
    "IGNORE:RESULT calls enthalpy step: factorise"
    "RESULT enthalpy matrix factorisations>${below}.5"
    "RESULT enthalpy matrix factorisations<${n}.5"
    "RESULT calls enthalpy step: factorise>${below}.5"
    "RESULT calls enthalpy step: factorise<${n}.5" PARENT_SCOPE)
endfunction()

# (An IGNORE: of a line the reference does not have is refused: a misspelt
# name must not leave a test that compares less than it says.)
add_test(NAME harness/ignore-unknown-line
  COMMAND ${T}/run_scene.sh ${BIN} ${P}/neumann_A.prm ${T}/references/neumann_A.output 1
          "IGNORE:RESULT enthalpy matrix factorisationz")
set_tests_properties(harness/ignore-unknown-line PROPERTIES PASS_REGULAR_EXPRESSION
  "IGNORE:RESULT enthalpy matrix factorisationz: no such line in .*neumann_A.output")

# (Likewise an IGNORE:column of a column the statistics table does not have.)
add_test(NAME harness/ignore-unknown-column
  COMMAND ${T}/run_scene.sh ${BIN} ${P}/neumann_A.prm ${T}/references/neumann_A.output 1
          "IGNORE:column front_positionz")
set_tests_properties(harness/ignore-unknown-column PROPERTIES PASS_REGULAR_EXPRESSION
  "IGNORE:column front_positionz: not a column of the statistics table")

# Bounds about 1.5 times the measured values: a reference regenerated from a
# wrong code cannot pass them.
set(NEUMANN_A_BOUNDS
  "RESULT relative L2 error temperature<0.0085"
  "RESULT front position error in mesh widths<0.45"
  "RESULT max energy-balance residual<1e-12"
  "RESULT nodes with h outside H(Theta)<1"
  "RESULT steps with relaxation fallback<1")
scene(neumann/A 1 ${P}/neumann_A.prm neumann_A ${NEUMANN_A_BOUNDS})
# Two ranks must reproduce the serial statistics (same reference).
klu_factorisations(NEUMANN_A_KLU 12)
scene(neumann/A-mpi2 2 ${P}/neumann_A.prm neumann_A ${NEUMANN_A_BOUNDS} ${NEUMANN_A_KLU})
# A serial run's MPI start (app/mpi_start.h) must leave the results alone and
# keep working when the user wants Open MPI's daemon (a singleton that is not
# isolated) or Open MPI's own defaults throughout (the switch at 'plain').
add_test(NAME neumann/A-singleton-not-isolated
  COMMAND env OMPI_MCA_ess_singleton_isolated=0 ${T}/run_scene.sh ${BIN} ${P}/neumann_A.prm
          ${T}/references/neumann_A.output 1 ${NEUMANN_A_BOUNDS})
add_test(NAME neumann/A-serial-mpi-plain
  COMMAND env CONTACT_STEFAN_SERIAL_MPI=plain ${T}/run_scene.sh ${BIN} ${P}/neumann_A.prm
          ${T}/references/neumann_A.output 1 ${NEUMANN_A_BOUNDS})
# The iterative solver must give the same discrete solution as the direct one.
scene(neumann/A-cg-amg 1 ${P}/neumann_A.prm neumann_A-cg-amg
  "SET:Solver/Linear solver=cg-amg" ${NEUMANN_A_BOUNDS})
# 'automatic' on one rank follows 'Automatic direct limit for heat' for the heat
# system: above it (the scene has 325 unknowns) CG + AMG, as above.
scene(neumann/A-heat-direct-limit 1 ${P}/neumann_A.prm neumann_A-cg-amg
  "SET:Solver/Automatic direct limit for heat=100" ${NEUMANN_A_BOUNDS}
  "RESULT enthalpy solver: CG solves>0.5")
# The same with every enthalpy solve to 'CG tolerance' and deal.II's two
# smoother sweeps: the reference of the code before loose solves while the set
# changes (12 AMG set-ups, 22 solves), to the last digit of the iteration counts.
scene(neumann/A-cg-amg-tight 1 ${P}/neumann_A.prm neumann_A-cg-amg-tight
  "SET:Solver/Linear solver=cg-amg" "SET:Solver/CG tolerance while the enthalpy set changes=0"
  "SET:Solver/Enthalpy AMG smoother sweeps=2" ${NEUMANN_A_BOUNDS})
# Loose solves without kept hierarchies (each recomputation replaces the one
# hierarchy, so borrowing and returning to a set must track which values it
# was made for): the same solution.
scene(neumann/A-cg-amg-no-kept 1 ${P}/neumann_A.prm neumann_A-cg-amg-no-kept
  "SET:Solver/Linear solver=cg-amg" "SET:Solver/Kept factorisations=0" ${NEUMANN_A_BOUNDS})
# MUMPS instead of KLU: the solver is set up again whenever tau changes (the
# shortened last step here), which once crashed (the old Amesos solver read its
# freed problem). Same results as KLU within the reference tolerance.
scene(neumann/A-mumps 1 ${P}/neumann_A.prm neumann_A-mumps
  "SET:Solver/Linear solver=direct" "SET:Solver/Direct solver type=Amesos_Mumps"
  "SET:Time stepping/End time=0.99" ${NEUMANN_A_BOUNDS})
# The heat operator's AMG kept across active sets (recomputed on its
# aggregates), the system edited in place: two ranks give the serial results.
scene(neumann/A-cg-amg-mpi2 2 ${P}/neumann_A.prm neumann_A-cg-amg
  "SET:Solver/Linear solver=cg-amg" ${NEUMANN_A_BOUNDS})
# The direct path on one rank is CHOLMOD by default (KLU on several ranks):
# KLU on one rank gives the same results.
scene(neumann/A-klu 1 ${P}/neumann_A.prm neumann_A "SET:Solver/Direct solver type=Amesos_Klu"
  ${NEUMANN_A_BOUNDS} ${NEUMANN_A_KLU})
# Without kept factorisations: the same solution with 20 factorisations, as
# the default counts on one rank too (the factors CHOLMOD modifies row by row
# are not kept; KLU, which keeps them, counts 12: the set without plateau
# nodes recurs).
scene(neumann/A-no-kept-factorisations 1 ${P}/neumann_A.prm neumann_A-no-kept
  "SET:Solver/Kept factorisations=0" ${NEUMANN_A_BOUNDS})
scene(contact/hertz-C1-klu 1 ${P}/hertz_C1.prm hertz_C1
  "SET:Solver/Direct solver type=Amesos_Klu")
# The heat operator's hierarchy kept unchanged across active sets.
# (Its own reference: no hierarchy is kept for recall, 20 set-ups instead of 12.)
scene(neumann/A-cg-amg-reuse 1 ${P}/neumann_A.prm neumann_A-cg-amg-reuse
  "SET:Solver/Linear solver=cg-amg" "SET:Solver/AMG update=reuse" ${NEUMANN_A_BOUNDS})
# The relaxation solver in every step must give the same discrete solution as
# the active-set method (to its tolerance): the same error to 6 digits.
scene(neumann/A-relaxation 1 ${P}/neumann_A.prm neumann_A-relaxation
  "SET:Solver/Enthalpy solver=relaxation"
  "RESULT steps with relaxation fallback>14"
  "RESULT relative L2 error temperature>0.0068263"
  "RESULT relative L2 error temperature<0.0068264")
# Case C, SI units, phase-dependent conductivity: s(1e5 yr) within 1 %.
scene(neumann/C 1 ${P}/neumann_C.prm neumann_C
  "RESULT front position error<0.2"
  "RESULT relative L2 error temperature<3.2e-4"
  "RESULT max energy-balance residual<1e-11"
  "RESULT nodes with h outside H(Theta)<1")
# Two transitions: both fronts within 2 mesh widths of the exact ones.
scene(neumann/two-transitions 1 ${P}/neumann_two_transitions.prm neumann_two_transitions
  "RESULT front position error in mesh widths 0<0.5"
  "RESULT front position error in mesh widths 1<0.5"
  "RESULT relative L2 error temperature<0.021"
  "RESULT max energy-balance residual<1e-12"
  "RESULT nodes with h outside H(Theta)<1"
  "RESULT steps with relaxation fallback<1")
scene(neumann/two-transitions-mpi2 2 ${P}/neumann_two_transitions.prm neumann_two_transitions
  "RESULT steps with relaxation fallback<1")

# --- large time steps: the truncated Newton method (doc/algorithms.md) ----------
# Neumann A at h = 1/128 with tau = 1000 h^2/kappa (the front crosses up to 8
# cells in one step): the same discrete solution as the active-set method, whose
# space-time error is 0.01062136362 (17.3 solves per step without its large-step
# mode, 5.53 with it), in at most 6 solves per step on average.
set(TRUNCATED_NEWTON "SET:Solver/Enthalpy solver=truncated-newton")
set(LARGE_STEP "SET:Mesh refinement/Initial global refinements=3"
  "SET:Time stepping/Time step=0.06103515625")
set(STEP_BOUNDS
  "RESULT max energy-balance residual<1e-12"
  "RESULT nodes with h outside H(Theta)<1"
  "RESULT steps with relaxation fallback<1")
scene(neumann/A-large-step-truncated-newton 1 ${P}/neumann_A.prm neumann_A_large_step
  ${LARGE_STEP} ${TRUNCATED_NEWTON} ${STEP_BOUNDS}
  "RESULT mean active-set iterations<6"
  "RESULT relative space-time L2 error temperature>0.0106213"
  "RESULT relative space-time L2 error temperature<0.0106214")
# The default active-set method at the same step: its first step hands over to
# the truncated Newton method after 'Truncated Newton hand-over' = 8 solves and
# the later ones start with it (large-step mode), so it too stays below 6
# solves per step (17.3 without the mode). The same solution.
scene(neumann/A-large-step-active-set 1 ${P}/neumann_A.prm neumann_A_large_step_active_set
  ${LARGE_STEP} ${STEP_BOUNDS}
  "RESULT mean active-set iterations<6"
  "RESULT steps solved by the truncated Newton method>13"
  "RESULT relative space-time L2 error temperature>0.0106213"
  "RESULT relative space-time L2 error temperature<0.0106214")
# (Its own reference: KLU on two ranks never modifies a factor row by row and
# keeps every factor it replaces, so it factorises 70 times where one rank
# factorises 73.)
scene(neumann/A-large-step-active-set-mpi2 2 ${P}/neumann_A.prm neumann_A_large_step_active_set_mpi2
  ${LARGE_STEP} ${STEP_BOUNDS}
  "RESULT mean active-set iterations<6"
  "RESULT steps solved by the truncated Newton method>13"
  "RESULT relative space-time L2 error temperature>0.0106213"
  "RESULT relative space-time L2 error temperature<0.0106214")
# Two ranks (Gauss-Seidel within each rank's nodes) take the same iterations.
klu_factorisations(LARGE_STEP_KLU 62)
scene(neumann/A-large-step-truncated-newton-mpi2 2 ${P}/neumann_A.prm
  neumann_A_large_step ${LARGE_STEP} ${TRUNCATED_NEWTON} ${STEP_BOUNDS} ${LARGE_STEP_KLU}
  "RESULT mean active-set iterations<6"
  "RESULT relative space-time L2 error temperature>0.0106213"
  "RESULT relative space-time L2 error temperature<0.0106214")
# tau = 10^4 h^2/kappa: the front crosses 51 cells in the first step. The
# truncated Newton method converges in a few solves; the active-set method
# hands the step over to it after 8 solves (large-step mode), or, with the
# hand-over at 0, when it reaches its iteration limit (before either, the
# relaxation fallback took over and failed). All give the same solution.
set(HUGE_STEP "SET:Mesh refinement/Initial global refinements=3"
  "SET:Time stepping/Time step=0.6103515625")
scene(neumann/A-huge-step-truncated-newton 1 ${P}/neumann_A.prm neumann_A_huge_step
  ${HUGE_STEP} ${TRUNCATED_NEWTON} ${STEP_BOUNDS}
  "RESULT mean active-set iterations<6"
  "RESULT relative space-time L2 error temperature>0.0721434"
  "RESULT relative space-time L2 error temperature<0.0721435")
scene(neumann/A-huge-step-active-set 1 ${P}/neumann_A.prm neumann_A_huge_step_active_set
  ${HUGE_STEP} ${STEP_BOUNDS}
  "RESULT mean active-set iterations<10"
  "RESULT relative space-time L2 error temperature>0.0721434"
  "RESULT relative space-time L2 error temperature<0.0721435")
scene(neumann/A-huge-step-hand-over-at-limit 1 ${P}/neumann_A.prm
  neumann_A_huge_step_hand_over_at_limit ${HUGE_STEP} ${STEP_BOUNDS}
  "SET:Solver/Truncated Newton hand-over=0"
  "RESULT mean active-set iterations>50"
  "RESULT relative space-time L2 error temperature>0.0721434"
  "RESULT relative space-time L2 error temperature<0.0721435")
# Two transitions, and an adaptive mesh with hanging nodes (tau/h^2 up to 256):
# the active-set references' errors and bounds.
scene(neumann/two-transitions-truncated-newton 1 ${P}/neumann_two_transitions.prm
  neumann_two_transitions_truncated_newton ${TRUNCATED_NEWTON} ${STEP_BOUNDS}
  "RESULT front position error in mesh widths 0<0.5"
  "RESULT front position error in mesh widths 1<0.5"
  "RESULT relative L2 error temperature<0.021")
scene(neumann/two-transitions-truncated-newton-mpi2 2 ${P}/neumann_two_transitions.prm
  neumann_two_transitions_truncated_newton ${TRUNCATED_NEWTON} ${STEP_BOUNDS}
  "RESULT front position error in mesh widths 0<0.5"
  "RESULT front position error in mesh widths 1<0.5"
  "RESULT relative L2 error temperature<0.021")

# Flux boundaries, sources, anisotropy, time-dependent Dirichlet data: exact.
scene(manufactured/flux-source-anisotropy 1 ${T}/scenes/manufactured_flux.prm manufactured_flux
  "RESULT relative L2 error temperature<1e-12"
  "RESULT max-norm error temperature<1e-12"
  "RESULT max energy-balance residual<1e-12")

# Two bodies with different enthalpy laws relax to the uniform temperature fixed
# by their laws and the initial heat: checks the mixed nodal laws at the interface
# and conservation (a wrong mixture moves the end state by 0.33).
# The initial data jump at the interface (-0.5 below, 3 above): the interface
# nodes start from the lumped-mass mean of both sides' enthalpies, so the
# discrete heat is the integral of the data and the end state is the exact
# one, 1 (0.5 (H_0(1) + H_1(1)) = 0.5 (2.5 + 3.9) = 0.5 (H_0(-0.5) + H_1(3));
# before 2026-12-07 the interface row took the lower body's -0.5 and the end
# state was 0.9177).
set(EQUILIBRIUM_BOUNDS
  "RESULT equilibrium temperature>0.999999999"
  "RESULT equilibrium temperature<1.000000001"
  "RESULT max deviation from equilibrium temperature<1e-9"
  "RESULT relative change of total enthalpy<1e-11"
  "RESULT nodes with h outside H(Theta)<1"
  "RESULT steps with relaxation fallback<1")
set(EQUILIBRIUM ${T}/scenes/two_body_equilibrium.prm)
scene(equilibrium/two-bodies 1 ${EQUILIBRIUM} two_body_equilibrium ${EQUILIBRIUM_BOUNDS})
scene(equilibrium/two-bodies-mpi2 2 ${EQUILIBRIUM} two_body_equilibrium ${EQUILIBRIUM_BOUNDS})

# Gmsh import, two bodies with different conductivities and enthalpy laws, a
# steady state Q1 represents exactly.
add_custom_command(OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/two_blocks.msh
  COMMAND ${CMAKE_COMMAND} -DOUTPUT=${CMAKE_CURRENT_BINARY_DIR}/two_blocks.msh
          -P ${T}/make_two_blocks_msh.cmake
  DEPENDS ${T}/make_two_blocks_msh.cmake)
add_custom_command(OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/kink.msh
  COMMAND ${CMAKE_COMMAND} -DOUTPUT=${CMAKE_CURRENT_BINARY_DIR}/kink.msh -DKINK=ON
          -P ${T}/make_two_blocks_msh.cmake
  DEPENDS ${T}/make_two_blocks_msh.cmake)
add_custom_target(test_meshes ALL DEPENDS ${CMAKE_CURRENT_BINARY_DIR}/two_blocks.msh
                                          ${CMAKE_CURRENT_BINARY_DIR}/kink.msh)
scene(gmsh/two-blocks 1 ${T}/scenes/two_blocks_gmsh.prm two_blocks_gmsh
  "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/two_blocks.msh"
  "RESULT relative L2 error temperature<1e-9"
  "RESULT max-norm error temperature<1e-9"
  "RESULT max energy-balance residual<1e-10")
scene(gmsh/two-blocks-mpi2 2 ${T}/scenes/two_blocks_gmsh.prm two_blocks_gmsh
  "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/two_blocks.msh"
  "RESULT relative L2 error temperature<1e-9")
