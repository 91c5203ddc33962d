#include "render/terrain_shaders.hpp"

namespace cellfx::fx::gl {
// Generated from the shader list in terrain/CMakeLists.txt (build tree: terrain_embedded_shaders.cpp).
const EmbeddedShader* terrain_embedded_shaders(std::size_t& count);
} // namespace cellfx::fx::gl

namespace cellfx::terrain {

const fx::gl::ShaderLibrary& terrain_shaders() {
    static const fx::gl::ShaderLibrary library = [] {
        fx::gl::ShaderLibrary lib;
        std::size_t count = 0;
        const fx::gl::EmbeddedShader* shaders = fx::gl::terrain_embedded_shaders(count);
        for (std::size_t k = 0; k < count; ++k) lib.add(shaders[k].name, shaders[k].text, shaders[k].path);
        return lib;
    }();
    return library;
}

} // namespace cellfx::terrain
