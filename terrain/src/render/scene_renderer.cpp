// Based on: Roettger & Ertl 2003, §5 — ground fog over a continuous-LOD terrain, the aurora and
// emissive effects as cells projected by fx::CellRenderer; the scene's depth (the game's and the
// terrain's) stops them at opaque surfaces. What runs per frame is in scene_renderer.hpp.
#include "terrain/scene_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <exception>
#include <optional>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "gl/composite_pass.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "render/depth_normalizer.hpp"
#include "terrain/layer_effects.hpp"
#include "terrain/terrain_lod.hpp"

namespace terrain {

namespace {

using Clock = std::chrono::steady_clock;
double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

// CPU time of the calling thread (not the time it waits), in ms.
double thread_cpu_ms() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

enum class Kind { Fog, Aurora, Other };

// One effect and its GL side.
struct Slot {
    std::string name;
    Kind kind = Kind::Other;
    std::unique_ptr<fx::Effect> effect;
    fx::TransferFunction tf; // in scalar units
    fx::RenderPath path = fx::RenderPath::PcpExact;
    bool absorb = false;
    bool enabled = true;
    std::optional<fx::CellRenderer> renderer; // made when the effect first has cells to draw
    fx::EffectChanges pending;                // changes not uploaded yet
    bool simulated = false;                   // updated this frame: to be drawn
    double distance = 0.0;                    // eye to its bounds' centre this frame
    EffectFrameStats stats;                   // name and type set once, the rest per frame
    fx::EffectCounters counters_before;       // at the start of this frame's update()
    fx::EffectChanges changes;                // this frame's update() (filled side by side)
    std::exception_ptr error;                 // what its update() threw, if it did
};

// Zero for a new frame; the names stay (no allocation).
void reset_frame(EffectFrameStats& e) {
    EffectFrameStats fresh;
    fresh.name.swap(e.name);
    fresh.type.swap(e.type);
    e = std::move(fresh);
}

// The scene's description of an effect (scene() shows what is drawn): its fields, or null where
// that kind of effect has none.
struct SpecFields {
    fx::TransferFunction* transfer_function = nullptr;
    double* extinction_scale = nullptr;
    fx::RenderPath* path = nullptr;
    bool* absorb = nullptr;
    bool* enabled = nullptr;
    EffectParams* params = nullptr;
};

// GL_TIME_ELAPSED around a block, when timing is on.
class GpuTimer {
public:
    GpuTimer(const fx::gl::Query& query, bool on) : query_(query), on_(on) {
        if (on_) glBeginQuery(GL_TIME_ELAPSED, query_.id());
    }
    double stop() {
        if (!on_) return -1.0;
        on_ = false;
        glEndQuery(GL_TIME_ELAPSED);
        GLuint64 ns = 0;
        glGetQueryObjectui64v(query_.id(), GL_QUERY_RESULT, &ns);
        return double(ns) * 1e-6;
    }
    ~GpuTimer() {
        if (on_) glEndQuery(GL_TIME_ELAPSED);
    }

private:
    const fx::gl::Query& query_;
    bool on_;
};

std::string format_ms(double ms) {
    char b[32];
    std::snprintf(b, sizeof b, "%.1f", ms);
    return b;
}

} // namespace

const char* effect_status_name(EffectStatus status) {
    switch (status) {
    case EffectStatus::Simulated: return "simulated";
    case EffectStatus::Moved: return "moved";
    case EffectStatus::Unchanged: return "unchanged";
    case EffectStatus::Disabled: return "disabled";
    case EffectStatus::OutOfView: return "out of view";
    }
    return "?";
}

const EffectFrameStats* FrameStats::find(std::string_view name) const {
    for (const EffectFrameStats& e : effects)
        if (e.name == name) return &e;
    return nullptr;
}

std::string FrameStats::summary() const {
    std::string s = "t " + format_ms(time) + " s  " + format_ms(frame_ms) + " ms";
    if (gpu_ms >= 0.0) s += " (gpu " + format_ms(gpu_ms) + ")";
    for (const EffectFrameStats& e : effects) {
        s += "  |  " + e.name + ": " + effect_status_name(e.status);
        if (effect_skipped(e.status)) continue;
        s += " " + std::string(fx::render_path_name(e.path)) + " " + std::to_string(e.cells_drawn) + " cells";
        if (e.cells_built) s += ", built " + std::to_string(e.cells_built);
        if (e.noise_samples) s += ", noise " + std::to_string(e.noise_samples);
    }
    return s;
}

struct SceneRenderer::Impl {
    Scene scene;
    bool draw_terrain = false;
    bool timing = false;
    double time = 0.0;
    fx::ParallelFor parallel_for;
    std::shared_ptr<TerrainLod> terrain; // the ground, with the fog layer when there is fog
    std::optional<SurfaceRenderer> surface; // made on the first frame that draws it
    std::vector<Slot> slots;
    GroundFog* fog = nullptr;
    Aurora* aurora = nullptr;
    fx::CellMesh no_prisms;
    LodMesh no_mesh;

    // The frame prepared by update().
    bool updated = false;
    fx::Camera camera;
    int width = 0, height = 0;
    FrameStats stats;
    std::vector<Slot*> to_update, order; // per frame, capacity kept

    fx::gl::RenderTarget target; // colour + depth, when the surface is drawn or the frame is opaque
    fx::gl::CompositePass composite;
    DepthNormalizer depth;
    fx::gl::Query surface_timer, composite_timer;

    explicit Impl(const Scene& s) : scene(s), draw_terrain(s.draw_terrain && s.has_terrain()) {
        if (s.has_terrain() && (s.fog || draw_terrain))
            terrain = std::make_shared<TerrainLod>(s.ground, s.fog ? std::optional<HeightField>(s.fog->thickness) : std::nullopt,
                                                   s.lod);
        const LayerEffectSettings lod_view{s.pixel_error, s.triangle_budget};
        if (s.fog) {
            const FogSpec& f = *s.fog;
            auto effect = std::make_unique<GroundFog>(terrain, f.thickness, f.prisms, lod_view);
            fog = effect.get();
            add_slot("fog", Kind::Fog, std::move(effect), f.transfer_function, f.extinction_scale, f.path, f.absorb, f.enabled);
        }
        if (s.aurora) {
            const AuroraSpec& a = *s.aurora;
            auto effect = std::make_unique<Aurora>(a.layer, s.lod, LayerEffectSettings{a.pixel_error, 0});
            aurora = effect.get();
            add_slot("aurora", Kind::Aurora, std::move(effect), a.transfer_function, a.extinction_scale, a.path, false,
                     a.enabled);
        }
        for (const EffectSpec& e : s.effects)
            add_slot(e.name, Kind::Other, make_effect(e.params), e.transfer_function, e.extinction_scale, e.path, e.absorb,
                     e.enabled);
        composite = fx::gl::CompositePass::create();
        surface_timer = fx::gl::Query::create(GL_TIME_ELAPSED);
        composite_timer = fx::gl::Query::create(GL_TIME_ELAPSED);
        FX_GL_CHECK("scene renderer set-up");
    }

    void add_slot(const std::string& name, Kind kind, std::unique_ptr<fx::Effect> effect, const fx::TransferFunction& tf,
                  double extinction_scale, fx::RenderPath path, bool absorb, bool enabled) {
        Slot slot;
        slot.name = name;
        slot.kind = kind;
        slot.tf = drawn_transfer_function(tf, extinction_scale, effect->scalar_range());
        slot.stats.name = name;
        slot.stats.type = effect->type_name();
        slot.effect = std::move(effect);
        slot.path = path;
        slot.absorb = absorb;
        slot.enabled = enabled;
        slots.push_back(std::move(slot));
        to_update.reserve(slots.size());
        order.reserve(slots.size());
        stats.effects.resize(slots.size());
    }

    Slot* find(const std::string& name) {
        for (Slot& s : slots)
            if (s.name == name) return &s;
        return nullptr;
    }

    Slot& slot(const std::string& name) {
        if (Slot* s = find(name)) return *s;
        std::string names;
        for (const Slot& s : slots) names += (names.empty() ? "" : ", ") + s.name;
        throw fx::Error("scene: no effect named '" + name + "' (the scene has: " + (names.empty() ? "none" : names) + ")");
    }

    SpecFields spec(const Slot& s) {
        SpecFields f;
        if (s.kind == Kind::Fog) {
            FogSpec& g = *scene.fog;
            f = {&g.transfer_function, &g.extinction_scale, &g.path, &g.absorb, &g.enabled, nullptr};
        } else if (s.kind == Kind::Aurora) {
            AuroraSpec& a = *scene.aurora;
            f = {&a.transfer_function, &a.extinction_scale, &a.path, nullptr, &a.enabled, nullptr};
        } else {
            for (EffectSpec& e : scene.effects)
                if (e.name == s.name) f = {&e.transfer_function, &e.extinction_scale, &e.path, &e.absorb, &e.enabled, &e.params};
        }
        return f;
    }

    // The effect's drawn transfer function changed (colour, extinction, scalar range).
    void set_drawn_transfer_function(Slot& s, fx::TransferFunction tf) {
        s.tf = std::move(tf);
        if (s.renderer) s.renderer->set_transfer_function(s.tf);
    }

    LodView terrain_view(const fx::Camera& cam, int h) const {
        return LodView::from_camera(cam, h, scene.pixel_error, scene.triangle_budget);
    }

    // One effect's update(), on whichever thread the host's job system chose.
    static void update_slot(Slot& s, const fx::EffectView& view) {
        try {
            const auto t = Clock::now();
            s.changes = s.effect->update(view);
            s.stats.simulate_ms = ms_since(t);
        } catch (...) {
            s.error = std::current_exception();
        }
    }

    void update(double dt, const fx::Camera& cam, int w, int h) {
        if (!std::isfinite(dt)) throw fx::Error("scene update: dt is not finite");
        if (w < 1 || h < 1) throw fx::Error("scene update: empty viewport " + std::to_string(w) + "x" + std::to_string(h));
        const auto start = Clock::now();
        const double cpu_start = thread_cpu_ms();
        time += dt;
        std::vector<EffectFrameStats> effect_stats = std::move(stats.effects); // keeps its strings
        stats = FrameStats{};
        stats.effects = std::move(effect_stats);
        stats.time = time;
        const fx::EffectView view{cam, w, h, time};
        const double aspect = double(w) / double(h);

        // Which effects run this frame: enabled and in view (bounds from parameters and pose).
        to_update.clear();
        for (Slot& s : slots) {
            s.simulated = false;
            reset_frame(s.stats);
            s.stats.path = s.path;
            if (!s.enabled) {
                s.stats.status = EffectStatus::Disabled;
                continue;
            }
            const fx::Bounds b = s.effect->world_bounds(time);
            if (!fx::bounds_in_view(b, cam, aspect)) {
                s.stats.status = EffectStatus::OutOfView;
                continue;
            }
            s.simulated = true;
            s.distance = glm::length(b.center() - cam.eye);
            to_update.push_back(&s);
        }
        // The terrain LOD, once, for the surface and the fog alike.
        const bool fog_runs = fog && find("fog")->simulated;
        if (terrain && (draw_terrain || fog_runs)) {
            terrain->update(terrain_view(cam, h), &stats.terrain_lod);
            stats.lod_ms += terrain->last_update_ms();
            stats.mesh_ms += terrain->last_extract_ms();
        }
        // The effects' own work, side by side on the host's job system when it gave one.
        for (Slot* s : to_update) {
            s->error = nullptr;
            s->counters_before = s->effect->counters();
        }
        struct Job {
            std::vector<Slot*>* slots;
            const fx::EffectView* view;
        } job{&to_update, &view};
        if (parallel_for && to_update.size() > 1) {
            parallel_for.run(parallel_for.host_context, to_update.size(),
                             [](void* context, std::size_t i) {
                                 const Job& j = *static_cast<const Job*>(context);
                                 update_slot(*(*j.slots)[i], *j.view);
                             },
                             &job);
        } else {
            for (Slot* s : to_update) update_slot(*s, view);
        }
        for (Slot* s : to_update)
            if (s->error) std::rethrow_exception(s->error);
        for (Slot* s : to_update) {
            const fx::EffectChanges& c = s->changes;
            const fx::EffectCounters& after = s->effect->counters();
            s->pending.mesh |= c.mesh;
            s->pending.scalars |= c.scalars;
            s->stats.status = (c.mesh || c.scalars) ? EffectStatus::Simulated
                              : c.pose              ? EffectStatus::Moved
                                                    : EffectStatus::Unchanged;
            s->stats.cells_built = std::size_t(after.cells_built - s->counters_before.cells_built);
            s->stats.noise_samples = std::size_t(after.noise_samples - s->counters_before.noise_samples);
            stats.noise_samples += s->stats.noise_samples;
            if (s->kind == Kind::Fog) {
                stats.mesh_ms += s->stats.simulate_ms; // the LOD was refined above: prisms only
            } else if (s->kind == Kind::Aurora) {
                stats.aurora_lod = aurora->lod_stats();
                stats.lod_ms += aurora->lod().last_update_ms();
                stats.mesh_ms += s->stats.simulate_ms - aurora->lod().last_update_ms();
            }
        }
        for (Slot& s : slots) s.stats.cells = s.effect->mesh().cell_count();
        camera = cam;
        width = w;
        height = h;
        updated = true;
        stats.update_ms = ms_since(start);
        stats.update_cpu_ms = thread_cpu_ms() - cpu_start;
        stats.frame_ms = stats.update_ms;
        collect_effect_stats();
    }

    // The per-effect figures into stats.effects, in the scene's order (copies into kept strings).
    void collect_effect_stats() {
        stats.effects.resize(slots.size());
        for (std::size_t i = 0; i < slots.size(); ++i) stats.effects[i] = slots[i].stats;
    }

    // Uploads what update() changed and draws one effect into the bound framebuffer.
    void draw_effect(Slot& s, const fx::Viewport& viewport, GLuint scene_depth) {
        const fx::CellMesh& mesh = s.effect->mesh();
        if (mesh.cell_count() == 0) return; // nothing to draw (changes stay pending)
        const auto t = Clock::now();
        if (!s.renderer) {
            s.renderer.emplace(mesh, s.effect->scalar_name(), s.tf);
        } else if (s.pending.mesh) {
            s.renderer->set_mesh(mesh, s.effect->scalar_name());
        } else if (s.pending.scalars) {
            s.renderer->set_scalars(mesh.find_scalar(s.effect->scalar_name())->values);
        }
        s.pending = fx::EffectChanges{};
        s.stats.upload_ms = ms_since(t);
        fx::CellRenderOptions options;
        options.fog = s.absorb && s.path == fx::RenderPath::PcpExact;
        options.scene_depth = scene_depth;
        options.timing = timing;
        const fx::CellRenderStats r =
            s.renderer->render(fx::camera_in_frame(camera, s.effect->transform()), viewport, s.path, options);
        s.stats.render = r;
        s.stats.cells_drawn = r.cells_drawn;
        s.stats.draw_ms = r.cpu_ms;
        s.stats.gpu_ms = r.gpu_ms;
        stats.cells_drawn += r.cells_drawn;
        stats.upload_ms += s.stats.upload_ms;
        if (timing) stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + r.gpu_ms;
        if (s.kind == Kind::Fog) stats.fog = r, stats.fog_prisms = fog->prism_stats();
        if (s.kind == Kind::Aurora) stats.aurora = r, stats.aurora_prisms = aurora->prism_stats();
    }

    // The effects to draw, fog and aurora first (they fill the scene), the rest far to near;
    // ties in the scene's order (std::sort with the slot as the last key: stable_sort would
    // allocate a buffer every frame).
    const std::vector<Slot*>& draw_order() {
        order.clear();
        for (Slot& s : slots)
            if (s.simulated) order.push_back(&s);
        std::sort(order.begin(), order.end(), [](const Slot* a, const Slot* b) {
            const int ka = a->kind == Kind::Other ? 1 : 0, kb = b->kind == Kind::Other ? 1 : 0;
            if (ka != kb) return ka < kb;
            if (ka == 1 && a->distance != b->distance) return a->distance > b->distance;
            return a < b;
        });
        return order;
    }

    enum class Mode {
        OverHost, // over the game's frame (render(Target))
        Opaque,   // the scene's background, terrain and effects (render(camera, viewport), render_to_image)
    };

    // Draws the prepared frame. With `host` it ends composited over the host framebuffer's
    // viewport; without, the opaque frame stays in `target` (render_to_image reads it). The
    // host's depth (0: none) is normalized from `convention` first.
    void draw(Mode mode, std::optional<GLuint> host, const fx::Viewport& viewport, GLuint host_depth,
              const DepthConvention& convention, bool finish) {
        if (!updated) throw fx::Error("scene render: update() has not been called");
        if (viewport.width != width || viewport.height != height)
            throw fx::Error("scene render: the viewport is " + std::to_string(viewport.width) + "x" +
                            std::to_string(viewport.height) + " but update() prepared " + std::to_string(width) + "x" +
                            std::to_string(height));
        const auto start = Clock::now();
        const double cpu_start = thread_cpu_ms();
        const double upload_before = stats.upload_ms;
        if (draw_terrain && !surface) surface.emplace(scene.ground);
        const std::vector<Slot*>& drawn = draw_order();
        const bool own_target = mode == Mode::Opaque || draw_terrain;
        {
            // The one save and restore of the frame: the passes below hold guards of their own
            // (CellRenderer::render, the composite), which do nothing inside this one.
            fx::gl::StateGuard guard;
            fx::gl::StateGuard::set_render_defaults();
            fx::Viewport effect_viewport = viewport;
            GLuint scene_depth = 0;
            if (own_target) {
                if (target.width() != width || target.height() != height)
                    target = fx::gl::RenderTarget::create(width, height, fx::gl::ColorFormat::RGBA32F, true);
                const glm::dvec3& bg = scene.background;
                target.clear(mode == Mode::Opaque ? glm::vec4(float(bg.r), float(bg.g), float(bg.b), 1.0f) : glm::vec4(0.0f),
                             1.0f);
                target.bind_for_drawing();
                if (host_depth != 0) depth.draw(host_depth, convention, camera, viewport, 0, 0);
                if (draw_terrain) {
                    GpuTimer timer(surface_timer, timing);
                    stats.surface = surface->draw(terrain->mesh(), camera, fx::Viewport{0, 0, width, height}, scene.surface);
                    stats.surface_gpu_ms = timer.stop();
                    if (timing) stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + stats.surface_gpu_ms;
                }
                effect_viewport = fx::Viewport{0, 0, width, height};
                scene_depth = target.depth_texture();
            } else {
                if (host_depth != 0) scene_depth = depth.normalized(host_depth, convention, camera, viewport);
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, host ? *host : 0);
            }
            for (Slot* s : drawn) draw_effect(*s, effect_viewport, scene_depth);
            if (own_target && host) {
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, *host);
                glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
                GpuTimer timer(composite_timer, timing);
                composite.draw_over_framebuffer(target.color_texture());
                stats.composite_gpu_ms = timer.stop();
                if (timing) stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + stats.composite_gpu_ms;
            }
            if (finish || timing) glFinish();
            FX_GL_CHECK("scene frame");
        }
        stats.render_ms = ms_since(start);
        stats.render_cpu_ms = thread_cpu_ms() - cpu_start;
        stats.draw_ms = stats.render_ms - (stats.upload_ms - upload_before);
        stats.frame_ms = stats.update_ms + stats.render_ms;
        for (Slot& s : slots) s.stats.cells = s.effect->mesh().cell_count();
        collect_effect_stats();
    }
};

SceneRenderer::SceneRenderer(const Scene& scene) : impl_(std::make_unique<Impl>(scene)) {}
SceneRenderer::~SceneRenderer() = default;
SceneRenderer::SceneRenderer(SceneRenderer&&) noexcept = default;
SceneRenderer& SceneRenderer::operator=(SceneRenderer&&) noexcept = default;

void SceneRenderer::update(double dt, const fx::Camera& camera, int width, int height) {
    impl_->update(dt, camera, width, height);
}

std::unique_ptr<fx::Effect> make_effect(const EffectParams& params) {
    struct Make {
        std::unique_ptr<fx::Effect> operator()(const fx::CampfireParams& p) const { return std::make_unique<fx::Campfire>(p); }
        std::unique_ptr<fx::Effect> operator()(const fx::SearchLightParams& p) const {
            return std::make_unique<fx::SearchLight>(p);
        }
        std::unique_ptr<fx::Effect> operator()(const fx::LaserConeParams& p) const { return std::make_unique<fx::LaserCone>(p); }
    };
    return std::visit(Make{}, params);
}

fx::TransferFunction drawn_transfer_function(const fx::TransferFunction& tf, double extinction_scale, fx::ScalarRange range) {
    const double lo = range.lo, hi = std::max(double(range.hi), lo + 1e-6 * std::max(1.0, std::abs(lo)));
    const fx::TransferFunction scaled = extinction_scale == 1.0 ? tf : tf.scaled_extinction(extinction_scale);
    return scaled.normalized() ? scaled.rescaled(lo, hi) : scaled;
}

const FrameStats& SceneRenderer::render(const Target& target) {
    const GLuint fb = target.framebuffer;
    impl_->draw(Impl::Mode::OverHost, fb, target.viewport, target.depth_texture, target.depth, false);
    return impl_->stats;
}

const FrameStats& SceneRenderer::stats() const { return impl_->stats; }

const FrameStats& SceneRenderer::render(const fx::Camera& camera, const fx::Viewport& viewport, bool finish) {
    if (viewport.width <= 0 || viewport.height <= 0) throw fx::Error("terrain scene: empty viewport");
    GLint host = 0;
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &host);
    impl_->update(0.0, camera, viewport.width, viewport.height);
    impl_->draw(Impl::Mode::Opaque, GLuint(host), viewport, 0, DepthConvention{}, finish);
    return impl_->stats;
}

fx::Image SceneRenderer::render_to_image(const fx::Camera& camera, int width, int height, FrameStats* stats) {
    if (width <= 0 || height <= 0) throw fx::Error("terrain scene: empty image size");
    impl_->update(0.0, camera, width, height);
    impl_->draw(Impl::Mode::Opaque, std::nullopt, fx::Viewport{0, 0, width, height}, 0, DepthConvention{}, true);
    if (stats) *stats = impl_->stats;
    return impl_->target.read();
}

std::vector<std::string> SceneRenderer::effect_names() const {
    std::vector<std::string> names;
    for (const Slot& s : impl_->slots) names.push_back(s.name);
    return names;
}
bool SceneRenderer::has_effect(const std::string& name) const { return impl_->find(name) != nullptr; }
void SceneRenderer::set_enabled(const std::string& name, bool enabled) {
    Slot& s = impl_->slot(name);
    s.enabled = *impl_->spec(s).enabled = enabled;
}
bool SceneRenderer::enabled(const std::string& name) const { return impl_->slot(name).enabled; }
void SceneRenderer::set_path(const std::string& name, fx::RenderPath path) {
    Slot& s = impl_->slot(name);
    s.path = *impl_->spec(s).path = path;
}
fx::RenderPath SceneRenderer::path(const std::string& name) const { return impl_->slot(name).path; }
fx::Effect& SceneRenderer::effect(const std::string& name) { return *impl_->slot(name).effect; }
fx::Effect* SceneRenderer::find_effect(const std::string& name) noexcept {
    Slot* s = impl_->find(name);
    return s ? s->effect.get() : nullptr;
}

void SceneRenderer::add_effect(const EffectSpec& spec) {
    Impl& m = *impl_;
    if (spec.name.empty()) throw fx::Error("scene: add_effect: the effect needs a name");
    if (spec.name == "fog" || spec.name == "aurora")
        throw fx::Error("scene: add_effect: '" + spec.name + "' names the scene's own " + spec.name + " section");
    if (m.find(spec.name)) throw fx::Error("scene: add_effect: there is already an effect named '" + spec.name + "'");
    try {
        std::unique_ptr<fx::Effect> effect = make_effect(spec.params);
        m.scene.effects.push_back(spec);
        try {
            m.add_slot(spec.name, Kind::Other, std::move(effect), spec.transfer_function, spec.extinction_scale, spec.path,
                       spec.absorb, spec.enabled);
        } catch (...) {
            m.scene.effects.pop_back();
            throw;
        }
    } catch (const fx::Error& e) {
        throw fx::Error("scene: add_effect '" + spec.name + "': " + e.what());
    }
}

void SceneRenderer::remove_effect(const std::string& name) {
    Impl& m = *impl_;
    Slot& s = m.slot(name);
    if (s.kind != Kind::Other)
        throw fx::Error("scene: remove_effect: '" + name + "' is the scene's " + name + " (switch it off with set_enabled)");
    m.slots.erase(m.slots.begin() + (&s - m.slots.data()));
    m.scene.effects.erase(std::find_if(m.scene.effects.begin(), m.scene.effects.end(),
                                       [&](const EffectSpec& e) { return e.name == name; }));
    m.stats.effects.resize(m.slots.size());
    m.collect_effect_stats();
}

void SceneRenderer::set_params(const std::string& name, const EffectParams& params) {
    Impl& m = *impl_;
    Slot& s = m.slot(name);
    const SpecFields spec = m.spec(s);
    if (!spec.params) throw fx::Error("scene: set_params: '" + name + "' is the scene's " + name + ", set in its own section");
    if (std::strcmp(effect_type_name(params), s.effect->type_name()) == 0) {
        // The same type: the effect keeps its state and rebuilds only what the change needs.
        struct Set {
            fx::Effect& e;
            void operator()(const fx::CampfireParams& p) const { static_cast<fx::Campfire&>(e).set_params(p); }
            void operator()(const fx::SearchLightParams& p) const { static_cast<fx::SearchLight&>(e).set_params(p); }
            void operator()(const fx::LaserConeParams& p) const { static_cast<fx::LaserCone&>(e).set_params(p); }
        };
        try {
            std::visit(Set{*s.effect}, params);
        } catch (const fx::Error& e) {
            throw fx::Error("scene: set_params '" + name + "': " + e.what());
        }
    } else {
        std::unique_ptr<fx::Effect> effect;
        try {
            effect = make_effect(params);
        } catch (const fx::Error& e) {
            throw fx::Error("scene: set_params '" + name + "': " + e.what());
        }
        effect->set_parent_transform(s.effect->parent_transform());
        s.effect = std::move(effect);
        s.stats.type = s.effect->type_name();
        s.pending.mesh = true;
    }
    *spec.params = params;
    // Its scalar range may have changed (a search light's intensity): map the colours again.
    m.set_drawn_transfer_function(s, drawn_transfer_function(*spec.transfer_function, *spec.extinction_scale, s.effect->scalar_range()));
}

void SceneRenderer::set_transfer_function(const std::string& name, const fx::TransferFunction& tf) {
    Slot& s = impl_->slot(name);
    const SpecFields spec = impl_->spec(s);
    impl_->set_drawn_transfer_function(s, drawn_transfer_function(tf, *spec.extinction_scale, s.effect->scalar_range()));
    *spec.transfer_function = tf;
}

void SceneRenderer::set_extinction_scale(const std::string& name, double scale) {
    Slot& s = impl_->slot(name);
    const SpecFields spec = impl_->spec(s);
    if (!(scale >= 0.0) || !std::isfinite(scale))
        throw fx::Error("scene: set_extinction_scale '" + name + "': must be finite and ≥ 0, got " + std::to_string(scale));
    impl_->set_drawn_transfer_function(s, drawn_transfer_function(*spec.transfer_function, scale, s.effect->scalar_range()));
    *spec.extinction_scale = scale;
}

void SceneRenderer::set_absorb(const std::string& name, bool absorb) {
    Slot& s = impl_->slot(name);
    const SpecFields spec = impl_->spec(s);
    if (!spec.absorb) throw fx::Error("scene: set_absorb: the " + name + " is emissive only");
    s.absorb = *spec.absorb = absorb;
}

void SceneRenderer::set_terrain_drawn(bool drawn) {
    Impl& m = *impl_;
    if (drawn && !m.scene.has_terrain()) throw fx::Error("scene: there is no terrain to draw");
    if (drawn && !m.terrain) m.terrain = std::make_shared<TerrainLod>(m.scene.ground, std::nullopt, m.scene.lod);
    m.draw_terrain = drawn;
}
bool SceneRenderer::terrain_drawn() const { return impl_->draw_terrain; }
void SceneRenderer::set_background(const glm::dvec3& rgb) {
    if (!std::isfinite(rgb.r) || !std::isfinite(rgb.g) || !std::isfinite(rgb.b)) throw fx::Error("scene: the background is not finite");
    impl_->scene.background = rgb;
}
void SceneRenderer::set_timing(bool timing) { impl_->timing = timing; }
bool SceneRenderer::timing() const { return impl_->timing; }
void SceneRenderer::set_parallel_for(const fx::ParallelFor& parallel_for) { impl_->parallel_for = parallel_for; }
double SceneRenderer::time() const { return impl_->time; }
void SceneRenderer::set_time(double seconds) {
    if (!std::isfinite(seconds)) throw fx::Error("scene: the time is not finite");
    impl_->time = seconds;
}

void SceneRenderer::set_fog_path(fx::RenderPath path) {
    if (impl_->fog) set_path("fog", path);
}
void SceneRenderer::set_aurora_path(fx::RenderPath path) {
    if (impl_->aurora) set_path("aurora", path);
}
void SceneRenderer::set_pixel_error(double pixels) {
    if (!(pixels > 0.0) || !std::isfinite(pixels)) throw fx::Error("terrain scene: the pixel error must be positive");
    impl_->scene.pixel_error = pixels;
    if (impl_->fog) impl_->fog->settings().pixel_error = pixels;
}

const Scene& SceneRenderer::scene() const { return impl_->scene; }
const ContinuousLod& SceneRenderer::terrain_lod() const {
    if (!impl_->terrain) throw fx::Error("scene: there is no terrain LOD (no terrain drawn and no fog)");
    return impl_->terrain->lod();
}
const LodMesh& SceneRenderer::terrain_mesh() const { return impl_->terrain ? impl_->terrain->mesh() : impl_->no_mesh; }
const fx::CellMesh& SceneRenderer::fog_prisms() const { return impl_->fog ? impl_->fog->mesh() : impl_->no_prisms; }
const fx::CellMesh& SceneRenderer::aurora_prisms() const {
    return impl_->aurora ? impl_->aurora->mesh() : impl_->no_prisms;
}

} // namespace terrain
