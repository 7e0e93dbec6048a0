# ctest script: the project configures and generates with OPTION off and every other part on (its default), and
# says which parts it leaves out for want of it (CMakeLists.txt, fcl_rs_needs). Configure only: building each
# combination would cost CI too much; core_alone and the main build build the two ends.
foreach(var BUILD_DIR SOURCE_DIR OPTION GENERATOR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "configure_without.cmake needs -D${var}=...")
  endif()
endforeach()
set(work "${BUILD_DIR}/configure_without/${OPTION}")
file(REMOVE_RECURSE "${work}")
execute_process(COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${work}" -G "${GENERATOR}" -D${OPTION}=OFF
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "-D${OPTION}=OFF does not configure:\n${out}")
endif()
string(REGEX MATCHALL "fcl_rs: [^\n]* not built: needs [^\n]*" left_out "${out}")
string(REPLACE ";" "\n  " left_out "${left_out}")
message(STATUS "-D${OPTION}=OFF configures; left out:\n  ${left_out}")
file(REMOVE_RECURSE "${work}")
