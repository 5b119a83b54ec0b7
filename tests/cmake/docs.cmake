# Tests: the command line and the documentation.
# Included by tests/CMakeLists.txt (BIN, T, P and the helper functions are set there
# or in the files included before this one).

# --- command line and generated documentation -----------------------------------------
add_test(NAME cli/help COMMAND ${BIN} --help)
set_tests_properties(cli/help PROPERTIES PASS_REGULAR_EXPRESSION "Usage: contact-stefan")
# --version names the commit, the compiler, the build type and deal.II; every
# run's output directory gets provenance.json (doc/output.md).
add_test(NAME cli/version COMMAND ${BIN} --version)
set_tests_properties(cli/version PROPERTIES PASS_REGULAR_EXPRESSION
  "^contact-stefan ([0-9a-f]+ [0-9-]+|unknown \\(not built from a git checkout\\)).*\\(.*build, deal\\.II [0-9.]+\\)")
# The solver's shared libraries in the order of cmake/load_order.py: the
# solver has the order of its response file, and every symbol that a library
# defines as global binds to the library it binds to in the default order.
if(LOAD_ORDER_PYTHON)
  add_test(NAME build/load_order
    COMMAND ${LOAD_ORDER_PYTHON} ${CMAKE_SOURCE_DIR}/cmake/load_order.py check
            $<TARGET_FILE:load-order-probe> $<TARGET_FILE:contact-stefan-solver> ${LOAD_ORDER})
endif()
add_test(NAME cli/provenance
  COMMAND ${T}/check_provenance.sh ${BIN} ${T}/scenes/column_heat_then_cool.prm)
# Serial runs side by side: one writing checkpoints while another starts and
# ends (each daemon-less singleton has its own Open MPI session directory,
# app/mpi_start.h).
add_test(NAME cli/concurrent-serial-runs
  COMMAND ${T}/check_concurrent_serial.sh ${BIN} ${P}/neumann_A.prm)
add_test(NAME cli/parameter_reference_is_current
  COMMAND sh -c "${BIN} --print-parameters | diff -u ${CMAKE_SOURCE_DIR}/doc/parameters.prm -")
foreach(prm ${P}/neumann_A.prm ${P}/neumann_C.prm ${P}/neumann_two_transitions.prm)
  get_filename_component(name ${prm} NAME_WE)
  add_test(NAME cli/check_${name} COMMAND ${BIN} --check ${prm})
endforeach()

# --- the documentation's numbers (issue 32): every number of README.md and doc/
# that a cheap run re-checks (errors, counts, iterations: benchmarks/claims.json)
# must still be in its document and agree with what the code prints now. The
# test counts are taken from this build directory (ctest -N on a copy).
# The house rules of doc/architecture.md: includes point down the layers, one
# instantiation per class, at most 1000 lines per file and 150 per function, no
# citation of a file outside the repository.
add_test(NAME docs/house
  COMMAND /usr/bin/python3 ${T}/check_house.py ${CMAKE_SOURCE_DIR})
add_test(NAME docs/claims
  COMMAND /usr/bin/python3 ${CMAKE_SOURCE_DIR}/benchmarks/check_claims.py --binary ${BIN}
          --build-dir ${CMAKE_BINARY_DIR} --jobs 2)
set_tests_properties(docs/claims PROPERTIES PROCESSORS 2)
