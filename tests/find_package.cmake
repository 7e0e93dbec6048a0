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

# pkg-config: the installed fcl_rs.pc compiles and links the same consumer.
find_program(PKG_CONFIG pkg-config REQUIRED)
set(ENV{PKG_CONFIG_PATH} "${work}/prefix/lib/pkgconfig:${work}/prefix/lib/x86_64-linux-gnu/pkgconfig")
execute_process(COMMAND ${PKG_CONFIG} --cflags --libs fcl_rs RESULT_VARIABLE rc OUTPUT_VARIABLE flags
                ERROR_VARIABLE err OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "pkg-config --cflags --libs fcl_rs failed: ${err}")
endif()
separate_arguments(flags UNIX_COMMAND "${flags}")
find_program(CXX NAMES c++ g++ REQUIRED)
run(${CXX} -O1 "${SOURCE_DIR}/tests/consumer/main.cpp" -o "${work}/pkg_config_consumer" ${flags})
run("${work}/pkg_config_consumer")
