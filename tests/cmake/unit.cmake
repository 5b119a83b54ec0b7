# Tests: unit tests of the pure pieces (core, interfaces, verification kernels, output parts).
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- unit tests of the pure pieces --------------------------------------------
foreach(unit enthalpy_law neumann_solution contact adaptation q1_kernels solidification_history
    interface_conductance step_control mpi_start linear_solver dipping_interface)
  add_executable(unit_${unit} unit_${unit}.cc)
  target_link_libraries(unit_${unit} contact_stefan)
  deal_ii_setup_target(unit_${unit})
  add_test(NAME unit/${unit}
    COMMAND ${T}/run_unit.sh $<TARGET_FILE:unit_${unit}> ${T}/unit_${unit}.output)
endforeach()

# Every entry any owner declares is in the checkpoint's parameter fingerprint,
# but the documented exclusions (tests/unit_parameters.cc).
add_executable(unit_parameters unit_parameters.cc)
target_link_libraries(unit_parameters contact_stefan)
deal_ii_setup_target(unit_parameters)
add_test(NAME unit/parameters
  COMMAND ${T}/run_unit.sh $<TARGET_FILE:unit_parameters> ${T}/unit_parameters.output
          1 ${CMAKE_SOURCE_DIR}/prm/coupled_melting_contact.prm ${P}/neumann_A.prm)

# The registry of the report's parts, the parts each scene selects, the order of
# the RESULT lines and a part's checkpoint state (tests/unit_parts.cc).
add_executable(unit_parts unit_parts.cc)
target_link_libraries(unit_parts contact_stefan)
deal_ii_setup_target(unit_parts)
add_test(NAME unit/parts
  COMMAND ${T}/run_unit.sh $<TARGET_FILE:unit_parts> ${T}/unit_parts.output
          1 ${CMAKE_SOURCE_DIR}/prm/coupled_melting_contact.prm ${P}/neumann_A.prm
          ${P}/hertz_C1.prm ${P}/patch_C2.prm ${P}/shrink_fit_T4.prm
          ${T}/scenes/two_body_equilibrium.prm ${T}/scenes/stacked_blocks_section.prm
          ${T}/scenes/manufactured_stress.prm ${T}/scenes/thermoelastic_block_correction.prm
          ${P}/adiabatic_compression_T2_plateau.prm)
