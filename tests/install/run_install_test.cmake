# The README's three ways into the library, each in a fresh folder, each building and running the
# consumer program (consumer/main.cpp: glTF round trip, analysis, one resize):
#   1. the installed package: the README's configure (tests, examples and bench off) must configure; the
#      package is then installed from the tree this test belongs to (BUILD_DIR, already built: the same
#      library and tool targets, built with the same flags, so building them a second time would check
#      nothing more), and a consumer project uses it with find_package(restitch), linking
#      restitch::compiled (which carries restitch::restitch's interface);
#   2. add_subdirectory of the source tree, header-only (restitch::compiled is then not built): the
#      program's whole pipeline compiled from the headers;
#   3. plain compiler flags, the README's command line, in the compiled mode: -DRESTITCH_COMPILED and the
#      installed library of way 1 (the same program compiled header-only is way 2's).
# With -DTOOLCHAIN=<Emscripten's toolchain file>, only way 2, configured with that toolchain as
# `emcmake cmake` does, its program run by plain node.
# Fails naming the step that failed.
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "failed: ${ARGV}\n${out}\n${err}")
  endif()
  set(LAST_OUTPUT "${out}" PARENT_SCOPE)
endfunction()
function(expect_ok program)
  run(${program} "${WORK_DIR}/out.glb")
  if(NOT LAST_OUTPUT MATCHES "consumer ok")
    message(FATAL_ERROR "${program} did not report success: ${LAST_OUTPUT}")
  endif()
  message(STATUS "${program}: ${LAST_OUTPUT}")
endfunction()
set(jobs -j 2)

if(TOOLCHAIN)
  find_program(NODE node REQUIRED)
  run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/install/subdirectory" -B "${WORK_DIR}/subdirectory" -G "${GENERATOR}"
      -DCMAKE_BUILD_TYPE=Release "-DCMAKE_TOOLCHAIN_FILE=${TOOLCHAIN}" "-DRESTITCH_SOURCE_DIR=${SOURCE_DIR}")
  run(${CMAKE_COMMAND} --build "${WORK_DIR}/subdirectory" ${jobs})
  expect_ok("${NODE};${WORK_DIR}/subdirectory/consumer.js")
  return()
endif()

# 1. Installed package.
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}" -B "${WORK_DIR}/lib" -G "${GENERATOR}" -DCMAKE_BUILD_TYPE=Release
    -DRESTITCH_BUILD_TESTS=OFF -DRESTITCH_BUILD_EXAMPLES=OFF -DRESTITCH_BUILD_BENCH=OFF)
if(NOT EXISTS "${WORK_DIR}/lib/restitchConfig.cmake" OR EXISTS "${WORK_DIR}/lib/tests")
  message(FATAL_ERROR "the README's configure did not write the package config, or configured the tests")
endif()
run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix")
foreach(f include/restitch/restitch.hpp include/restitch/instantiate.hpp bin/restitch)
  if(NOT EXISTS "${WORK_DIR}/prefix/${f}")
    message(FATAL_ERROR "cmake --install did not install ${f}")
  endif()
endforeach()
run("${WORK_DIR}/prefix/bin/restitch" sample pin_header -o "${WORK_DIR}/tool.glb")
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/install/consumer" -B "${WORK_DIR}/consumer" -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/consumer" ${jobs})
expect_ok("${WORK_DIR}/consumer/consumer_compiled")

# 2. From the source tree, header-only.
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/tests/install/subdirectory" -B "${WORK_DIR}/subdirectory" -G "${GENERATOR}"
    -DCMAKE_BUILD_TYPE=Release "-DRESTITCH_SOURCE_DIR=${SOURCE_DIR}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/subdirectory" ${jobs})
if(EXISTS "${WORK_DIR}/subdirectory/restitch/librestitch_compiled.a")
  message(FATAL_ERROR "add_subdirectory built restitch::compiled, which the consumer does not link")
endif()
expect_ok("${WORK_DIR}/subdirectory/consumer")

# 3. Plain compiler flags (the README's command line), in the compiled mode.
file(GLOB compiled_library "${WORK_DIR}/prefix/lib*/librestitch_compiled.a")
if(NOT compiled_library)
  message(FATAL_ERROR "cmake --install did not install librestitch_compiled.a")
endif()
run(${CXX} -std=c++17 -O2 -DRESTITCH_COMPILED -I "${SOURCE_DIR}/include" -I /usr/include/eigen3
    "${SOURCE_DIR}/tests/install/consumer/main.cpp" ${compiled_library} -pthread -o "${WORK_DIR}/plain")
expect_ok("${WORK_DIR}/plain")
