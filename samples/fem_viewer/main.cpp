// cellfx sample: A finite-element mesh (any file the readers take) with a transfer function and a choice of scalar field.
// `fem_viewer --help` lists the options; the keys are printed on start. docs/samples.md.
#include "sample.hpp"

int main(int argc, char** argv) { return cellfx_samples::run_sample("fem_viewer", argc, argv); }
