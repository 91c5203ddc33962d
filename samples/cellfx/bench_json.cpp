#include "bench_json.hpp"

#include "io/output_file.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

void write_scenes_json(const std::string& path, const std::vector<BenchJsonRow>& rows) {
    nlohmann::ordered_json document;
    document["scenes"] = nlohmann::ordered_json::array();
    for (const BenchJsonRow& row : rows) document["scenes"].push_back(row);
    fx::io::write_output_file(path, document.dump(2) + "\n");
}

} // namespace cellfx_cli
