# ctest's `cli_suites` test: every tag in TAGS (comma-separated) has test cases in the test
# program TESTS.
# The suites that run the cellfx command and the samples as programs (test_cli.cpp,
# test_bench_*.cpp, test_hostile_input.cpp) are compiled in only when the samples are built;
# this fails, naming the tag, where one is missing, rather than letting the suite shrink unseen.
string(REPLACE "," ";" tags "${TAGS}")
foreach(tag IN LISTS tags)
  execute_process(COMMAND "${TESTS}" --list-test-names-only "${tag}" OUTPUT_VARIABLE names RESULT_VARIABLE rc)
  string(STRIP "${names}" names)
  if(names STREQUAL "")
    message(FATAL_ERROR "no ${tag} test cases in ${TESTS}: the suites that run the cellfx command need the samples "
                        "(configure with -DCELLFX_BUILD_SAMPLES=ON)")
  endif()
  string(REGEX MATCHALL "\n" lines "${names}")
  list(LENGTH lines count)
  math(EXPR count "${count} + 1")
  message(STATUS "${tag}: ${count} test cases")
endforeach()
