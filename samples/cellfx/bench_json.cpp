#include "bench_json.hpp"

#include <cstdio>
#include <fstream>

#include "fx/error.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

void write_scenes_json(const std::string& path, const std::vector<BenchJsonRow>& rows) {
    nlohmann::ordered_json document;
    document["scenes"] = nlohmann::ordered_json::array();
    for (const BenchJsonRow& row : rows) document["scenes"].push_back(row);
    const std::string temporary = path + ".tmp";
    {
        std::ofstream out(temporary);
        out << document.dump(2) << "\n";
        if (!out) throw fx::Error("bench: cannot write " + temporary);
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
        std::remove(temporary.c_str());
        throw fx::Error("bench: cannot rename " + temporary + " to " + path);
    }
}

} // namespace cellfx_cli
