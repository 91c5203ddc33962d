// The six samples, by name (sample.hpp: sample_catalog). Each is defined in samples/<name>/.
#include "fx/error.hpp"
#include "sample.hpp"

namespace cellfx_samples {

SampleInfo fog_valley_sample();
SampleInfo campfire_sample();
SampleInfo searchlight_sample();
SampleInfo aurora_sample();
SampleInfo fem_viewer_sample();
SampleInfo night_valley_sample();

const std::vector<SampleInfo>& sample_catalog() {
    static const std::vector<SampleInfo> catalog = {fog_valley_sample(), campfire_sample(), searchlight_sample(),
                                                    aurora_sample(), fem_viewer_sample(), night_valley_sample()};
    return catalog;
}

} // namespace cellfx_samples
