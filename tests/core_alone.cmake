# ctest script: the project configured with every optional part off asks for none of their packages; the core it
# would build is the same library this build tree already built and find_package.cmake links (not built twice).
foreach(var BUILD_DIR SOURCE_DIR)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "core_alone.cmake needs -D${var}=...")
  endif()
endforeach()
set(work "${BUILD_DIR}/core_alone_test")
file(REMOVE_RECURSE "${work}")
execute_process(
  COMMAND ${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${work}" -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF
          -DFCL_RS_BUILD_HULL=OFF -DFCL_RS_BUILD_ROBOT=OFF -DFCL_RS_BUILD_TOOLS=OFF -DFCL_RS_BUILD_EXAMPLES=OFF
          -DFCL_RS_BUILD_BENCHMARKS=OFF -DFCL_RS_BUILD_EXPERIMENTS=OFF -DFCL_RS_BUILD_BATCH=OFF
  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the core alone does not configure:\n${out}")
endif()
file(STRINGS "${work}/CMakeCache.txt" cache)
foreach(line IN LISTS cache)
  if(line MATCHES "^(urdfdom|tinyxml2|Qhull|nlohmann_json|GTest|benchmark|CLI11|TBB|pybind11|CGAL|Python3)_DIR:")
    message(FATAL_ERROR "the core alone looked for an optional package: ${line}")
  endif()
endforeach()
file(STRINGS "${work}/Makefile" targets REGEX "^(fcl_rs_robot|fcl_rs_hull|test_[a-z_]+|fcl_rs_[a-z_]+):")
if(NOT targets STREQUAL "")
  message(FATAL_ERROR "the core alone has optional targets: ${targets}")
endif()
file(STRINGS "${work}/Makefile" core REGEX "^fcl_rs:")
if(core STREQUAL "")
  message(FATAL_ERROR "the core alone has no fcl_rs target")
endif()
message(STATUS "core alone: configured with FCL, libccd, Eigen and assimp only")
