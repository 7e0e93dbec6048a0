# ctest script: a consumer project finds fcl_rs in the build tree, then in an install tree.
foreach(var BUILD_DIR SOURCE_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "find_package.cmake needs -D${var}=...")
  endif()
endforeach()
set(work "${BUILD_DIR}/find_package_test")
file(REMOVE_RECURSE "${work}")

function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed (${rc}): ${ARGV}\n${out}")
  endif()
endfunction()

run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/consumer" -B "${work}/from_build" -DCMAKE_BUILD_TYPE=Release
    "-Dfcl_rs_DIR=${BUILD_DIR}")
run(${CMAKE_COMMAND} --build "${work}/from_build")
run("${work}/from_build/consumer")

run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${work}/prefix")
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/consumer" -B "${work}/from_install" -DCMAKE_BUILD_TYPE=Release
    "-DCMAKE_PREFIX_PATH=${work}/prefix")
run(${CMAKE_COMMAND} --build "${work}/from_install")
run("${work}/from_install/consumer")
