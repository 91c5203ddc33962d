# The samples where Dear ImGui is not installed, for ctest:
#   1. cellfx configured with -DCELLFX_SAMPLES_IMGUI=OFF (as if libimgui-dev were absent) says
#      so and leaves the panel and ImGui out of the samples' build (its build files are read;
#      nothing is compiled);
#   2. PROGRAM — this build's campfire with the panel's absence linked in its place
#      (samples/CMakeLists.txt: cellfx_campfire_without_panel) — runs, asked for the panel: it
#      draws its frames, says the panel was compiled out, and carries nothing of ImGui.
#   cmake -DCELLFX_SOURCE=<src> -DWORK=<dir> -DPROGRAM=<campfire_without_panel> [-DCXX=..] [-DCC=..]
#         -P samples_without_imgui.cmake
cmake_minimum_required(VERSION 3.21)

function(run what)
  execute_process(COMMAND ${ARGN} WORKING_DIRECTORY "${WORK}" RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "samples without ImGui: ${what} failed (${rc}):\n${out}\n${err}")
  endif()
  set(run_output "${out}${err}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK}")
file(MAKE_DIRECTORY "${WORK}")
set(args -S "${CELLFX_SOURCE}" -B "${WORK}/build" -G Ninja -DCELLFX_BUILD_TESTS=OFF -DCELLFX_INSTALL=OFF
    -DCELLFX_SAMPLES_IMGUI=OFF)
if(CXX)
  list(APPEND args "-DCMAKE_CXX_COMPILER=${CXX}" "-DCMAKE_C_COMPILER=${CC}")
endif()
run("configuring with CELLFX_SAMPLES_IMGUI=OFF" "${CMAKE_COMMAND}" ${args})
if(NOT run_output MATCHES "CELLFX_SAMPLES_IMGUI=OFF: the samples are built without their tuning panel")
  message(FATAL_ERROR "samples without ImGui: the configure did not say the panel is left out:\n${run_output}")
endif()
file(READ "${WORK}/build/build.ninja" ninja)
if(NOT ninja MATCHES "common/panel_absent\\.cpp" OR ninja MATCHES "common/panel\\.cpp" OR ninja MATCHES "libimgui|-limgui|include/imgui")
  message(FATAL_ERROR "samples without ImGui: the build still names the panel or ImGui (${WORK}/build/build.ninja)")
endif()

run("the campfire without the panel" "${PROGRAM}" --headless --frames 2 --width 64 --height 48 --panel --out "${WORK}/frames")
if(NOT run_output MATCHES "built without Dear ImGui")
  message(FATAL_ERROR "samples without ImGui: asked for the panel, the campfire did not say it has none:\n${run_output}")
endif()
if(NOT EXISTS "${WORK}/frames/frame_0001.png")
  message(FATAL_ERROR "samples without ImGui: the campfire wrote no frames:\n${run_output}")
endif()
file(STRINGS "${PROGRAM}" imgui_strings REGEX "imgui\\.ini|ImGui_Impl|ImGuiContext")
if(imgui_strings)
  message(FATAL_ERROR "samples without ImGui: ${PROGRAM} carries ImGui's code")
endif()
message("configured without ImGui, and the campfire ran without it:\n${run_output}")
