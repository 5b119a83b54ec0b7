# Tests: solidification stress, material born stress-free (doc/solidification.md).
# Every test's name contains 'birth', so that 'ctest -R birth' runs them all.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- the frozen layer (tests/scenes/birth_layer.prm) --------------------------------
# A laterally held plane-strain layer freezes out of its melt and cools to
# Theta_m - 10: the final stress is E alpha dT / (1 - nu) = 4/3 in x and z,
# uniform, to round-off of the cell-centre values, whatever Theta_0 and the
# cooling path (all 256 material points born once).
set(BIRTH_EXACT
  "RESULT max relative stress L2 error (cell centres)<1e-12"
  "RESULT max relative stress L2 error (recovered)<1e-12"
  "RESULT max energy-balance residual<1e-12"
  "RESULT nodes with h outside H(Theta)<1")
# (One reference for 1 and 2 ranks; KLU on 2 ranks counts its own
# factorisations, klu_factorisations.)
scene(birth/layer 1 ${T}/scenes/birth_layer.prm birth_layer ${BIRTH_EXACT}
  "RESULT material points born>255.5" "RESULT material points born<256.5")
klu_factorisations(BIRTH_LAYER_KLU 15)
scene(birth/layer-mpi2 2 ${T}/scenes/birth_layer.prm birth_layer ${BIRTH_EXACT} ${BIRTH_LAYER_KLU})
# Theta_0 = 50: the same run, to the last digit of every RESULT line and
# statistics row (birth_layer.output): nothing of a body that is stress-free at
# solidification depends on Theta_0 once it has been melt.
scene(birth/layer-reference-50 1 ${T}/scenes/birth_layer.prm birth_layer
  "SET:Coupling/Reference temperature=50" ${BIRTH_EXACT})
# Another cooling path: to Theta_m - 20 first, then back up to Theta_m - 10.
set(BIRTH_PATH_B "if(t < 1, -20, -10)")
scene(birth/layer-cooling-path 1 ${T}/scenes/birth_layer.prm birth_layer-cooling-path
  "SET:Boundary conditions/Thermal boundary 2/Value=${BIRTH_PATH_B}"
  "SET:Boundary conditions/Thermal boundary 3/Value=${BIRTH_PATH_B}" ${BIRTH_EXACT})
# Frozen, re-molten (Theta_m + 5) and frozen again: every point's history
# restarts twice (768 births), and the final stress is again 4/3.
set(BIRTH_REMELT "if(t < 1.5, -10, if(t < 4, 5, -10))")
scene(birth/layer-remelt 1 ${T}/scenes/birth_layer.prm birth_layer-remelt
  "SET:Coupling/Reference temperature=50"
  "SET:Boundary conditions/Thermal boundary 2/Value=${BIRTH_REMELT}"
  "SET:Boundary conditions/Thermal boundary 3/Value=${BIRTH_REMELT}"
  "SET:Time stepping/Time step function=if(t < 6, tau, 100)" ${BIRTH_EXACT}
  "RESULT material points born>767.5" "RESULT material points born<768.5")
# Where the birth strain itself decides the answer: the melt is stretched
# (the right face at u_x = 0.001, e_xx = 0.004) while it freezes, and the
# stretch is then halved (u_x = 0.0005 from t = 100). Born in the stretched
# configuration, the layer ends at sigma_xx = E / (1 - nu^2) (0.002 - 0.004) +
# 4/3 = -0.8 and sigma_zz = nu sigma_xx + E alpha dT = 0.8 (e_ref = 0 would
# give +3.47 and 1.87).
scene(birth/layer-stretched 1 ${T}/scenes/birth_layer.prm birth_layer-stretched
  "SET:Boundary conditions/Mechanical boundary 1/Type=displacement"
  "SET:Boundary conditions/Mechanical boundary 1/Components=x"
  "SET:Boundary conditions/Mechanical boundary 1/Value=if(t < 100, 0.001, 0.0005)<semicolon> 0"
  "SET:Exact solution/Stress=-0.8<semicolon> 0<semicolon> 0<semicolon> 0.8" ${BIRTH_EXACT})
# In plane stress (a thin plate: sigma_zz = 0) the frozen layer, held in x and
# free in y, is uniaxial: sigma_xx = E alpha dT = 1, everything else 0.
scene(birth/layer-plane-stress 1 ${T}/scenes/birth_layer.prm birth_layer-plane-stress
  "SET:Physics/Plane constraint=plane stress"
  "SET:Exact solution/Stress=1<semicolon> 0<semicolon> 0<semicolon> 0" ${BIRTH_EXACT})
# In generalized plane strain (e_zz uniform and free, no net out-of-plane force)
# a layer frozen from its faces is NOT uniformly stressed in the end: points
# born later carry the e_zz of their later birth (residual stress; the freezing
# slab below checks it against the semi-analytic solution). Frozen all at once
# instead (insulated faces, a uniform heat sink of 10.5 until t = 2: every node
# crosses the plateau in the same step, and the layer ends at Theta_m - 10),
# every point has the same reference, and the layer held in x is uniaxial:
# sigma_xx = E alpha dT = 1, sigma_zz = 0, whatever Theta_0. (The same scene in
# plane strain ends at 4/3 within 1.5e-11: the enthalpy step's plateau
# crossing, not the out-of-plane strain, sets the 1e-11.)
set(BIRTH_UNIFORM "SET:Boundary conditions/Thermal boundary 2/Type=flux"
  "SET:Boundary conditions/Thermal boundary 2/Value=0"
  "SET:Boundary conditions/Thermal boundary 3/Type=flux"
  "SET:Boundary conditions/Thermal boundary 3/Value=0"
  "SET:Materials/Body 0/Heat source=if(t < 2.025, -10.5, 0)"
  "SET:Physics/Plane constraint=generalized plane strain")
set(BIRTH_GPS_EXACT
  "RESULT max relative stress L2 error (cell centres)<1e-10"
  "RESULT max relative stress L2 error (recovered)<1e-10"
  "RESULT max energy-balance residual<1e-12"
  "RESULT relative out-of-plane force body 0<1e-13"
  "RESULT relative out-of-plane force body 0>-1e-13"
  "RESULT material points born>255.5" "RESULT material points born<256.5")
scene(birth/layer-gps-uniform 1 ${T}/scenes/birth_layer.prm birth_layer-gps-uniform
  ${BIRTH_UNIFORM} "SET:Exact solution/Stress=1<semicolon> 0<semicolon> 0<semicolon> 0"
  ${BIRTH_GPS_EXACT})
scene(birth/layer-gps-uniform-reference-50 1 ${T}/scenes/birth_layer.prm
  birth_layer-gps-uniform ${BIRTH_UNIFORM} "SET:Coupling/Reference temperature=50"
  "SET:Exact solution/Stress=1<semicolon> 0<semicolon> 0<semicolon> 0" ${BIRTH_GPS_EXACT})
scene(birth/layer-gps-uniform-mpi2 2 ${T}/scenes/birth_layer.prm birth_layer-gps-uniform
  ${BIRTH_UNIFORM} "SET:Exact solution/Stress=1<semicolon> 0<semicolon> 0<semicolon> 0"
  ${BIRTH_GPS_EXACT})
# Born stretched (e_xx = 0.004) and the stretch halved: sigma_xx = E (0.002 -
# 0.004) + E alpha dT = -1, sigma_zz = 0 only if each point also keeps the
# e_zz of its birth (the stretched melt narrows out of plane).
scene(birth/layer-gps-uniform-stretched 1 ${T}/scenes/birth_layer.prm
  birth_layer-gps-uniform-stretched ${BIRTH_UNIFORM}
  "SET:Boundary conditions/Mechanical boundary 1/Type=displacement"
  "SET:Boundary conditions/Mechanical boundary 1/Components=x"
  "SET:Boundary conditions/Mechanical boundary 1/Value=if(t < 100, 0.001, 0.0005)<semicolon> 0"
  "SET:Exact solution/Stress=-1<semicolon> 0<semicolon> 0<semicolon> 0" ${BIRTH_GPS_EXACT})
# The melting threshold (Materials/Body N/Phase change/Solid fraction at
# melting). The layer (plane strain) frozen all at once as above, then stretched
# while solid (the right face to u_x = 0.001 from t = 3: e_xx = 0.004), warmed to
# the middle of its plateau (solid fraction 0.5, t in (4, 5.5]) and frozen again
# (t in (6, 7.5]) to Theta_m - 10. With one threshold (the default, 1) every
# point re-melts at 0.5 and is born again stretched: sigma_xx = sigma_zz = E alpha
# dT / (1 - nu) = 4/3. With 'Solid fraction at melting = 0.1' no point re-melts,
# each keeps its first birth (unstretched): sigma_xx = E / (1 - nu^2) 0.004 + 4/3
# = 5.6, sigma_zz = nu sigma_xx + E alpha dT = 2.4.
set(BIRTH_TOUCH ${BIRTH_UNIFORM} "SET:Physics/Plane constraint=plane strain"
  "SET:Materials/Body 0/Heat source=if(t < 2.025, -10.5, if(t > 4.025 && t < 5.525, 10, if(t > 6.025 && t < 7.525, -10, 0)))"
  "SET:Boundary conditions/Mechanical boundary 1/Type=displacement"
  "SET:Boundary conditions/Mechanical boundary 1/Components=x"
  "SET:Boundary conditions/Mechanical boundary 1/Value=if(t < 3, 0, 0.001)<semicolon> 0"
  "SET:Time stepping/Time step function=if(t < 8, tau, 100)")
set(BIRTH_TOUCH_EXACT
  "RESULT max relative stress L2 error (cell centres)<1e-10"
  "RESULT max relative stress L2 error (recovered)<1e-10"
  "RESULT max energy-balance residual<1e-12")
scene(birth/layer-touch-plateau 1 ${T}/scenes/birth_layer.prm birth_layer-touch-plateau
  ${BIRTH_TOUCH} "SET:Exact solution/Stress=4 / 3<semicolon> 0<semicolon> 0<semicolon> 4 / 3"
  ${BIRTH_TOUCH_EXACT} "RESULT material points born>767.5" "RESULT material points born<768.5")
scene(birth/layer-touch-plateau-hysteresis 1 ${T}/scenes/birth_layer.prm
  birth_layer-touch-plateau-hysteresis ${BIRTH_TOUCH}
  "SET:Materials/Body 0/Phase change/Solid fraction at melting=0.1"
  "SET:Exact solution/Stress=5.6<semicolon> 0<semicolon> 0<semicolon> 2.4" ${BIRTH_TOUCH_EXACT}
  "RESULT material points born>255.5" "RESULT material points born<256.5")
# The switch off (the seed's model) with Theta_0 = 50: the stress of the
# global reference, E alpha (Theta_0 - Theta_f) / (1 - nu) = 8, to round-off.
scene(birth/layer-switch-off 1 ${T}/scenes/birth_layer.prm birth_layer-switch-off
  "SET:Coupling/Reference temperature=50"
  "SET:Materials/Body 0/Phase change/Stress free at solidification=false"
  "SET:Exact solution/Stress=8<semicolon> 0<semicolon> 0<semicolon> 8" ${BIRTH_EXACT})
# Adapted every step (the fronts refined up to level 2, nothing coarsened:
# once the layer is frozen and the temperature uniform, a fixed-fraction
# marking would follow round-off; coarsening is checked bit for bit in
# unit/solidification_history): the references move with the mesh while the
# layer freezes (each child takes its quadrant's point), and the final stress
# is still exact.
set(BIRTH_ADAPTIVE "SET:Mesh refinement/Adaptive refinement interval=1"
  "SET:Mesh refinement/Maximum level=2" "SET:Mesh refinement/Minimum level=0"
  "SET:Mesh refinement/Coarsen fraction=0")
scene(birth/layer-adaptive 1 ${T}/scenes/birth_layer.prm birth_layer-adaptive
  ${BIRTH_ADAPTIVE} ${BIRTH_EXACT} "RESULT mesh adaptations>3.5")
# (Its own reference: on the adapted mesh the enthalpy step's damped Newton
# path, not its result, depends on the order of the parallel sums.)
scene(birth/layer-adaptive-mpi2 2 ${T}/scenes/birth_layer.prm birth_layer-adaptive-mpi2
  ${BIRTH_ADAPTIVE} ${BIRTH_EXACT} "RESULT mesh adaptations>3.5")

# --- the freezing slab against the closed form (tests/scenes/birth_freezing_slab.prm) ---
# A melt frozen from a wall (S1's Neumann problem, mirrored), the slab held
# laterally: the crust's stress is -E alpha / (1 - nu) (Theta - Theta_m), the
# melt's the same with the melt's E, in closed form (doc/benchmarks.md B1).
# On 1 x 32 cells the cell-centre stress is within 3.9 % (L2, relative) at
# t = 1; the ladder of 4 levels (h and tau halved) converges at rate 1.04 for
# the cell-centre and 1.22 for the recovered stress (measured).
scene(birth/freezing-slab 1 ${T}/scenes/birth_freezing_slab.prm birth_freezing_slab
  "RESULT max relative stress L2 error (cell centres)<0.06"
  "RESULT max relative stress L2 error (recovered)<0.09"
  "RESULT max energy-balance residual<1e-12")
add_test(NAME birth/freezing-slab-rate
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/benchmarks/ladder.py
  ${T}/scenes/birth_freezing_slab.prm --levels 3 --binary ${BIN}
  --require-rate "max relative stress L2 error (cell centres)>=0.9"
  --require-rate "max relative stress L2 error (recovered)>=1.1")

# The freezing slab in generalized plane strain against the semi-analytic
# solution of benchmarks/gps_slab.py (doc/benchmarks.md B1), steps uniform in
# sqrt(t) (e_zz changes like sqrt(t) at the start). The file must hold the
# script's solution; on 1 x 32 cells the cell-centre stress is within 6.8 %
# and the net out-of-plane force is zero to round-off.
add_test(NAME birth/freezing-slab-gps-exact-solution
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/benchmarks/gps_slab.py
  --check ${T}/scenes/birth_freezing_slab_gps.prm)
scene(birth/freezing-slab-gps 1 ${T}/scenes/birth_freezing_slab_gps.prm birth_freezing_slab_gps
  "RESULT max relative stress L2 error (cell centres)<0.085"
  "RESULT max relative stress L2 error (recovered)<0.12"
  "RESULT relative out-of-plane force body 0<1e-13"
  "RESULT relative out-of-plane force body 0>-1e-13"
  "RESULT max energy-balance residual<1e-12")
# It converges, but at about half order (measured 0.55 for the cell-centre stress
# over levels 0-4, doc/benchmarks.md B1): the cells at the front are already
# stiff (their nodes are on the plateau) while their points still carry the
# melt's reference, and with e_zz != 0 that costs a stress of E_s e_zz there.
add_test(NAME birth/freezing-slab-gps-rate
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/benchmarks/ladder.py
  ${T}/scenes/birth_freezing_slab_gps.prm --levels 3 --binary ${BIN}
  --require-rate "max relative stress L2 error (cell centres)>=0.4"
  --require-rate "max relative stress L2 error (recovered)>=0.6")

# --- checkpoint/restart ---------------------------------------------------------------
# Killed mid-solidification (after step 5, checkpoint at step 4; the fronts
# are inside the layer, the adaptive mesh still refining) and resumed: the
# references come back with the mesh, and the resumed run repeats the
# uninterrupted one (tests/run_resume.sh), on 1 and 2 ranks.
set(BIRTH_RESUME "SET:Checkpoint/Interval (steps)=2")
resume_test(restart/birth-layer 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 5
  ${T}/scenes/birth_layer.prm ${BIRTH_RESUME})
resume_test(restart/birth-layer-adaptive 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 5
  ${T}/scenes/birth_layer.prm ${BIRTH_RESUME} ${BIRTH_ADAPTIVE})
resume_test(restart/birth-layer-adaptive-mpi2 2 2 CONTACT_STEFAN_KILL_AFTER_STEP 5
  ${T}/scenes/birth_layer.prm ${BIRTH_RESUME} ${BIRTH_ADAPTIVE})
# Generalized plane strain: e_zz and its value at the step's start come back
# too (the births of the next steps extrapolate from both).
resume_test(restart/birth-layer-gps 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 5
  ${T}/scenes/birth_layer.prm ${BIRTH_RESUME} "SET:Physics/Plane constraint=generalized plane strain")
# With CG + AMG the e_zz responses are CG's starting guesses: a checkpoint drops
# them, as a resumed run has none (the statistics of the CG work then agree).
resume_test(restart/birth-layer-gps-cg-amg 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 5
  ${T}/scenes/birth_layer.prm ${BIRTH_RESUME} "SET:Physics/Plane constraint=generalized plane strain"
  "SET:Solver/Linear solver=cg-amg")

# (The bad input of the switch: tests/bad_input/birth_*.prm.)
