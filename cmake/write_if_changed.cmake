# write_if_changed(FILE TEXT): writes TEXT to FILE unless FILE already holds it,
# so that an unchanged generated source recompiles and relinks nothing. Used by
# the scripts that generate sources at build time (build_info.cmake,
# parameters_text.cmake).
function(write_if_changed file text)
  set(old "")
  if(EXISTS "${file}")
    file(READ "${file}" old)
  endif()
  if(NOT "${old}" STREQUAL "${text}")
    file(WRITE "${file}" "${text}")
  endif()
endfunction()
