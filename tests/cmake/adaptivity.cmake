# Tests: adaptive refinement (mesh).
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- adaptive refinement (doc/adaptivity.md) ------------------------------------------
# Neumann case A adapted after every step (and twice to the initial data) from
# the 64 x 4 mesh up to level 2: the space-time error of the global level 2
# (0.010398 with 4369 DoFs) with about 850 time-averaged DoFs. Refinement
# conserves the total enthalpy to round-off, coarsening changes it by < 1e-4.
set(ADAPTIVE_A "SET:Mesh refinement/Adaptive refinement interval=1"
  "SET:Mesh refinement/Initial adaptive refinements=2" "SET:Mesh refinement/Maximum level=2")
set(ADAPTIVE_A_BOUNDS
  "RESULT relative space-time L2 error temperature<0.0107"
  "RESULT front position error in local mesh widths<2"
  "RESULT time-averaged dofs<1100"
  "RESULT mesh adaptations>13"
  "RESULT max relative enthalpy change through refinement<1e-12"
  "RESULT max relative enthalpy change through coarsening<1e-4"
  "RESULT max energy-balance residual<1e-12"
  "RESULT nodes with h outside H(Theta)<1"
  "RESULT steps with relaxation fallback<1")
# Its finest cells see tau/h^2 up to 256: the large-step mode hands step 1 over
# to the truncated Newton method and step 5 hands back (5 of 15 steps; all 15
# without the hand-back).
scene(adaptive/neumann-A 1 ${P}/neumann_A.prm neumann_A_adaptive ${ADAPTIVE_A}
  ${ADAPTIVE_A_BOUNDS} "RESULT steps solved by the truncated Newton method>0"
  "RESULT steps solved by the truncated Newton method<15")
klu_factorisations(ADAPTIVE_A_KLU 71)
scene(adaptive/neumann-A-mpi2 2 ${P}/neumann_A.prm neumann_A_adaptive ${ADAPTIVE_A} ${ADAPTIVE_A_KLU}
  ${ADAPTIVE_A_BOUNDS})
scene(adaptive/neumann-A-truncated-newton 1 ${P}/neumann_A.prm
  neumann_A_adaptive_truncated_newton ${ADAPTIVE_A} ${TRUNCATED_NEWTON} ${ADAPTIVE_A_BOUNDS}
  "RESULT mean active-set iterations<4.5")
# Front margin = Front buffer = 2: checked after every step, adapted only when
# the front comes within 2 finest cells of a coarser cell. 6 adaptations
# instead of 14, space-time error 0.010402 against 0.010400 for every step
# (global level 2: 0.010398). The bounds fail a test that never skips (more
# than 8) and one that never adapts (the front leaves its zone).
# (One reference for 1 and 2 ranks; KLU on 2 ranks counts its own
# factorisations, klu_factorisations.)
scene(adaptive/neumann-A-front-margin 1 ${P}/neumann_A.prm neumann_A_front_margin ${ADAPTIVE_A}
  "SET:Mesh refinement/Front margin=2"
  "RESULT relative space-time L2 error temperature<0.0105"
  "RESULT front position error in local mesh widths<1"
  "RESULT mesh adaptations>3"
  "RESULT mesh adaptations<9"
  "RESULT time-averaged dofs<1100"
  "RESULT max relative enthalpy change through coarsening<1e-4"
  "RESULT max energy-balance residual<1e-12")
klu_factorisations(FRONT_MARGIN_KLU 65)
scene(adaptive/neumann-A-front-margin-mpi2 2 ${P}/neumann_A.prm neumann_A_front_margin ${ADAPTIVE_A}
  "SET:Mesh refinement/Front margin=2" ${FRONT_MARGIN_KLU}
  "RESULT relative space-time L2 error temperature<0.0105"
  "RESULT mesh adaptations>3"
  "RESULT mesh adaptations<9")
# Longest wait = 1 interval: no adaptation may be skipped, and the run is the
# one adapted after every step (its reference).
scene(adaptive/neumann-A-front-margin-longest-wait 1 ${P}/neumann_A.prm neumann_A_adaptive
  ${ADAPTIVE_A} "SET:Mesh refinement/Front margin=2" "SET:Mesh refinement/Longest wait=1"
  ${ADAPTIVE_A_BOUNDS})
# Fronts present but not marked (Mark phase fronts = false) are followed by the
# indicator alone, so the margin must not skip: a stationary contact zone once
# let every adaptation after step 4 wait while the melt area doubled (4
# adaptations instead of 19). No exact solution: the reference is the code's
# (its melt area 0.1015625 equals the run without a margin); the bound on the
# adaptations is what fails the fault.
scene(adaptive/front-margin-unmarked-fronts 1 ${CMAKE_SOURCE_DIR}/prm/coupled_melting_contact.prm
  coupled_front_margin_unmarked "SET:Mesh refinement/Adaptive refinement interval=1"
  "SET:Mesh refinement/Initial adaptive refinements=1" "SET:Mesh refinement/Maximum level=2"
  "SET:Mesh refinement/Mark phase fronts=false" "SET:Mesh refinement/Front margin=1"
  "RESULT mesh adaptations>18")
# Refinement only: every adaptation conserves the enthalpy to round-off. (13 of
# the 14 adaptations change the mesh; one finds every flagged cell at the
# maximum level and leaves the mesh alone, which is not counted.)
scene(adaptive/neumann-A-refine-only 1 ${P}/neumann_A.prm neumann_A_refine_only ${ADAPTIVE_A}
  "SET:Mesh refinement/Coarsen fraction=0"
  "RESULT mesh adaptations>12"
  "RESULT max relative enthalpy change through refinement<1e-13"
  "RESULT max relative enthalpy change through coarsening<1e-300")
# An adaptation that flags no cell (Maximum level 0 = the initial level, which
# is also the minimum: nothing may be refined or coarsened) keeps the mesh and
# everything built on it: the run is the fixed-mesh run (neumann/A: error
# 0.01295275065) and counts no mesh adaptation.
scene(adaptive/neumann-A-no-op 1 ${P}/neumann_A.prm neumann_A_no_op
  "SET:Mesh refinement/Adaptive refinement interval=1"
  "SET:Mesh refinement/Maximum level=0"
  "RESULT mesh adaptations<1"
  "RESULT relative space-time L2 error temperature>0.012952750"
  "RESULT relative space-time L2 error temperature<0.012952751")
# Adaptivity pays only if it keeps the accuracy: Neumann A adapted every 3
# steps (front buffer 4, coarsen fraction 0.02: benchmarks/adaptivity.py, the
# settings of doc/adaptivity.md) must end within 1 % of the global run's
# space-time error at levels 1, 2 and 3 (measured +0.03 %, +0.36 %, -0.09 %).
# No time is checked here; the timings are the benchmark's.
add_test(NAME adaptive/neumann-A-vs-global
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/benchmarks/adaptivity.py --problem stefan
  --levels 3 --repeat 1 --require-error-ratio 1.01 --binary ${BIN})
# C1 as a ramp of 10 steps on the 16 x 8 mesh without pre-refinement, adapted
# after every step to the contact zone (buffer 3) and the displacement jumps:
# a and p0 within 0.1 % (the geometric pre-refinement of contact/hertz-C1 gives
# 1.9 % for a with half the DoFs of the final mesh, 6102 against 12416). The
# length in contact, summed over the adapted boundary's unequal weights, is the
# exact 2a = 0.0648833 within the finest contact cell h = 0.00048828 (measured
# 0.0649414).
set(ADAPTIVE_C1 "SET:Time stepping/Time step=0.1" "SET:Mesh refinement/Pre-refinement radius=0"
  "SET:Mesh refinement/Adaptive refinement interval=1" "SET:Mesh refinement/Maximum level=9"
  "SET:Mesh refinement/Coarsen fraction=0.02" "SET:Mesh refinement/Contact buffer=3")
set(ADAPTIVE_C1_BOUNDS
  "RESULT Hertz half-width relative error<0.002"
  "RESULT Hertz peak pressure relative error<0.001"
  "RESULT Hertz pressure profile relative L2 error<0.005"
  "RESULT contact length boundary 3>0.0643950" "RESULT contact length boundary 3<0.0653716"
  "RESULT displacement dofs<16000")
scene(adaptive/hertz-C1 1 ${P}/hertz_C1.prm hertz_C1_adaptive ${ADAPTIVE_C1}
  ${ADAPTIVE_C1_BOUNDS})
scene(adaptive/hertz-C1-mpi2 2 ${P}/hertz_C1.prm hertz_C1_adaptive ${ADAPTIVE_C1}
  ${ADAPTIVE_C1_BOUNDS})
# C2 with the pre-refinement on the lower block only (centre 0.3, 0.3): the
# cells across the interface are refined with it, and the patch test stays
# exact to round-off with 12 instead of 9 interface nodes.
set(ONE_SIDED "SET:Mesh refinement/Pre-refinement center=0.3, 0.3"
  "SET:Mesh refinement/Pre-refinement radius=0.1" "SET:Mesh refinement/Pre-refinement steps=2")
scene(adaptive/patch-C2-one-sided 1 ${P}/patch_C2.prm patch_C2_one_sided ${ONE_SIDED}
  ${PATCH_BOUNDS} "RESULT patch interface nodes>9")
scene(adaptive/patch-C2-one-sided-mpi2 2 ${P}/patch_C2.prm patch_C2_one_sided ${ONE_SIDED}
  ${PATCH_BOUNDS} "RESULT patch interface nodes>9")
# The coupled scene (melting at a contact interface) adapted every 2 steps:
# fronts, contact zone and both indicators; two ranks give the same meshes.
set(ADAPTIVE_COUPLED "SET:Mesh refinement/Adaptive refinement interval=2"
  "SET:Mesh refinement/Initial adaptive refinements=1" "SET:Mesh refinement/Maximum level=2"
  "SET:Output/VTU interval=0")
set(ADAPTIVE_COUPLED_BOUNDS
  "RESULT max energy-balance residual<1e-12"
  "RESULT max relative enthalpy change through refinement<1e-12"
  "RESULT max relative enthalpy change through coarsening<1e-4"
  "RESULT mesh adaptations>8")
scene(adaptive/coupled-melting-contact 1 ${CMAKE_SOURCE_DIR}/prm/coupled_melting_contact.prm
  coupled_melting_contact_adaptive ${ADAPTIVE_COUPLED} ${ADAPTIVE_COUPLED_BOUNDS})
scene(adaptive/coupled-melting-contact-mpi2 2 ${CMAKE_SOURCE_DIR}/prm/coupled_melting_contact.prm
  coupled_melting_contact_adaptive ${ADAPTIVE_COUPLED} ${ADAPTIVE_COUPLED_BOUNDS})
