# ctest's `gl_call_clock_covers` test: `cellfx bench effects --only-cpu` splits a frame's CPU into
# cellfx's and the GL driver's by wrapping GL entry points (samples/common/gl_call_clock.cpp). A
# GL function that fx/ or terrain/ calls and the clock does not wrap would count as cellfx's own
# work; this lists any such function.
# SOURCE: the project's source folder.
cmake_policy(SET CMP0057 NEW) # if(IN_LIST)
file(READ "${SOURCE}/samples/common/gl_call_clock.cpp" clock)
string(REGEX MATCHALL "CELLFX_HOOK\\(gl[A-Za-z0-9_]+" hooked "${clock}")
string(REPLACE "CELLFX_HOOK(" "" hooked "${hooked}")
file(GLOB_RECURSE sources "${SOURCE}/fx/*.cpp" "${SOURCE}/fx/*.hpp" "${SOURCE}/terrain/*.cpp" "${SOURCE}/terrain/*.hpp")
set(missing "")
set(called "")
foreach(source IN LISTS sources)
  file(READ "${source}" text)
  string(REGEX MATCHALL "[^A-Za-z0-9_]gl[A-Z][A-Za-z0-9_]+[ ]*\\(" calls "${text}")
  foreach(call IN LISTS calls)
    string(REGEX REPLACE "^.(gl[A-Za-z0-9_]+).*" "\\1" name "${call}")
    list(APPEND called "${name}")
    if(NOT name IN_LIST hooked)
      file(RELATIVE_PATH where "${SOURCE}" "${source}")
      list(APPEND missing "${name} (${where})")
    endif()
  endforeach()
endforeach()
list(REMOVE_DUPLICATES missing)
list(REMOVE_DUPLICATES called)
if(missing)
  string(REPLACE ";" "\n  " listed "${missing}")
  message(FATAL_ERROR "GL functions cellfx calls that GlCallClock does not wrap (add each to "
                      "GlCallClock::install() in samples/common/gl_call_clock.cpp, as Driver, Upload or "
                      "State):\n  ${listed}")
endif()
list(LENGTH called count)
message(STATUS "all ${count} GL functions fx/ and terrain/ call are wrapped by GlCallClock")
