// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2 (intersecting grids). The scan-line
// reference of a scene's frame (terrain/scene_reference.hpp).
#include "terrain/scene_reference.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "fx/effect.hpp" // camera_in_frame
#include "fx/scanline_renderer.hpp"

namespace cellfx::terrain {

namespace {

// Appends the effect's mesh, moved into the world relative to `origin` (the eye), to `out`
// (its blocks stay blocks; one scalar field, the effect's). Returns the number of blocks added.
// The pose's translation has `origin` taken off before it is applied: an effect 2 units across
// at 1e17 from the world's origin keeps its shape, where world coordinates in double would
// collapse it (as the GPU paths draw it, in its own frame).
std::size_t append_world_mesh(const fx::Effect& effect, const glm::dvec3& origin, fx::CellMesh& out) {
    const fx::CellMesh& mesh = effect.mesh();
    glm::dmat4 m = effect.transform();
    m[3] -= glm::dvec4(origin, 0.0);
    const std::uint32_t base = std::uint32_t(out.points.size());
    for (const glm::dvec3& p : mesh.points) out.points.push_back(glm::dvec3(m * glm::dvec4(p, 1.0)));
    if (out.scalars.empty()) out.scalars.push_back({"scalar", {}});
    const fx::ScalarField* field = mesh.find_scalar(effect.scalar_name());
    std::vector<float>& values = out.scalars[0].values;
    for (std::size_t i = 0; i < mesh.point_count(); ++i) values.push_back(field ? field->values[i] : 0.0f);
    std::uint32_t v[fx::kMaxCellVertices];
    for (const fx::Block& b : mesh.blocks) {
        out.begin_block(b.name);
        for (std::uint32_t c = b.first_cell; c < b.first_cell + b.cell_count; ++c) {
            const int n = fx::cell_vertex_count(mesh.cell_types[c]);
            for (int k = 0; k < n; ++k) v[k] = mesh.cell_vertices(c)[k] + base;
            out.add_cell(mesh.cell_types[c], v);
        }
    }
    return mesh.blocks.size();
}

} // namespace

SceneReferenceInput capture_scene_reference(const SceneRenderer& renderer, const fx::Camera& camera) {
    // Everything relative to the eye: the camera there, the volumes and lights moved alike.
    const glm::dvec3 origin = camera.eye;
    SceneReferenceInput input;
    input.camera = fx::camera_in_frame(camera, glm::translate(glm::dmat4(1.0), origin));
    for (const SceneRenderer::DrawnVolume& v : renderer.drawn_volumes()) {
        if (v.in_medium) {
            const std::size_t blocks = append_world_mesh(*v.effect, origin, input.medium_mesh);
            fx::MediumVolume medium = v.medium;
            medium.light.origin -= origin;
            input.media.insert(input.media.end(), blocks, medium);
            continue;
        }
        // pcp (emission) and mip (maximum) effects: their own model, added as the renderer adds them.
        SceneReferenceInput::Layer layer;
        append_world_mesh(*v.effect, origin, layer.mesh);
        layer.model = v.path == fx::RenderPath::Mip ? fx::OpticalModel::Maximum : fx::OpticalModel::Emission;
        layer.tf = v.medium.tf;
        input.layers.push_back(std::move(layer));
    }
    return input;
}

fx::Image render_scene_reference(const SceneReferenceInput& input, int width, int height, unsigned threads,
                                 fx::ScanlineProgress* progress) {
    fx::Image image(width, height, glm::vec4(0.0f));
    fx::ScanlineOptions options;
    options.threads = threads;
    options.progress = progress;
    for (const SceneReferenceInput::Layer& l : input.layers) {
        fx::ScanlineOptions own = options;
        own.model = l.model;
        const fx::Image layer = fx::ScanlineRenderer(l.mesh).render(input.camera, width, height, l.mesh.scalars[0], l.tf, own);
        for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] += glm::vec4(glm::vec3(layer.pixels[i]), 0.0f);
    }
    if (input.medium_mesh.cell_count() > 0) {
        const fx::Medium medium(input.media);
        options.medium = &medium;
        const fx::Image volumes = fx::ScanlineRenderer(input.medium_mesh)
                                      .render(input.camera, width, height, input.medium_mesh.scalars[0], fx::TransferFunction(), options);
        // The additive effects lie over the medium: medium first, then their light.
        for (std::size_t i = 0; i < image.pixels.size(); ++i) image.pixels[i] += volumes.pixels[i];
    }
    return image;
}

fx::Image render_scene_reference(const SceneRenderer& renderer, const fx::Camera& camera, int width, int height,
                                 unsigned threads) {
    return render_scene_reference(capture_scene_reference(renderer, camera), width, height, threads);
}

} // namespace cellfx::terrain
