# Tests: heat transfer across conductance interfaces (doc/interface_heat.md).
# Every name contains 'conductance': ctest -R conductance runs them all.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# I1: two slabs joined by a constant h, steady: exact for Q1 (round-off bounds).
set(CONDUCTANCE_I1_BOUNDS
  "RESULT relative L2 error temperature<1e-13"
  "RESULT max-norm error temperature<1e-11"
  "RESULT heat rate interface 0-1>21.05263157"
  "RESULT heat rate interface 0-1<21.05263159"
  "RESULT max energy-balance residual<1e-14")
scene(conductance/two-slabs-steady 1 ${T}/scenes/conductance_two_slabs.prm
  conductance_two_slabs ${CONDUCTANCE_I1_BOUNDS})
scene(conductance/two-slabs-steady-mpi2 2 ${T}/scenes/conductance_two_slabs.prm
  conductance_two_slabs ${CONDUCTANCE_I1_BOUNDS})
# I2: h = 0 insulates each slab: 100 below, 0 above, nothing crosses.
scene(conductance/two-slabs-insulated 1 ${T}/scenes/conductance_two_slabs.prm
  conductance_two_slabs_insulated
  "SET:Contact/Interface 0-1/Conductance/Constant=0"
  "SET:Exact solution/Function=y < 1 ? 100 : 0"
  "RESULT relative L2 error temperature<1e-13"
  "RESULT max-norm error temperature<1e-11"
  "RESULT heat rate interface 0-1<1e-300"
  "RESULT heat rate interface 0-1>-1e-300")

# I3: a prescribed gap, gas and radiation, against the closed form of
# benchmarks/conductance_gap.py (each rate to the 10 digits RESULT prints).
set(CONDUCTANCE_I3_BOUNDS
  "RESULT relative L2 error temperature<1e-13"
  "RESULT heat rate interface 0-1>26206.52703"
  "RESULT heat rate interface 0-1<26206.52705"
  "RESULT heat rate gas interface 0-1>1224.061713"
  "RESULT heat rate gas interface 0-1<1224.061715"
  "RESULT heat rate radiation interface 0-1>24982.46532"
  "RESULT heat rate radiation interface 0-1<24982.46534"
  "RESULT max energy-balance residual<1e-14")
scene(conductance/gap-gas-radiation 1 ${T}/scenes/conductance_gap.prm conductance_gap
  ${CONDUCTANCE_I3_BOUNDS})
scene(conductance/gap-gas-radiation-mpi2 2 ${T}/scenes/conductance_gap.prm conductance_gap
  ${CONDUCTANCE_I3_BOUNDS})

# A transient into a melting body through h: the bookkeeping (energy balance
# to round-off, no node outside H(Theta)), on two ranks, with adaptivity, and
# across a resume.
set(CONDUCTANCE_TRANSIENT_BOUNDS
  "RESULT max energy-balance residual<1e-14"
  "RESULT nodes with h outside H(Theta)<1"
  "RESULT steps with relaxation fallback<1")
set(CONDUCTANCE_ADAPTIVE "SET:Mesh refinement/Adaptive refinement interval=1"
  "SET:Mesh refinement/Initial global refinements=1"
  "SET:Mesh refinement/Initial adaptive refinements=2" "SET:Mesh refinement/Maximum level=3")
scene(conductance/transient-melting 1 ${T}/scenes/conductance_transient.prm
  conductance_transient ${CONDUCTANCE_TRANSIENT_BOUNDS})
scene(conductance/transient-melting-mpi2 2 ${T}/scenes/conductance_transient.prm
  conductance_transient ${CONDUCTANCE_TRANSIENT_BOUNDS})
scene(conductance/transient-melting-adaptive 1 ${T}/scenes/conductance_transient.prm
  conductance_transient_adaptive ${CONDUCTANCE_ADAPTIVE} ${CONDUCTANCE_TRANSIENT_BOUNDS})
scene(conductance/transient-melting-adaptive-mpi2 2 ${T}/scenes/conductance_transient.prm
  conductance_transient_adaptive ${CONDUCTANCE_ADAPTIVE} ${CONDUCTANCE_TRANSIENT_BOUNDS})
resume_test(restart/conductance-transient-adaptive 1 1 CONTACT_STEFAN_KILL_AFTER_STEP 20
  ${T}/scenes/conductance_transient.prm ${CONDUCTANCE_ADAPTIVE}
  "SET:Checkpoint/Interval (steps)=7")
resume_test(restart/conductance-transient-adaptive-mpi2 2 2 CONTACT_STEFAN_KILL_AFTER_STEP 20
  ${T}/scenes/conductance_transient.prm ${CONDUCTANCE_ADAPTIVE}
  "SET:Checkpoint/Interval (steps)=7")
