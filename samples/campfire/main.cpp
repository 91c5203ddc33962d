// cellfx sample: A campfire of animated 4-D noise on rough ground, the camera circling it (content/scenes/campfire.json).
// `campfire --help` lists the options; the keys are printed on start. docs/samples.md.
#include "sample.hpp"

int main(int argc, char** argv) { return cellfx_samples::run_sample("campfire", argc, argv); }
