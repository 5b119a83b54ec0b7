# Tests: the contact step.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- contact ------------------------------------------------------------------------
# C2 patch test: Q1 reproduces the uniform stress to round-off, every interface
# node in contact; two ranks give the same statistics.
set(PATCH_BOUNDS
  "RESULT patch stress relative error<1e-10"
  "RESULT patch pressure relative error<1e-10"
  "RESULT patch interface nodes active>8"
  "RESULT max contact iterations<3")
scene(contact/patch-C2 1 ${P}/patch_C2.prm patch_C2 ${PATCH_BOUNDS})
scene(contact/patch-C2-mpi2 2 ${P}/patch_C2.prm patch_C2 ${PATCH_BOUNDS})
# CG with ML AMG built for the rigid-body modes of both bodies: the same exact
# patch solution as the direct solver, serial and on 2 ranks.
scene(contact/patch-C2-cg-amg 1 ${P}/patch_C2.prm patch_C2_cg_amg
  "SET:Solver/Linear solver=cg-amg" "SET:Solver/CG tolerance=1e-12" ${PATCH_BOUNDS})
scene(contact/patch-C2-cg-amg-mpi2 2 ${P}/patch_C2.prm patch_C2_cg_amg
  "SET:Solver/Linear solver=cg-amg" "SET:Solver/CG tolerance=1e-12" ${PATCH_BOUNDS})
# The contact block of benchmarks/ (N = 32) with CG + AMG: inexact solves while
# the active set changes (5 sets from the cold start), the hierarchy recomputed
# on its aggregates, one tight solve on the settled set. The force must be the
# direct solver's 1.379839892e-2 to 1e-9 relative, on 1 and 2 ranks.
set(BLOCK_BOUNDS
  "RESULT contact force boundary 2>0.013798398906"
  "RESULT contact force boundary 2<0.013798398934"
  "RESULT calls contact step: linear solve<7"
  "RESULT elasticity solver: max CG iterations per solve<20")
scene(contact/block-cg-amg 1 ${CMAKE_SOURCE_DIR}/benchmarks/scenes/contact_block.prm
  contact_block_cg_amg "SET:Solver/Linear solver=cg-amg" ${BLOCK_BOUNDS})
scene(contact/block-cg-amg-mpi2 2 ${CMAKE_SOURCE_DIR}/benchmarks/scenes/contact_block.prm
  contact_block_cg_amg "SET:Solver/Linear solver=cg-amg" ${BLOCK_BOUNDS})
# The reuse limit (16 contact-set changes): at N = 128 the first set change
# after the cold start activates 65 nodes, and the kept hierarchy of the cold
# start is recomputed for the new set instead of preconditioning it: no CG
# solve above 16 iterations (19 without the limit, and the largest solve grew
# by about 30 % per doubling of N; doc/performance.md).
scene(contact/block-cg-amg-reuse-limit 1 ${CMAKE_SOURCE_DIR}/benchmarks/scenes/contact_block.prm
  contact_block_128_cg_amg "SET:Solver/Linear solver=cg-amg" "SET:Geometry/Subdivisions=128, 128"
  "RESULT contact force boundary 2>0.013788972735"
  "RESULT contact force boundary 2<0.013788972745"
  "RESULT elasticity solver: max CG iterations per solve<17"
  "RESULT elasticity solver: AMG recomputations>0")
# Without the limit: the same force, a hierarchy kept across the cold start's
# set change (and rebuilt when CG slowed down).
scene(contact/block-cg-amg-no-reuse-limit 1 ${CMAKE_SOURCE_DIR}/benchmarks/scenes/contact_block.prm
  contact_block_128_cg_amg "SET:Solver/Linear solver=cg-amg"
  "SET:Geometry/Subdivisions=128, 128" "SET:Solver/Elasticity AMG reuse limit=0"
  "RESULT contact force boundary 2>0.013788972735"
  "RESULT contact force boundary 2<0.013788972745"
  "RESULT elasticity solver: AMG recomputations<1")
# The hierarchy recomputed for every contact set (the automatic choice keeps
# the first one for all), or built afresh every time: the same force.
scene(contact/block-cg-amg-recompute 1 ${CMAKE_SOURCE_DIR}/benchmarks/scenes/contact_block.prm
  contact_block_cg_amg "SET:Solver/Linear solver=cg-amg" "SET:Solver/AMG update=recompute"
  ${BLOCK_BOUNDS})
# deal.II's aggregation threshold (the default before the fifth session): the
# same force and reference, so the threshold changes the preconditioner only.
scene(contact/block-cg-amg-threshold 1 ${CMAKE_SOURCE_DIR}/benchmarks/scenes/contact_block.prm
  contact_block_cg_amg "SET:Solver/Linear solver=cg-amg"
  "SET:Solver/Elasticity AMG aggregation threshold=1e-4" ${BLOCK_BOUNDS})
scene(contact/block-cg-amg-rebuild-mpi2 2 ${CMAKE_SOURCE_DIR}/benchmarks/scenes/contact_block.prm
  contact_block_cg_amg "SET:Solver/Linear solver=cg-amg" "SET:Solver/AMG update=rebuild"
  ${BLOCK_BOUNDS})
# The same isotropic tensor given by Lame parameters and as an anisotropic Voigt
# tensor (E = 1, nu = 0.3: lambda = 0.5769230769, mu = 0.3846153846).
set(LAME "SET:Materials/Body 0/Elasticity=lame" "SET:Materials/Body 1/Elasticity=lame"
  "SET:Materials/Body 0/Lame lambda=0.576923076923077"
  "SET:Materials/Body 1/Lame lambda=0.576923076923077"
  "SET:Materials/Body 0/Lame mu=0.384615384615385" "SET:Materials/Body 1/Lame mu=0.384615384615385")
scene(contact/patch-C2-lame 1 ${P}/patch_C2.prm patch_C2_lame ${LAME} ${PATCH_BOUNDS})
set(ISOTROPIC_VOIGT
  "1.346153846153846, 0.576923076923077, 0, 1.346153846153846, 0, 0.384615384615385")
set(VOIGT "SET:Materials/Body 0/Elasticity=anisotropic"
  "SET:Materials/Body 1/Elasticity=anisotropic"
  "SET:Materials/Body 0/Elasticity tensor=${ISOTROPIC_VOIGT}"
  "SET:Materials/Body 1/Elasticity tensor=${ISOTROPIC_VOIGT}")
scene(contact/patch-C2-voigt 1 ${P}/patch_C2.prm patch_C2_voigt ${VOIGT} ${PATCH_BOUNDS})
# Blocks of different stiffness (E = 1 below, 2 above: springs in series) and an
# orthotropic tensor (C11 != C22, so a swapped index would show).
scene(contact/patch-C2-stiff-upper 1 ${P}/patch_C2.prm patch_C2_stiff_upper
  "SET:Materials/Body 1/Youngs modulus=2" ${PATCH_BOUNDS})
set(ORTHO "2, 0.5, 0, 1, 0, 0.4")
scene(contact/patch-C2-orthotropic 1 ${P}/patch_C2.prm patch_C2_orthotropic
  "SET:Materials/Body 0/Elasticity=anisotropic" "SET:Materials/Body 1/Elasticity=anisotropic"
  "SET:Materials/Body 0/Elasticity tensor=${ORTHO}"
  "SET:Materials/Body 1/Elasticity tensor=${ORTHO}"
  ${PATCH_BOUNDS})
# Tied interface: the glued blocks carry the same uniform stress.
scene(contact/patch-C2-tied 1 ${P}/patch_C2.prm patch_C2_tied
  "SET:Contact/Interfaces=tied" "RESULT patch stress relative error<1e-10")
# A partly open interface (gap 0.02 for x < 0.6, closed beyond): a mixture of
# active and inactive interface nodes; 2 ranks must agree with 1.
set(PARTLY_OPEN "SET:Contact/Interface gap=if(x < 0.6, 0.02, 0)")
scene(contact/partly-open-interface 1 ${P}/patch_C2.prm patch_C2_partly_open ${PARTLY_OPEN}
  "RESULT max contact iterations<5" "RESULT patch min interface gap>-1e-14")
scene(contact/partly-open-interface-mpi2 2 ${P}/patch_C2.prm patch_C2_partly_open ${PARTLY_OPEN}
  "RESULT max contact iterations<5")
# Hertz with a small refined zone on 8 ranks: hanging nodes next to contact nodes
# on ranks that do not own them (constraints must agree between ranks).
set(SMALL_ZONE "SET:Mesh refinement/Pre-refinement radius=0.02")
scene(contact/hertz-C1-small-zone 1 ${P}/hertz_C1.prm hertz_C1_small_zone ${SMALL_ZONE}
  "RESULT max contact iterations<6")
scene(contact/hertz-C1-small-zone-mpi8 8 ${P}/hertz_C1.prm hertz_C1_small_zone ${SMALL_ZONE}
  "RESULT max contact iterations<6")
# Body force and traction: the total contact force is fixed by equilibrium.
scene(contact/block-on-obstacle 1 ${T}/scenes/block_on_obstacle.prm block_on_obstacle
  "RESULT contact force boundary 2>3.4999999999" "RESULT contact force boundary 2<3.5000000001")
# A roller boundary with a corner under one id (left and bottom of an 8 x 4 block):
# the corner gets both components fixed, and the top pushed down by 0.001 gives
# uniaxial strain, force = 8 (lambda + 2 mu) 0.001 / 4 = 0.002692307692 exactly.
scene(contact/kinked-roller 1 ${T}/scenes/kinked_roller.prm kinked_roller
  "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/kink.msh"
  "RESULT contact force boundary 12>0.0026923076" "RESULT contact force boundary 12<0.0026923078")
# An inclined interface (17, 45, -45 degrees from the vertical) between two
# blocks under equal biaxial compression p = 0.01, rollers on the left and the
# bottom: sigma = -p I, so every interface node -- including the one on the
# bottom roller, where the roller's reaction must not enter the contact force --
# has pressure p, and the interface force is p / cos(angle) (length 1/cos).
# Force bounds: the exact p / cos(angle) to 1e-9 relative.
set(INCLINED_CASES "17\;0.010456917554\;0.010456917575"
  "45\;0.014142135609\;0.014142135638" "-45\;0.014142135609\;0.014142135638")
foreach(case ${INCLINED_CASES})
  list(GET case 0 angle)
  list(GET case 1 force_low)
  list(GET case 2 force_high)
  set(mesh ${CMAKE_CURRENT_BINARY_DIR}/inclined_${angle}.msh)
  add_custom_command(OUTPUT ${mesh}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${mesh} -DANGLE=${angle} -DN=4
            -P ${T}/make_inclined_blocks_msh.cmake
    DEPENDS ${T}/make_inclined_blocks_msh.cmake)
  list(APPEND inclined_meshes ${mesh})
  scene(contact/inclined-interface-${angle} 1 ${T}/scenes/inclined_interface.prm
    inclined_interface_${angle} "SET:Geometry/Mesh file=${mesh}"
    "RESULT active contact nodes>4"
    "RESULT max contact pressure<0.010000000001"
    "RESULT min contact pressure at active nodes>0.009999999999"
    "RESULT contact force interface 1-2>${force_low}"
    "RESULT contact force interface 1-2<${force_high}")
endforeach()
add_custom_target(inclined_meshes ALL DEPENDS ${inclined_meshes})
# The interface geometry without a solve: pairing, normals, weights and corners
# on the 17-degree mesh and on an L-shaped interface (tests/unit_body_interface.cc).
add_executable(unit_body_interface unit_body_interface.cc)
target_link_libraries(unit_body_interface contact_stefan)
deal_ii_setup_target(unit_body_interface)
add_test(NAME unit/body_interface
  COMMAND ${T}/run_unit.sh $<TARGET_FILE:unit_body_interface> ${T}/unit_body_interface.output
          1 ${CMAKE_CURRENT_BINARY_DIR}/inclined_17.msh)
scene(contact/inclined-interface-17-mpi2 2 ${T}/scenes/inclined_interface.prm
  inclined_interface_17 "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/inclined_17.msh"
  "RESULT min contact pressure at active nodes>0.009999999999")
# Contact pressure windows (Output/Contact pressure windows, doc/output.md) on
# the 17-degree interface, whose exact pressure is p = 0.01 everywhere: the mean
# over any band that holds interface nodes is p, both bounds included (y from 0
# to 0.5 holds the roller corner node, x from 0.9 to 1.2 a part of the inclined
# interface, y from 0.25 to 1 the top corner), serial and on 2 ranks (the sums
# of both ranks' nodes).
set(PRESSURE_WINDOWS
  "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/inclined_17.msh"
  "SET:Output/Contact pressure windows=y from 0 to 0.5, x from 0.9 to 1.2, y from 0.25 to 1")
foreach(window "y from 0 to 0.5" "x from 0.9 to 1.2" "y from 0.25 to 1")
  list(APPEND PRESSURE_WINDOWS
    "RESULT mean contact pressure interface 1-2 ${window}>0.009999999999"
    "RESULT mean contact pressure interface 1-2 ${window}<0.010000000001")
endforeach()
# Where the obstacle meets the interface (tests/scenes/obstacle_meets_interface.prm):
# exact pressures 0.01 (obstacle) and 0.02 (interface) in every window, and the
# windows' lengths: the interface once per node pair, the obstacle on both bodies.
set(JUNCTION_WINDOWS)
# group:band:lower bound:upper bound of the length (awk compares the numbers as
# written: no arithmetic in a bound)
foreach(window "interface 0-1:x from 0 to 1:0.999999999999:1.000000000001"
               "interface 0-1:x from 0 to 0.1:0.249999999999:0.250000000001"
               "interface 0-1:y from 0.9 to 1.1:0.999999999999:1.000000000001"
               "interface 0-1:y from 0 to 2:0.999999999999:1.000000000001"
               "boundary 0:x from 0 to 1:1.999999999999:2.000000000001"
               "boundary 0:x from 0 to 0.1:1.999999999999:2.000000000001"
               "boundary 0:y from 0.9 to 1.1:0.499999999999:0.500000000001"
               "boundary 0:y from 0 to 2:1.999999999999:2.000000000001")
  string(REPLACE ":" ";" parts "${window}")
  list(GET parts 0 group)
  list(GET parts 1 band)
  list(GET parts 2 low)
  list(GET parts 3 high)
  if(group STREQUAL "boundary 0")
    set(p_low 0.009999999999)
    set(p_high 0.010000000001)
  else()
    set(p_low 0.019999999999)
    set(p_high 0.020000000001)
  endif()
  list(APPEND JUNCTION_WINDOWS
    "RESULT mean contact pressure ${group} ${band}>${p_low}"
    "RESULT mean contact pressure ${group} ${band}<${p_high}"
    "RESULT contact window length ${group} ${band}>${low}"
    "RESULT contact window length ${group} ${band}<${high}")
endforeach()
# Every node is in contact: the length in contact is the whole interface (1)
# and the whole obstacle boundary, on both bodies (2), at the end and over the
# steps.
foreach(what "contact length" "max contact length over the steps")
  list(APPEND JUNCTION_WINDOWS
    "RESULT ${what} interface 0-1>0.999999999999" "RESULT ${what} interface 0-1<1.000000000001"
    "RESULT ${what} boundary 0>1.999999999999" "RESULT ${what} boundary 0<2.000000000001")
endforeach()
scene(contact/pressure-windows-junction 1 ${T}/scenes/obstacle_meets_interface.prm
  obstacle_meets_interface ${JUNCTION_WINDOWS})
scene(contact/pressure-windows-junction-mpi2 2 ${T}/scenes/obstacle_meets_interface.prm
  obstacle_meets_interface ${JUNCTION_WINDOWS})
scene(contact/pressure-windows 1 ${T}/scenes/inclined_interface.prm
  inclined_interface_17_windows ${PRESSURE_WINDOWS})
scene(contact/pressure-windows-mpi2 2 ${T}/scenes/inclined_interface.prm
  inclined_interface_17_windows ${PRESSURE_WINDOWS})
# Inclined section lines (Output/Section lines 'a x + b y = c') on the 45-degree
# mesh (N = 4), where sigma = -p I: the interface x - y = 0.5 (length sqrt 2, a
# body on each side), the middle grid line of each trapezoid, x - 0.5 y = 0.25 and
# x - 0.5 y = 1.25 (length sqrt 1.25), and y = 0.5 across both (length 2). The
# normal force is -p times the length, the tangential zero, for both outputs
# (but the cell-centre tangential force of y = 0.5, below).
# The exact force is a function evaluated at each line's point nearest the
# origin: (0.25, -0.25), (0.2, -0.1), (1, -0.5) and (0, 0.5).
set(INCLINED_SECTIONS
  "SET:Output/Section lines=x - y = 0.5, x - 0.5 y = 0.25, 1 * x - 0.5 * y = 1.25, y = 0.5"
  "SET:Exact solution/Section normal force=if(y > 0, -0.02, if(abs(y + 0.25) < 0.01, -0.01 * sqrt(2), -0.01 * sqrt(1.25)))"
  "RESULT section sides compared>7"
  "RESULT section sides on rows of equal cells<1"
  "RESULT max relative section normal force error (cell centres)<1e-12"
  "RESULT max relative section normal force error (recovered)<1e-12"
  "RESULT section force x-y=0.5 minus side: tangential (cell centres)<1e-14"
  "RESULT section force x-y=0.5 minus side: tangential (cell centres)>-1e-14"
  "RESULT section force x-y=0.5 plus side: tangential (recovered)<1e-14"
  "RESULT section force x-y=0.5 plus side: tangential (recovered)>-1e-14"
  # y = 0.5 keeps its load term: the row's end node on the right side carries
  # half a cell's traction, p h / 2 = 1.25e-3 (doc/output.md, inclined lines).
  "RESULT section force y=0.5 below: tangential (cell centres)>0.0012499999999"
  "RESULT section force y=0.5 below: tangential (cell centres)<0.0012500000001"
  "RESULT section force y=0.5 above: tangential (cell centres)<-0.0012499999999"
  "RESULT section force y=0.5 above: tangential (cell centres)>-0.0012500000001")
scene(stress_recovery/section-force-inclined 1 ${T}/scenes/inclined_interface.prm
  inclined_interface_45_sections "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/inclined_45.msh"
  ${INCLINED_SECTIONS})
scene(stress_recovery/section-force-inclined-mpi2 2 ${T}/scenes/inclined_interface.prm
  inclined_interface_45_sections "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/inclined_45.msh"
  ${INCLINED_SECTIONS})

# An obstacle meeting a tied interface: the obstacle force is fixed by equilibrium.
scene(contact/tied-on-obstacle 1 ${T}/scenes/tied_on_obstacle.prm tied_on_obstacle
  "RESULT contact force boundary 0>0.0199999999" "RESULT contact force boundary 0<0.0200000001"
  "RESULT max contact pressure<0.0100000001"
  "RESULT min contact pressure at active nodes>0.0099999999")

# Laws per interface (tests/scenes/mixed_interfaces.prm): three stacked blocks,
# 0-1 tied and 1-2 a contact with its own gap 0.002 (the global default: a
# contact without gap). The uniaxial stress E*(delta - g)/H to round-off and
# the force on 1-2; the same with 0-1 a contact at the default gap, and with
# 1-2's gap taken from the global default while 0-1 sets its own (0).
set(MIXED_INTERFACE_BOUNDS
  "RESULT max relative stress L2 error<1e-12"
  "RESULT contact force interface 1-2>0.0058608058598" "RESULT contact force interface 1-2<0.0058608058618")
scene(contact/mixed-interfaces 1 ${T}/scenes/mixed_interfaces.prm mixed_interfaces
  ${MIXED_INTERFACE_BOUNDS})
scene(contact/mixed-interfaces-mpi2 2 ${T}/scenes/mixed_interfaces.prm mixed_interfaces
  ${MIXED_INTERFACE_BOUNDS})
# On 3 ranks some rank owns no vertex of the tied interface 0-1: every rank must
# still decide alike which groups are tied (a rank-local decision hung here).
scene(contact/mixed-interfaces-mpi3 3 ${T}/scenes/mixed_interfaces.prm mixed_interfaces
  ${MIXED_INTERFACE_BOUNDS})
scene(contact/mixed-interfaces-both-contact 1 ${T}/scenes/mixed_interfaces.prm
  mixed_interfaces_both_contact "SET:Contact/Interface 0-1/Kind=default" ${MIXED_INTERFACE_BOUNDS}
  "RESULT contact force interface 0-1>0.0058608058598" "RESULT contact force interface 0-1<0.0058608058618")
scene(contact/mixed-interfaces-default-gap 1 ${T}/scenes/mixed_interfaces.prm
  mixed_interfaces_both_contact "SET:Contact/Interface 0-1/Kind=contact"
  "SET:Contact/Interface 0-1/Gap=0" "SET:Contact/Interface 1-2/Gap=" "SET:Contact/Interface gap=0.002"
  ${MIXED_INTERFACE_BOUNDS}
  "RESULT contact force interface 0-1>0.0058608058598" "RESULT contact force interface 0-1<0.0058608058618")

# Open-gap variant: gap 0.02 > delta = 0.01: no stress, no pressure, gap kept.
scene(contact/patch-C2-open-gap 1 ${P}/patch_C2.prm patch_C2_open_gap
  "SET:Contact/Interface gap=0.02"
  "RESULT active contact nodes<1"
  "RESULT max contact pressure<1e-14"
  "RESULT patch stress relative error<1e-10"
  "RESULT patch min interface gap>0.00999999")
# C1 Hertz on the coarsest ladder level, cold start. The length in contact
# (the weights of the active nodes: each edge node adds half a cell beyond
# itself) is the exact width 2a = 0.0651884 within one contact mesh width
# h = 0.00390625.
scene(contact/hertz-C1 1 ${P}/hertz_C1.prm hertz_C1
  "RESULT contact length boundary 3>0.0612821" "RESULT contact length boundary 3<0.0690947"
  "RESULT Hertz half-width relative error<0.028"
  "RESULT Hertz peak pressure relative error<0.0005"
  "RESULT Hertz pressure profile relative L2 error<0.022"
  "RESULT contact iterations first step<10")
# The same indentation as a load ramp of 10 steps: warm-started steps need at
# most 3 iterations.
scene(contact/hertz-C1-ramp 1 ${P}/hertz_C1.prm hertz_C1_ramp
  "SET:Time stepping/Time step=0.1"
  "RESULT max contact iterations after the first step<4"
  "RESULT Hertz pressure profile relative L2 error<0.022")
