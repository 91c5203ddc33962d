# ctest's `include_roots` test: one root per include prefix. fx's own sources see both fx/src
# and fx/internal, so "gl/x.hpp" must name one folder: a prefix (gl/, io/, medium/, ...) that
# holds headers under fx/internal holds none under fx/src, and the other way round.
# SOURCE: the project's source folder.
file(GLOB internal_prefixes RELATIVE "${SOURCE}/fx/internal" "${SOURCE}/fx/internal/*")
set(clashes "")
foreach(prefix IN LISTS internal_prefixes)
  if(IS_DIRECTORY "${SOURCE}/fx/internal/${prefix}")
    file(GLOB_RECURSE private_headers RELATIVE "${SOURCE}" "${SOURCE}/fx/src/${prefix}/*.hpp")
    if(private_headers)
      string(REPLACE ";" ", " listed "${private_headers}")
      string(APPEND clashes "\n  ${prefix}/: fx/internal/${prefix} and ${listed}")
    endif()
  endif()
endforeach()
if(clashes)
  message(FATAL_ERROR "include prefixes with two roots (move the header into fx/internal, or give the "
                      "private folder a prefix of its own):${clashes}")
endif()
list(LENGTH internal_prefixes count)
message(STATUS "${count} include prefixes under fx/internal, none also under fx/src")
