# Tests: non-matching contact interfaces coupled by dual mortar (doc/contact.md,
# doc/benchmarks.md M1-M3). Every test name contains "mortar": `ctest -R mortar`.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# The coupling's kernel: matching sides give node-to-node, non-matching
# straight sides balance and reproduce linear fields, curved sides balance.
add_executable(unit_mortar unit_mortar.cc)
target_link_libraries(unit_mortar contact_stefan)
deal_ii_setup_target(unit_mortar)
add_test(NAME unit/mortar COMMAND ${T}/run_unit.sh $<TARGET_FILE:unit_mortar> ${T}/unit_mortar.output)

# The meshes (tests/make_mortar_msh.py): two blocks meshed independently.
set(MORTAR_MESHES)
function(mortar_mesh name)
  set(mesh ${CMAKE_CURRENT_BINARY_DIR}/mortar_${name}.msh)
  add_custom_command(OUTPUT ${mesh}
    COMMAND /usr/bin/python3 ${T}/make_mortar_msh.py ${mesh} ${ARGN}
    DEPENDS ${T}/make_mortar_msh.py)
  set(MORTAR_MESHES ${MORTAR_MESHES} ${mesh} PARENT_SCOPE)
endfunction()
mortar_mesh(1_2 --lower 4,2 --upper 8,4)
mortar_mesh(2_3 --lower 6,3 --upper 9,4)
mortar_mesh(1_7 --lower 2,2 --upper 14,6 --perturb upper)
mortar_mesh(7_1 --lower 14,6 --upper 2,2 --perturb lower)
mortar_mesh(matching_nodal --lower 8,4 --upper 8,4 --merge)
mortar_mesh(matching_split --lower 8,4 --upper 8,4)
add_custom_target(mortar_test_meshes ALL DEPENDS ${MORTAR_MESHES})
set(M ${CMAKE_CURRENT_BINARY_DIR})

# M1: the patch test on non-matching meshes. The uniform pressure at every
# slave node to round-off (measured 4.9e-14 to 3.0e-13), no penetration
# (measured 1.7e-18 to 3.6e-18 m), in one active-set pass.
set(MORTAR_PATCH_BOUNDS
  "RESULT patch stress relative error<1e-12"
  "RESULT patch pressure relative error<1e-12"
  "RESULT patch min interface gap>-1e-14"
  "RESULT max contact iterations<1.5"
  "RESULT mortar force balance interface 1-2<1e-14")
scene(mortar/patch-1-2 1 ${T}/scenes/mortar_patch.prm mortar_patch_1_2
  "SET:Geometry/Mesh file=${M}/mortar_1_2.msh" ${MORTAR_PATCH_BOUNDS}
  "RESULT patch interface nodes>8.5" "RESULT patch interface nodes<9.5")
scene(mortar/patch-2-3 1 ${T}/scenes/mortar_patch.prm mortar_patch_2_3
  "SET:Geometry/Mesh file=${M}/mortar_2_3.msh" ${MORTAR_PATCH_BOUNDS}
  "RESULT patch interface nodes>9.5" "RESULT patch interface nodes<10.5")
scene(mortar/patch-1-7-perturbed 1 ${T}/scenes/mortar_patch.prm mortar_patch_1_7
  "SET:Geometry/Mesh file=${M}/mortar_1_7.msh" ${MORTAR_PATCH_BOUNDS}
  "RESULT patch interface nodes>14.5" "RESULT patch interface nodes<15.5")
# The fine side below: the lower body is the slave ('Mortar slave = finer').
scene(mortar/patch-7-1-perturbed 1 ${T}/scenes/mortar_patch.prm mortar_patch_7_1
  "SET:Geometry/Mesh file=${M}/mortar_7_1.msh" ${MORTAR_PATCH_BOUNDS}
  "RESULT mortar slave body interface 1-2<1.5")

# M2: on matching meshes the mortar interface is the node-to-node one: the
# same statistics and RESULT lines within 1e-10 over four steps in which the
# active set grows.
add_test(NAME mortar/matching-equals-nodal
  COMMAND /usr/bin/python3 ${T}/compare_mortar.py ${BIN} ${T}/scenes/mortar_matching.prm
          ${M}/mortar_matching_nodal.msh ${M}/mortar_matching_split.msh)
