# Tests: field-level tests (thermal, mechanics): each field alone through its step contract.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- field-level tests: each field driven alone through its step contract -------
set(FIELD_TESTS
  "thermal\;${T}/scenes/manufactured_flux.prm"
  "mechanical\;${P}/patch_C2.prm"
  "mechanical_load\;${T}/scenes/block_on_obstacle.prm"
  "mesh_change\;${P}/patch_C2.prm")
foreach(entry ${FIELD_TESTS})
  list(GET entry 0 field)
  list(GET entry 1 scene_file)
  string(REGEX REPLACE "_load$" "" program ${field})
  if(NOT TARGET field_${program})
    add_executable(field_${program} field_${program}.cc)
    target_link_libraries(field_${program} contact_stefan)
    deal_ii_setup_target(field_${program})
  endif()
  add_test(NAME field/${field}
    COMMAND ${T}/run_unit.sh $<TARGET_FILE:field_${program}> ${T}/field_${field}.output
            1 ${scene_file})
  add_test(NAME field/${field}-mpi2
    COMMAND ${T}/run_unit.sh $<TARGET_FILE:field_${program}> ${T}/field_${field}.output
            2 ${scene_file})
  set_tests_properties(field/${field}-mpi2 PROPERTIES PROCESSORS 2)
endforeach()
