# cellfx_embed_shaders(OUTPUT <var> FUNCTION <name> BASE_DIR <dir> FILES <file>...)
#
# Turns an explicit list of GLSL files into one generated .cpp that defines
#   const fx::gl::EmbeddedShader* fx::gl::<FUNCTION>(std::size_t& count);
# returning {name, path, text} per file: name relative to BASE_DIR ("pcp.frag", what the shader
# library and #include use), path relative to the source tree ("shaders/pcp.frag", what error
# messages print) and the text as a raw string literal. The generated file includes
# "gl/shader_library.hpp" (fx's private include directory) for the EmbeddedShader type.
#
# The .cpp is written under CMAKE_CURRENT_BINARY_DIR and its path is stored in <var>; append
# it to the target's sources. It is regenerated at build time whenever a listed file (or the
# generator script) changes; changing the list itself re-runs CMake, which changes the command.
set(_cellfx_embed_script "${CMAKE_CURRENT_LIST_DIR}/EmbedShadersScript.cmake")

function(cellfx_embed_shaders)
  cmake_parse_arguments(ARG "" "OUTPUT;FUNCTION;BASE_DIR" "FILES" ${ARGN})
  if(NOT ARG_OUTPUT OR NOT ARG_FUNCTION OR NOT ARG_BASE_DIR OR NOT ARG_FILES)
    message(FATAL_ERROR "cellfx_embed_shaders: OUTPUT, FUNCTION, BASE_DIR and FILES are required")
  endif()
  set(out "${CMAKE_CURRENT_BINARY_DIR}/${ARG_FUNCTION}.cpp")
  set(abs_files "")
  foreach(f IN LISTS ARG_FILES)
    get_filename_component(abs "${f}" ABSOLUTE BASE_DIR "${ARG_BASE_DIR}")
    if(NOT EXISTS "${abs}")
      message(FATAL_ERROR "cellfx_embed_shaders: ${abs} does not exist")
    endif()
    list(APPEND abs_files "${abs}")
  endforeach()
  # A ';' list would be split by the shell/ninja command line; '|' never occurs in our paths.
  string(REPLACE ";" "|" joined "${abs_files}")
  add_custom_command(
    OUTPUT "${out}"
    COMMAND ${CMAKE_COMMAND}
      "-DOUTPUT=${out}" "-DFUNCTION=${ARG_FUNCTION}" "-DBASE_DIR=${ARG_BASE_DIR}"
      "-DSOURCE_ROOT=${PROJECT_SOURCE_DIR}" "-DFILES=${joined}"
      -P "${_cellfx_embed_script}"
    DEPENDS ${abs_files} "${_cellfx_embed_script}"
    COMMENT "Embedding shaders into ${ARG_FUNCTION}.cpp"
    VERBATIM)
  set(${ARG_OUTPUT} "${out}" PARENT_SCOPE)
endfunction()
