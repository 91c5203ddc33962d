// cellfx sample: Valley fog on Mount St. Helens over continuous-LOD terrain (content/scenes/fog_valley.json).
// `fog_valley --help` lists the options; the keys are printed on start. docs/samples.md.
#include "sample.hpp"

int main(int argc, char** argv) { return cellfx_samples::run_sample("fog_valley", argc, argv); }
