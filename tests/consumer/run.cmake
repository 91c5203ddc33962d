# Builds and runs the consumer game (tests/consumer) one way, for ctest:
#   cmake -DMODE=<mode> -DCELLFX_SOURCE=<src> -DWORK=<dir> [-DBUILD_TYPE=..] [-DLAUNCHER=ccache]
#         [-DCXX=..] [-DCC=..] [-DCELLFX_BUILD=<cellfx build dir>] [-DLIBDIR=lib] -P run.cmake
# MODE:
#   subdirectory    add_subdirectory with the game's defaults (no build type, no cellfx option):
#                   the consumer's CMakeLists checks what cellfx left in the game's build, the
#                   game's ctest lists only the game's own test; build, run
#   fetchcontent    the same through FetchContent from the source folder
#   install         cmake --install CELLFX_BUILD into WORK/prefix (the fixture of the next three)
#   package         find_package(cellfx) from WORK/../install/prefix, build, run
#   no_exceptions   the same with the game built -fno-exceptions -fno-rtti (game_noexcept.cpp)
#   pkg_config      no CMake: c++ game.cpp $(pkg-config --cflags --libs cellfx), run
cmake_minimum_required(VERSION 3.21)

function(run what)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "consumer ${MODE}: ${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(run_output "${out}" PARENT_SCOPE)
endfunction()

set(consumer "${CMAKE_CURRENT_LIST_DIR}")
set(prefix "${WORK}/../install/prefix")
if(NOT LIBDIR)
  set(LIBDIR lib)
endif()
file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(common -G Ninja "-DCELLFX_SOURCE=${CELLFX_SOURCE}")
if(CXX)
  list(APPEND common "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_C_COMPILER=${CC}")
endif()
if(LAUNCHER)
  list(APPEND common "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}" "-DCMAKE_C_COMPILER_LAUNCHER=${LAUNCHER}")
endif()

if(MODE STREQUAL "install")
  run("cmake --install" "${CMAKE_COMMAND}" --install "${CELLFX_BUILD}" --prefix "${WORK}/prefix")
  foreach(f include/cellfx/cellfx/cellfx.hpp include/cellfx/fx/effect.hpp ${LIBDIR}/cmake/cellfx/cellfxConfig.cmake
            ${LIBDIR}/cmake/cellfx/cellfxConfigVersion.cmake ${LIBDIR}/pkgconfig/cellfx.pc)
    if(NOT EXISTS "${WORK}/prefix/${f}")
      message(FATAL_ERROR "consumer install: ${f} was not installed")
    endif()
  endforeach()
  # Test support and cellfx's own stages stay out of what a game gets (testing/, fx/src).
  foreach(f include/cellfx/fx/headless_context.hpp include/cellfx/fx/segment_integral.hpp
            include/cellfx/harness include/cellfx/verify ${LIBDIR}/libcellfx_harness.a ${LIBDIR}/libcellfx_verify.a)
    if(EXISTS "${WORK}/prefix/${f}")
      message(FATAL_ERROR "consumer install: ${f} was installed (test support is not part of the package)")
    endif()
  endforeach()
  return()
endif()

if(MODE STREQUAL "pkg_config")
  set(ENV{PKG_CONFIG_PATH} "${prefix}/${LIBDIR}/pkgconfig")
  run("pkg-config" pkg-config --cflags --libs cellfx)
  string(STRIP "${run_output}" flags)
  separate_arguments(flags UNIX_COMMAND "${flags}")
  if(NOT CXX)
    set(CXX c++)
  endif()
  run("compiling with pkg-config's flags" ${CXX} -std=c++17 -O1 -Wall -Wextra -Wconversion -Wsign-conversion -Werror
      "${consumer}/game.cpp" -o game ${flags})
  run("the game" "${WORK}/game")
  message("${run_output}")
  return()
endif()

set(build "${WORK}/build")
if(MODE STREQUAL "subdirectory" OR MODE STREQUAL "fetchcontent")
  # The game's defaults: no build type (no optimisation: also the quickest build of cellfx's
  # sources, which are compiled again here).
  set(options "-DCELLFX_CONSUME=${MODE}")
elseif(MODE STREQUAL "package" OR MODE STREQUAL "no_exceptions")
  set(options "-DCMAKE_BUILD_TYPE=${BUILD_TYPE}" -DCELLFX_CONSUME=package "-DCMAKE_PREFIX_PATH=${prefix}")
  if(MODE STREQUAL "no_exceptions")
    list(APPEND options -DCONSUMER_NO_EXCEPTIONS=ON)
  endif()
else()
  message(FATAL_ERROR "run.cmake: unknown MODE '${MODE}'")
endif()
run("configure" "${CMAKE_COMMAND}" -S "${consumer}" -B "${build}" ${common} ${options})
run("ctest -N" "${CMAKE_CTEST_COMMAND}" -N --test-dir "${build}")
if(NOT run_output MATCHES "Total Tests: 1\n")
  message(FATAL_ERROR "consumer ${MODE}: the game's ctest lists more than its own test:\n${run_output}")
endif()
run("build" "${CMAKE_COMMAND}" --build "${build}")
run("the game" "${build}/game")
message("${run_output}")
