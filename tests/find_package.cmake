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
run("${work}/from_build/consumer" "${work}/from_build/tetra.obj")

run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${work}/prefix")
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/consumer" -B "${work}/from_install" -DCMAKE_BUILD_TYPE=Release
    "-DCMAKE_PREFIX_PATH=${work}/prefix")
run(${CMAKE_COMMAND} --build "${work}/from_install")
run("${work}/from_install/consumer" "${work}/from_install/tetra.obj")

# pkg-config: README's command line (app.cpp: the consumer) compiles and links the consumer against the installed
# static library, whose link needs assimp (the consumer loads a mesh file).
file(READ "${SOURCE_DIR}/README.md" readme)
if(NOT readme MATCHES "`(c\\+\\+ [^`]*\\$\\(pkg-config --cflags --libs fcl_rs\\))`")
  message(FATAL_ERROR "README.md shows no `c++ ... $(pkg-config --cflags --libs fcl_rs)` line")
endif()
string(REPLACE "app.cpp" "'${SOURCE_DIR}/tests/consumer/main.cpp' -o '${work}/pkg_config_consumer'" command
       "${CMAKE_MATCH_1}")
find_program(PKG_CONFIG pkg-config REQUIRED)
file(GLOB pc_dirs "${work}/prefix/lib*/pkgconfig" "${work}/prefix/lib*/*/pkgconfig")
string(REPLACE ";" ":" pc_path "${pc_dirs}")
set(ENV{PKG_CONFIG_PATH} "${pc_path}")
message(STATUS "README's pkg-config line: ${command}")
run(sh -c "${command}")
run("${work}/pkg_config_consumer" "${work}/pkg_config_tetra.obj")
