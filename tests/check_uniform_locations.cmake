# ctest's `uniform_locations_named` test: every explicit uniform location in shaders/ is a name
# from an interface table (fx/src/projector/gl_interface.hpp, terrain/src/render/terrain_interface.hpp,
# samples/common/sample_interface.hpp), never a bare number: a number written twice, in the
# shader and in C++, can drift apart with nothing to say so. Vertex inputs and fragment outputs
# (`in`/`out`) may be numbered.
# SOURCE: the project's source folder. CONTROL (optional): a file that must fail the check.
if(CONTROL)
  set(files "${CONTROL}")
else()
  file(GLOB files "${SOURCE}/shaders/*.vert" "${SOURCE}/shaders/*.frag" "${SOURCE}/shaders/*.comp"
                  "${SOURCE}/shaders/*.glsl")
endif()
set(bare "")
foreach(file IN LISTS files)
  file(STRINGS "${file}" lines REGEX "location *= *[0-9]+ *\\) *uniform")
  foreach(line IN LISTS lines)
    get_filename_component(name "${file}" NAME)
    string(STRIP "${line}" line)
    string(APPEND bare "\n  ${name}: ${line}")
  endforeach()
endforeach()
if(bare)
  message(FATAL_ERROR "uniform locations written as bare numbers (name them in the interface table "
                      "the shader's C++ side uses):${bare}")
endif()
list(LENGTH files count)
message(STATUS "${count} shader files, every uniform location named")
