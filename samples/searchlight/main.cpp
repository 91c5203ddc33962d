// cellfx sample: Search lights at night; the patrol light rides a drone circling the hill (content/scenes/searchlight.json).
// `searchlight --help` lists the options; the keys are printed on start. docs/samples.md.
#include "sample.hpp"

int main(int argc, char** argv) { return cellfx_samples::run_sample("searchlight", argc, argv); }
