// cellfx sample: Aurora curtains over the mountains, drawn with MIP (content/scenes/aurora.json).
// `aurora --help` lists the options; the keys are printed on start. docs/samples.md.
#include "sample.hpp"

int main(int argc, char** argv) { return cellfx_samples::run_sample("aurora", argc, argv); }
