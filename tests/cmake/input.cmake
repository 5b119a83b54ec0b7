# Tests: bad input and data that turn bad later.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- bad input: one line naming the parameter, exit code 1, no output --------------
file(GLOB bad_inputs ${T}/bad_input/*.prm)
foreach(prm ${bad_inputs})
  get_filename_component(name ${prm} NAME_WE)
  file(STRINGS ${prm} expect REGEX "^# EXPECT: ")
  string(REPLACE "# EXPECT: " "" expect "${expect}")
  # '# CHECK: refuses': --check must refuse the file as well.
  file(STRINGS ${prm} check REGEX "^# CHECK: refuses")
  if(check)
    set(check check)
  endif()
  add_test(NAME bad_input/${name} COMMAND ${T}/expect_error.sh ${BIN} ${prm} "${expect}" ${check})
endforeach()
# Cells far from square: the run goes on, with one warning naming the worst
# cell, its aspect ratio and the parameter to change.
add_test(NAME bad_input/flat_cells_warning
  COMMAND ${T}/expect_warning.sh ${BIN} ${T}/scenes/flat_cells.prm
  "64 of 64 cells give the conductivity matrix positive off-diagonal entries")
add_test(NAME bad_input/missing_file
  COMMAND ${T}/expect_error.sh ${BIN} ${T}/bad_input/does-not-exist.prm "cannot be opened")
add_test(NAME bad_input/directory_as_parameter_file
  COMMAND ${T}/expect_error.sh ${BIN} ${T}/bad_input "is not a regular file")
# The switch of the serial MPI start (app/mpi_start.h) takes 'fast' or 'plain'.
add_test(NAME bad_input/serial_mpi_switch
  COMMAND env CONTACT_STEFAN_SERIAL_MPI=off ${T}/expect_error.sh ${BIN} ${P}/neumann_A.prm
          "CONTACT_STEFAN_SERIAL_MPI is 'off'")
# A binary file as the parameter file: one line, no raw control bytes echoed.
add_test(NAME bad_input/binary_parameter_file
  COMMAND sh -c "head -c 2000 ${BIN} > binary.prm && ${T}/expect_error.sh ${BIN} $PWD/binary.prm \
                 'is not a text file (it contains NUL bytes)'")
set_tests_properties(bad_input/binary_parameter_file PROPERTIES
  WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
# Parameter files in other encodings and line ends, and included files that are
# binary, CR-only or UTF-16 (tests/encode_scene.sh makes them from a scene at
# test time): one line naming the file and the reason. deal.II read a CR-only
# file as one comment line and ran the defaults with exit 0.
set(ENCODED_SCENE ${P}/neumann_A.prm)
set(ENCODING_CASES
  "cr-only\;has CR-only line ends (line 1 ends in a carriage return"
  "utf16\;is UTF-16 encoded (save it as ASCII or UTF-8)"
  "utf16le\;looks UTF-16 encoded (a NUL in every other byte"
  "include-binary\;.inc' (included in line 1 of '"
  "include-cr-only\;.inc' (included in line 1 of '"
  "include-utf16\;.inc' (included in line 1 of '")
foreach(case ${ENCODING_CASES})
  list(GET case 0 kind)
  list(GET case 1 expect)
  add_test(NAME bad_input/encoding_${kind}
    COMMAND sh -c "${T}/encode_scene.sh ${kind} ${ENCODED_SCENE} $PWD/encoding_${kind}.prm && \
                   ${T}/expect_error.sh ${BIN} $PWD/encoding_${kind}.prm \"${expect}\"")
  set_tests_properties(bad_input/encoding_${kind} PROPERTIES
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endforeach()
# CRLF line ends and a UTF-8 byte-order mark are read: the same scene.
foreach(kind crlf utf8-bom)
  add_test(NAME cli/check_encoding_${kind}
    COMMAND sh -c "${T}/encode_scene.sh ${kind} ${ENCODED_SCENE} $PWD/encoding_${kind}.prm && \
                   ${BIN} --check $PWD/encoding_${kind}.prm")
  set_tests_properties(cli/check_encoding_${kind} PROPERTIES
    WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR} PASS_REGULAR_EXPRESSION ": OK")
endforeach()
# An included file is found relative to the including file, from any working
# directory.
add_test(NAME cli/check_include COMMAND ${BIN} --check ${T}/scenes/include/neumann_A_included.prm)
set_tests_properties(cli/check_include PROPERTIES PASS_REGULAR_EXPRESSION ": OK")

# Invalid Gmsh meshes: one line naming the file and the first bad cell (or edge).
foreach(defect inverted bowtie split tjunction nonmatching split-rounded tjunction-rounded)
  set(mesh ${CMAKE_CURRENT_BINARY_DIR}/two_blocks_${defect}.msh)
  add_custom_command(OUTPUT ${mesh}
    COMMAND ${CMAKE_COMMAND} -DOUTPUT=${mesh} -DDEFECT=${defect} -P ${T}/make_two_blocks_msh.cmake
    DEPENDS ${T}/make_two_blocks_msh.cmake)
  list(APPEND defect_meshes ${mesh})
endforeach()
add_custom_target(defect_meshes ALL DEPENDS ${defect_meshes})
set(TWO_BLOCKS_MECHANICS ${T}/scenes/two_blocks_gmsh.prm)
set(DEFECT_CASES "bowtie\;is self-overlapping" "split\;coincide at (4, 0): the mesh is cut there"
  "tjunction\;the node (2, 1) lies inside the edge from (1, 1) to (3, 1) of body 1: a T-junction"
  "split-rounded\;coincide at (4, 0): the mesh is cut there"
  "tjunction-rounded\;the node (2, 1) lies inside the edge from (1, 1) to (3, 1) of body 1: a T-junction" "nonmatching\;the node (4, 1) lies inside the edge from (4, 0) to (4, 2) of body 2, a node of body 1: a non-matching interface")
foreach(case ${DEFECT_CASES})
  list(GET case 0 defect)
  list(GET case 1 expect)
  add_test(NAME bad_input/mesh_${defect}
    COMMAND sh -c "sed 's|^ *set Mesh file.*|set Mesh file = ${CMAKE_CURRENT_BINARY_DIR}/two_blocks_${defect}.msh|' \
                   ${TWO_BLOCKS_MECHANICS} > mesh_${defect}.prm && \
                   ${T}/expect_error.sh ${BIN} $PWD/mesh_${defect}.prm '${expect}'")
  set_tests_properties(bad_input/mesh_${defect} PROPERTIES WORKING_DIRECTORY ${CMAKE_CURRENT_BINARY_DIR})
endforeach()

# A cell listed clockwise is valid geometry: deal.II reorients it, and the run
# gives exactly the result of the counter-clockwise mesh (same reference).
scene(gmsh/two-blocks-clockwise-cell 1 ${T}/scenes/two_blocks_gmsh.prm two_blocks_gmsh
  "SET:Geometry/Mesh file=${CMAKE_CURRENT_BINARY_DIR}/two_blocks_inverted.msh"
  "RESULT relative L2 error temperature<1e-9")

# --- bad data at a later time: one line and exit code, complete earlier output ----
file(GLOB bad_runs ${T}/bad_runs/*.prm)
foreach(prm ${bad_runs})
  get_filename_component(name ${prm} NAME_WE)
  file(STRINGS ${prm} expect REGEX "^# EXPECT: ")
  string(REPLACE "# EXPECT: " "" expect "${expect}")
  file(STRINGS ${prm} code REGEX "^# EXPECT-EXIT: ")
  string(REPLACE "# EXPECT-EXIT: " "" code "${code}")
  add_test(NAME bad_run/${name} COMMAND ${T}/expect_failure.sh ${BIN} ${prm} ${code} "${expect}")
endforeach()
# On 2 ranks a run-time failure that every rank finds is one line, not one per rank.
add_test(NAME bad_run/fixed_point_not_converging-mpi2
  COMMAND ${T}/expect_failure.sh ${BIN} ${T}/bad_runs/fixed_point_not_converging.prm 2
          "the fixed-point coupling did not converge" 2)
set_tests_properties(bad_run/fixed_point_not_converging-mpi2 PROPERTIES PROCESSORS 2)
