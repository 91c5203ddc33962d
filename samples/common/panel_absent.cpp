// The samples built without Dear ImGui (libimgui-dev not found, or CELLFX_SAMPLES_IMGUI=OFF):
// no panel (panel.hpp).
#include <cstdio>

#include "panel.hpp"

namespace cellfx_samples {

std::unique_ptr<Panel> make_panel(void*) {
    static bool told = false;
    if (!told)
        std::fprintf(stderr, "cellfx samples: built without Dear ImGui (libimgui-dev), so there is no tuning panel; "
                             "the keys, --set and --save still work\n");
    told = true;
    return nullptr;
}

bool panel_built() { return false; }

} // namespace cellfx_samples
