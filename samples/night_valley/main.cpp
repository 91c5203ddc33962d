// cellfx sample: Valley fog at night: a campfire in the fog, smoke drifting over it, a search light sweeping through (content/scenes/fog_valley_night.json).
// `night_valley --help` lists the options; the keys are printed on start. docs/samples.md.
#include "sample.hpp"

int main(int argc, char** argv) { return cellfx_samples::run_sample("night_valley", argc, argv); }
