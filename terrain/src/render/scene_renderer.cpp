// Based on: Roettger & Ertl 2003, §5 — ground fog over a continuous-LOD terrain and the aurora,
// as prisms projected by the cell renderer; the terrain's depth stops the fog at the ground.
#include "terrain/scene_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>

#include "fx/error.hpp"
#include "gl/composite_pass.hpp"
#include "gl/gl_check.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"

namespace terrain {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// A normalized transfer function mapped once onto the layer's full scalar range, so that the
// colours do not shift as the LOD (and with it the range of the frame's scalars) changes.
fx::TransferFunction fixed_range(const fx::TransferFunction& tf, double lo, double hi) {
    return tf.normalized() ? tf.rescaled(lo, std::max(hi, lo + 1e-6 * std::max(1.0, std::abs(lo)))) : tf;
}

// One volumetric layer (fog or aurora): its LOD, its prisms, its cell renderer.
struct Layer {
    std::optional<ContinuousLod> lod; // the aurora's own; the fog rides on the terrain's LOD
    LayerPrismOptions prism_options;
    fx::TransferFunction tf;
    fx::RenderPath path;
    bool absorb = false;
    double pixel_error = 2.0;
    LodMesh mesh;
    fx::CellMesh prisms;
    std::optional<fx::CellRenderer> renderer; // made on the first frame with prisms
};

} // namespace

struct SceneRenderer::Impl {
    Scene scene;
    ContinuousLod terrain; // the ground, with the fog layer when there is fog
    LodMesh terrain_mesh;
    SurfaceRenderer surface;
    std::optional<Layer> fog, aurora;
    fx::CellMesh no_prisms;
    fx::gl::RenderTarget target;
    fx::gl::CompositePass composite;

    explicit Impl(const Scene& s)
        : scene(s),
          terrain(s.fog ? ContinuousLod(s.ground, s.fog->thickness, s.lod) : ContinuousLod(s.ground, s.lod)),
          surface(s.ground), composite(fx::gl::CompositePass::create()) {}

    void draw_layer(Layer& layer, const fx::Camera& camera, int width, int height, fx::CellRenderStats& stats,
                    double& upload_ms) {
        if (layer.prisms.cell_count() == 0) return;
        const auto t = Clock::now();
        if (!layer.renderer) layer.renderer.emplace(layer.prisms, layer.prism_options.scalar_name, layer.tf);
        else layer.renderer->set_mesh(layer.prisms, layer.prism_options.scalar_name);
        upload_ms += ms_since(t);
        fx::CellRenderOptions options;
        options.fog = layer.absorb && layer.path == fx::RenderPath::PcpExact;
        options.scene_depth = target.depth_texture();
        stats = layer.renderer->render(camera, fx::Viewport{0, 0, width, height}, layer.path, options);
    }

    // Draws the frame into `target` (resized to width × height).
    FrameStats draw(const fx::Camera& camera, int width, int height, bool finish) {
        const auto start = Clock::now();
        FrameStats stats;
        auto t = Clock::now();
        stats.terrain_lod = terrain.update(LodView::from_camera(camera, height, scene.pixel_error, scene.triangle_budget));
        if (aurora) stats.aurora_lod = aurora->lod->update(LodView::from_camera(camera, height, aurora->pixel_error));
        stats.lod_ms = ms_since(t);

        t = Clock::now();
        terrain.extract(terrain_mesh);
        if (fog) fog->prisms = build_layer_prisms(terrain_mesh, fog->prism_options, &stats.fog_prisms);
        if (aurora) {
            aurora->lod->extract(aurora->mesh);
            aurora->prisms = build_layer_prisms(aurora->mesh, aurora->prism_options, &stats.aurora_prisms);
        }
        stats.mesh_ms = ms_since(t);

        if (target.width() != width || target.height() != height)
            target = fx::gl::RenderTarget::create(width, height, fx::gl::ColorFormat::RGBA32F, true);
        t = Clock::now();
        double upload_ms = 0.0;
        {
            fx::gl::StateGuard guard;
            fx::gl::StateGuard::set_render_defaults();
            const glm::dvec3& bg = scene.background;
            target.clear(glm::vec4(float(bg.r), float(bg.g), float(bg.b), 1.0f), 1.0f);
            target.bind_for_drawing();
            stats.surface = surface.draw(terrain_mesh, camera, fx::Viewport{0, 0, width, height}, scene.surface);
            if (fog) draw_layer(*fog, camera, width, height, stats.fog, upload_ms);
            if (aurora) draw_layer(*aurora, camera, width, height, stats.aurora, upload_ms);
            if (finish) glFinish();
            FX_GL_CHECK("terrain scene frame");
        }
        stats.upload_ms = upload_ms;
        stats.draw_ms = ms_since(t) - upload_ms;
        stats.frame_ms = ms_since(start);
        return stats;
    }
};

SceneRenderer::SceneRenderer(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {
    Impl& m = *impl_;
    if (scene.fog) {
        const FogSpec& f = *scene.fog;
        Layer layer{std::nullopt, f.prisms, {}, f.path, f.absorb, scene.pixel_error, {}, {}, {}};
        double hi = f.prisms.density_scale;
        if (f.prisms.density == LayerDensity::LayerHeight) {
            hi *= f.thickness.max_height();
        } else if (f.prisms.density == LayerDensity::Noise) {
            double top = 0.0;
            for (int j = 0; j < f.thickness.size; ++j)
                for (int i = 0; i < f.thickness.size; ++i)
                    top = std::max(top, f.prisms.noise(f.thickness.x(i), f.thickness.y(j)));
            hi *= top;
        }
        layer.tf = fixed_range(f.transfer_function, 0.0, hi);
        m.fog.emplace(std::move(layer));
    }
    if (scene.aurora) {
        const AuroraSpec& a = *scene.aurora;
        LodSettings settings = scene.lod;
        LayerPrismOptions options;
        options.density = LayerDensity::LowerBorder;
        options.scalar_name = "emission";
        Layer layer{ContinuousLod(a.layer.lower_border, a.layer.depth, settings), options, {}, a.path, false,
                    a.pixel_error, {}, {}, {}};
        layer.tf = fixed_range(a.transfer_function, 0.0, options.density_scale);
        m.aurora.emplace(std::move(layer));
    }
}

SceneRenderer::~SceneRenderer() = default;
SceneRenderer::SceneRenderer(SceneRenderer&&) noexcept = default;
SceneRenderer& SceneRenderer::operator=(SceneRenderer&&) noexcept = default;

FrameStats SceneRenderer::render(const fx::Camera& camera, const fx::Viewport& viewport, bool finish) {
    if (viewport.width <= 0 || viewport.height <= 0) throw fx::Error("terrain scene: empty viewport");
    Impl& m = *impl_;
    GLint host = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host);
    FrameStats stats = m.draw(camera, viewport.width, viewport.height, false);
    const auto t = Clock::now();
    {
        fx::gl::StateGuard guard;
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(host));
        glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
        m.composite.draw_over_framebuffer(m.target.color_texture());
        if (finish) glFinish();
        FX_GL_CHECK("terrain scene composite");
    }
    stats.draw_ms += ms_since(t);
    stats.frame_ms += ms_since(t);
    return stats;
}

fx::Image SceneRenderer::render_to_image(const fx::Camera& camera, int width, int height, FrameStats* stats) {
    if (width <= 0 || height <= 0) throw fx::Error("terrain scene: empty image size");
    const FrameStats s = impl_->draw(camera, width, height, true);
    if (stats) *stats = s;
    return impl_->target.read();
}

void SceneRenderer::set_fog_path(fx::RenderPath path) {
    if (impl_->fog) impl_->fog->path = path;
}
void SceneRenderer::set_aurora_path(fx::RenderPath path) {
    if (impl_->aurora) impl_->aurora->path = path;
}
void SceneRenderer::set_pixel_error(double pixels) {
    if (!(pixels > 0.0) || !std::isfinite(pixels)) throw fx::Error("terrain scene: the pixel error must be positive");
    impl_->scene.pixel_error = pixels;
}

const Scene& SceneRenderer::scene() const { return impl_->scene; }
const ContinuousLod& SceneRenderer::terrain_lod() const { return impl_->terrain; }
const LodMesh& SceneRenderer::terrain_mesh() const { return impl_->terrain_mesh; }
const fx::CellMesh& SceneRenderer::fog_prisms() const { return impl_->fog ? impl_->fog->prisms : impl_->no_prisms; }
const fx::CellMesh& SceneRenderer::aurora_prisms() const {
    return impl_->aurora ? impl_->aurora->prisms : impl_->no_prisms;
}

} // namespace terrain
