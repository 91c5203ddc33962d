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
#include "fx/resource_limits.hpp"
#include "gl/composite_pass.hpp"
#include "gl/gl_check.hpp"
#include "gl/gl_object.hpp"
#include "gl/render_target.hpp"
#include "gl/state_guard.hpp"
#include "medium/froxel_medium.hpp"
#include "render/depth_normalizer.hpp"
#include "render/fx_layer.hpp"
#include "render/scene_medium.hpp"
#include "terrain/layer_effects.hpp"
#include "terrain/terrain_lod.hpp"

namespace cellfx::terrain {

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
    double albedo = 0.0;  // absorbing: how much light it scatters
    LightSpec light;      // how its medium_light() shows in the absorbing media
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

// The paths of the emission–absorption model integrate together as one medium; pcp (classic,
// emission only) and mip (maximum) keep their own models and are added over it.
bool in_medium(const Slot& s) {
    return s.path == fx::RenderPath::PcpExact || s.path == fx::RenderPath::Absorption ||
           s.path == fx::RenderPath::AbsorptionExact;
}
// The sorted paths always absorb; pcp-exact when the effect is declared absorbing.
bool absorbs(const Slot& s) { return s.path != fx::RenderPath::PcpExact ? in_medium(s) : s.absorb; }

// The effect's medium in the world: its transfer function, whether it absorbs, its albedo and
// its light (moved by its transform). Assigned into `v`, whose storage a frame reuses.
void set_medium_volume(const Slot& s, fx::MediumVolume& v) {
    v.tf = s.tf;
    v.absorbs = absorbs(s);
    v.albedo = v.absorbs ? s.albedo : 0.0;
    v.light = fx::MediumLight{};
    fx::MediumLight l = s.effect->medium_light();
    if (l.kind != fx::MediumLight::Kind::None && s.light.strength > 0.0) {
        const glm::dmat4& m = s.effect->transform();
        l.origin = glm::dvec3(m * glm::dvec4(l.origin, 1.0));
        l.axis = glm::normalize(glm::dvec3(m * glm::dvec4(l.axis, 0.0)));
        l.color = s.light.color * s.light.strength;
        l.phase_g = s.light.phase_g;
        if (s.light.radius > 0.0) l.radius = s.light.radius;
        v.light = l;
    }
}
fx::MediumVolume medium_volume(const Slot& s) {
    fx::MediumVolume v;
    set_medium_volume(s, v);
    return v;
}

// What the effect can change on screen at `time`: its world bounds, and — when the scene has a
// medium its light scatters in (`scatterers`) — the reach of its glow (a campfire off screen
// still lights the fog in view).
fx::Bounds view_bounds(const Slot& s, double time, bool scatterers) {
    fx::Bounds b = s.effect->world_bounds(time);
    const fx::MediumLight l = s.effect->medium_light();
    if (!scatterers || l.kind != fx::MediumLight::Kind::Point || !(s.light.strength > 0.0) || !in_medium(s)) return b;
    const glm::dvec3 centre(s.effect->transform_at(time) * glm::dvec4(l.origin, 1.0));
    const double r = s.light.radius > 0.0 ? s.light.radius : l.radius;
    b.lo = glm::min(b.lo, centre - r);
    b.hi = glm::max(b.hi, centre + r);
    return b;
}

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
    if (medium.pixels > 0)
        s += "  |  medium " + std::to_string(medium.pixels) + " px, " + std::to_string(medium.segments) + " segments";
    for (const EffectFrameStats& e : effects) {
        s += "  |  " + e.name + ": " + effect_status_name(e.status);
        if (effect_skipped(e.status)) continue;
        s += " " + std::string(fx::render_path_name(e.path)) + (e.in_medium ? "+medium " : " ") + std::to_string(e.cells_drawn) +
             " cells";
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
    fx::gl::Framebuffer target_color; // its colour alone: drawn into while its depth is read
    fx::gl::CompositePass composite;
    DepthNormalizer depth;
    fx::gl::Query surface_timer, composite_timer;
    std::optional<fx::MediumCompositor> medium; // exact: made on the first frame whose volumes overlap
    std::optional<fx::FroxelMedium> froxels;    // froxel: the same
    fx::gl::Texture behind;                     // exact: the frame behind the medium's region
    int behind_width = 0, behind_height = 0;
    std::optional<FxLayer> layer;               // the effects at scene.fx_scale < 1
    fx::Camera draw_camera;                     // the camera the effects draw with this frame
    // The frame's medium, kept so that a steady frame reuses their storage.
    std::vector<Slot*> medium_slots, appended;  // appended: the volumes that reach the region
    int appended_bulk = -1;                     // the ground fog among them (exact: binned), −1: none
    std::vector<MediumCandidate> candidates;
    std::vector<fx::MediumVolume> volumes;      // of the appended volumes
    MediumPlan plan;

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
            slots.back().albedo = f.albedo;
        }
        if (s.aurora) {
            const AuroraSpec& a = *s.aurora;
            auto effect = std::make_unique<Aurora>(a.layer, s.lod, LayerEffectSettings{a.pixel_error, 0});
            aurora = effect.get();
            add_slot("aurora", Kind::Aurora, std::move(effect), a.transfer_function, a.extinction_scale, a.path, false,
                     a.enabled);
        }
        for (const EffectSpec& e : s.effects) {
            add_slot(e.name, Kind::Other, make_effect(e.params), e.transfer_function, e.extinction_scale, e.path, e.absorb,
                     e.enabled);
            set_medium_spec(slots.back(), e);
        }
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

    // What an effect's scene entry says of its part in the medium.
    static void set_medium_spec(Slot& s, const EffectSpec& e) {
        s.albedo = e.albedo;
        s.light = e.light;
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
        cam.validate("scene update: camera");
        if (fx::exceeds(fx::Limit::ImagePixels, std::uint64_t(w) * std::uint64_t(h)))
            throw fx::Error(fx::over_limit(fx::Limit::ImagePixels, std::uint64_t(w) * std::uint64_t(h),
                                           "scene update: a " + std::to_string(w) + "x" + std::to_string(h) + " viewport"));
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
        bool scatterers = false; // an absorbing medium that lights scatter in
        for (const Slot& s : slots) scatterers = scatterers || (s.enabled && absorbs(s) && s.albedo > 0.0);
        for (Slot& s : slots) {
            s.simulated = false;
            reset_frame(s.stats);
            s.stats.path = s.path;
            if (!s.enabled) {
                s.stats.status = EffectStatus::Disabled;
                continue;
            }
            const fx::Bounds b = view_bounds(s, time, scatterers);
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

    // Uploads what update() changed; false when there is nothing to draw (changes stay pending).
    bool upload(Slot& s) {
        const fx::CellMesh& mesh = s.effect->mesh();
        if (mesh.cell_count() == 0) return false;
        const auto t = Clock::now();
        if (!s.renderer) {
            s.renderer.emplace(mesh, s.effect->scalar_name(), s.tf);
            if (parallel_for) s.renderer->set_parallel_for(parallel_for); // else cellfx's own pool (the default)
            // The terrain's layers span far more than the view: only the prisms in view are drawn.
            s.renderer->set_culling(s.kind == Kind::Fog || s.kind == Kind::Aurora);
        } else if (s.pending.mesh) {
            // Only the points and cells that changed (all of them for effects that rebuild whole).
            s.renderer->update_mesh(mesh, s.effect->scalar_name(), s.effect->mesh_changes());
        } else if (s.pending.scalars) {
            s.renderer->set_scalars(mesh.find_scalar(s.effect->scalar_name())->values);
        }
        s.effect->clear_mesh_changes();
        s.pending = fx::EffectChanges{};
        s.stats.upload_ms = ms_since(t);
        stats.upload_ms += s.stats.upload_ms;
        return true;
    }

    // Uploads what update() changed and draws one effect into the bound framebuffer.
    void draw_effect(Slot& s, const fx::Viewport& viewport, GLuint scene_depth) {
        if (!upload(s)) return;
        fx::CellRenderOptions options;
        options.fog = s.absorb && s.path == fx::RenderPath::PcpExact;
        options.scene_depth = scene_depth;
        options.timing = timing;
        const fx::CellRenderStats r =
            s.renderer->render(fx::camera_in_frame(draw_camera, s.effect->transform()), viewport, s.path, options);
        s.stats.render = r;
        s.stats.cells_drawn = r.cells_drawn;
        s.stats.draw_ms = r.cpu_ms;
        s.stats.gpu_ms = r.gpu_ms;
        stats.cells_drawn += r.cells_drawn;
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

    // The volumes of the emission–absorption paths and where they overlap on screen (`plan`),
    // from their bounds, in the pixels of the effects' size.
    void plan_frame_medium(const std::vector<Slot*>& drawn, const glm::ivec2& size) {
        medium_slots.clear();
        std::size_t n = 0;
        for (Slot* s : drawn) {
            if (!in_medium(*s) || s->effect->mesh().cell_count() == 0) continue;
            if (candidates.size() <= n) candidates.emplace_back();
            MediumCandidate& c = candidates[n++];
            const bool absorbing = absorbs(*s);
            c.bounds = s->effect->world_bounds(time);
            c.bulk = s->kind == Kind::Fog;
            c.absorbs = absorbing;
            c.scatters = absorbing && s->albedo > 0.0;
            c.light_reach = fx::Bounds{glm::dvec3(1.0), glm::dvec3(-1.0)};
            const fx::MediumLight l = s->effect->medium_light();
            if (l.kind == fx::MediumLight::Kind::Point && s->light.strength > 0.0) {
                const glm::dvec3 centre(s->effect->transform() * glm::dvec4(l.origin, 1.0));
                const double r = s->light.radius > 0.0 ? s->light.radius : l.radius;
                c.light_reach = fx::Bounds{centre - r, centre + r};
            }
            medium_slots.push_back(s);
        }
        candidates.resize(n);
        plan_medium(candidates, draw_camera, size.x, size.y, plan);
        // The volumes that reach the region, with their media (storage reused frame to frame).
        appended.clear();
        appended_bulk = -1;
        if (plan.region.empty()) return;
        for (std::size_t i = 0; i < medium_slots.size(); ++i) { // at most kMaxVolumes (plan_medium)
            if (!plan.appended[i]) continue;
            if (medium_slots[i]->kind == Kind::Fog) appended_bulk = int(appended.size());
            if (volumes.size() <= appended.size()) volumes.emplace_back();
            set_medium_volume(*medium_slots[i], volumes[appended.size()]);
            appended.push_back(medium_slots[i]);
        }
        volumes.resize(appended.size());
    }

    // The appended volume's figures: drawn as one medium.
    void count_in_medium(Slot& s) {
        s.stats.in_medium = true;
        if (s.stats.cells_drawn == 0) s.stats.cells_drawn = s.effect->mesh().cell_count(), stats.cells_drawn += s.stats.cells_drawn;
    }

    // Exact: the region of the plan, every appended volume's segments integrated over the frame
    // behind them (`behind_texture`: a copy of the effects' target before they were drawn),
    // into the bound framebuffer, `viewport` the effects' target at its origin.
    void draw_exact_medium(const fx::Viewport& viewport, GLuint scene_depth, GLuint behind_texture) {
        if (!medium) medium.emplace();
        medium->begin(draw_camera, viewport, plan.region, volumes, appended_bulk, timing);
        for (std::size_t v = 0; v < appended.size(); ++v) {
            Slot& s = *appended[v];
            medium->append(*s.renderer, fx::camera_in_frame(draw_camera, s.effect->transform()), v, scene_depth);
            count_in_medium(s);
        }
        stats.medium = medium->resolve(behind_texture);
        if (timing) stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + stats.medium.gpu_ms;
    }

    // Froxel: the appended absorbing volumes injected into the grid (its tiles sized for the
    // effects' resolution `size`), lit and integrated; the grid composited over the bound
    // framebuffer's `viewport` (the full view: its edges as sharp as the depth) at each pixel's
    // depth (texel depth_origin + pixel).
    void draw_froxel_medium(const glm::ivec2& size, const fx::Viewport& viewport, GLuint scene_depth, glm::ivec2 depth_origin) {
        if (!froxels) froxels.emplace();
        // The slices end at the farthest corner of the absorbing volumes.
        double far_depth = 0.0;
        const glm::dvec3 forward = camera.forward();
        for (std::size_t v = 0; v < appended.size(); ++v) {
            if (!volumes[v].absorbs) continue;
            const fx::Bounds b = appended[v]->effect->world_bounds(time);
            for (int k = 0; k < 8; ++k) far_depth = std::max(far_depth, glm::dot(b.corner(k) - camera.eye, forward));
        }
        GLint framebuffer = 0;
        glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &framebuffer);
        froxels->begin(draw_camera, size.x, size.y, std::max(far_depth, 2.0 * camera.near_distance), volumes, timing);
        for (std::size_t v = 0; v < appended.size(); ++v) {
            Slot& s = *appended[v];
            if (!upload(s)) continue;
            if (volumes[v].absorbs) froxels->inject(*s.renderer, s.effect->transform(), v);
            count_in_medium(s);
        }
        froxels->integrate();
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, GLuint(framebuffer));
        froxels->apply(viewport, scene_depth, depth_origin);
    }

    // Froxel: the appended emission-only volumes (fire, beams) at the effects' resolution, dimmed
    // by the grid in front of them and lighting its medium.
    void draw_froxel_emission(const fx::Viewport& viewport, GLuint scene_depth) {
        for (std::size_t v = 0; v < appended.size(); ++v) {
            Slot& s = *appended[v];
            if (!volumes[v].absorbs && s.renderer) froxels->draw_emission(*s.renderer, s.effect->transform(), v, viewport, scene_depth);
        }
        stats.medium = froxels->stats();
        if (timing) stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + stats.medium.gpu_ms;
    }

    enum class Mode {
        OverHost, // over the game's frame (render(Target))
        Opaque,   // the scene's background, terrain and effects (render(camera, viewport), render_to_image)
    };

    // Draws the prepared frame. With `host` it ends composited over the host framebuffer's
    // viewport; without, the opaque frame stays in `target` (render_to_image reads it). The
    // host's depth (0: none) is normalized from `convention` first.
    //
    // Where things are drawn: the full-resolution frame is `target` (own: the opaque frames, the
    // terrain surface, the exact medium at full resolution) or the host's framebuffer; with
    // scene.fx_scale < 1 every effect path and the medium draw into `layer` at that fraction,
    // against the scene's depth reduced to it, and the layer is upsampled over the frame. The
    // froxel medium's grid is applied at full resolution in either case.
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
        // The effects' resolution, and their camera: at a reduced size, the full view's projection
        // (the layer's aspect may differ from the view's by rounding).
        const bool scaled = scene.fx_scale < 1.0;
        const glm::ivec2 effect_size = scaled ? fx_layer_size(width, height, scene.fx_scale) : glm::ivec2(width, height);
        draw_camera = camera;
        if (scaled && !draw_camera.projection) draw_camera.projection = camera.projection_matrix(double(width) / double(height));
        // One medium: where volumes of the emission–absorption model overlap on screen, they
        // are integrated together (planned from their bounds: nothing more when none overlap).
        plan_frame_medium(drawn, effect_size);
        const bool use_medium = !plan.region.empty();
        const bool froxel = use_medium && scene.medium == fx::MediumMethod::Froxel;
        const bool exact = use_medium && !froxel;
        const bool own_target = mode == Mode::Opaque || draw_terrain || (exact && !scaled);
        {
            // The one save and restore of the frame: the passes below hold guards of their own
            // (CellRenderer::render, the composite), which do nothing inside this one.
            fx::gl::StateGuard guard;
            fx::gl::StateGuard::set_render_defaults();
            // The full-resolution frame and its depth (texel depth_origin + pixel).
            fx::Viewport frame_viewport = viewport;
            GLuint frame_framebuffer = host ? *host : 0, scene_depth = 0;
            glm::ivec2 depth_origin(0);
            if (own_target) {
                if (target.width() != width || target.height() != height) {
                    target = fx::gl::RenderTarget::create(width, height, fx::gl::ColorFormat::RGBA32F, true);
                    target_color = fx::gl::Framebuffer::create();
                    glNamedFramebufferTexture(target_color.id(), GL_COLOR_ATTACHMENT0, target.color_texture(), 0);
                }
                const glm::dvec3& bg = scene.background;
                target.clear(mode == Mode::Opaque ? glm::vec4(float(bg.r), float(bg.g), float(bg.b), 1.0f) : glm::vec4(0.0f),
                             1.0f);
                target.bind_for_drawing();
                if (host_depth != 0) depth.draw(host_depth, convention, camera, viewport, 0, 0);
                if (draw_terrain) {
                    GpuTimer timer(surface_timer, timing);
                    stats.surface = surface->draw(*terrain, camera, fx::Viewport{0, 0, width, height}, scene.surface);
                    stats.surface_gpu_ms = timer.stop();
                    if (timing) stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + stats.surface_gpu_ms;
                }
                frame_viewport = fx::Viewport{0, 0, width, height};
                frame_framebuffer = target_color.id(); // passes that read the target's depth draw here
                scene_depth = target.depth_texture();
            } else {
                if (host_depth != 0) {
                    scene_depth = depth.normalized(host_depth, convention, camera, viewport);
                    depth_origin = glm::ivec2(viewport.x, viewport.y);
                }
            }
            glBindFramebuffer(GL_DRAW_FRAMEBUFFER, frame_framebuffer);
            glViewportIndexedf(0, float(frame_viewport.x), float(frame_viewport.y), float(frame_viewport.width),
                               float(frame_viewport.height));
            // The froxel grid, over the frame at full resolution.
            if (froxel) draw_froxel_medium(effect_size, frame_viewport, scene_depth, depth_origin);
            // Where the effects draw: the frame, or the reduced layer.
            fx::Viewport effect_viewport = frame_viewport;
            GLuint effect_depth = scene_depth;
            if (scaled) {
                if (!layer) layer.emplace();
                layer->begin(width, height, scene.fx_scale, scene_depth, depth_origin);
                effect_viewport = layer->viewport();
                effect_depth = layer->depth_texture();
            } else {
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, frame_framebuffer);
            }
            if (exact) {
                // What lies behind the volumes in the region: the effects' target so far.
                if (behind_width != effect_viewport.width || behind_height != effect_viewport.height) {
                    behind = fx::gl::make_texture_2d(GL_RGBA32F, effect_viewport.width, effect_viewport.height);
                    behind_width = effect_viewport.width, behind_height = effect_viewport.height;
                }
                const fx::PixelRect& r = plan.region;
                glCopyImageSubData(scaled ? layer->color_texture() : target.color_texture(), GL_TEXTURE_2D, 0, r.x, r.y, 0,
                                   behind.id(), GL_TEXTURE_2D, 0, r.x, r.y, 0, r.width, r.height, 1);
            }
            // The volumes of the medium: each with its own path where the medium does not draw it ...
            for (std::size_t i = 0; i < medium_slots.size(); ++i) {
                Slot& s = *medium_slots[i];
                if (froxel && plan.appended[i]) continue;                        // the grid and its emission pass
                if (exact && plan.region_only[i]) upload(s);                      // drawn in the region only
                else draw_effect(s, effect_viewport, effect_depth);
            }
            // ... and together where it does.
            if (froxel) draw_froxel_emission(effect_viewport, effect_depth);
            if (exact) draw_exact_medium(effect_viewport, effect_depth, behind.id());
            // The emission (pcp) and maximum (mip) effects add their light over it.
            for (Slot* s : drawn)
                if (!in_medium(*s)) draw_effect(*s, effect_viewport, effect_depth);
            if (scaled) {
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, frame_framebuffer);
                GpuTimer timer(composite_timer, timing);
                layer->composite(frame_viewport, scene_depth, depth_origin, camera);
                stats.composite_gpu_ms = timer.stop();
                if (timing) stats.gpu_ms = std::max(stats.gpu_ms, 0.0) + stats.composite_gpu_ms;
            }
            if (own_target && host) {
                glBindFramebuffer(GL_DRAW_FRAMEBUFFER, *host);
                glViewportIndexedf(0, float(viewport.x), float(viewport.y), float(viewport.width), float(viewport.height));
                GpuTimer timer(composite_timer, timing);
                composite.draw_over_framebuffer(target.color_texture());
                const double ms = timer.stop();
                if (timing) stats.composite_gpu_ms = std::max(stats.composite_gpu_ms, 0.0) + ms, stats.gpu_ms += ms;
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
        std::unique_ptr<fx::Effect> operator()(const fx::VolumeParams& p) const { return std::make_unique<fx::Volume>(p); }
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
    if (target.depth_texture != 0) check_depth_state(target.depth); // before any GL state changes
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

fx::Image SceneRenderer::depth_image() const {
    const fx::gl::RenderTarget& t = impl_->target;
    if (!t.has_depth()) return fx::Image();
    fx::Image image(t.width(), t.height());
    std::vector<float> depth(std::size_t(t.width()) * std::size_t(t.height()));
    {
        fx::gl::StateGuard guard;
        fx::gl::StateGuard::set_render_defaults();
        glGetTextureImage(t.depth_texture(), 0, GL_DEPTH_COMPONENT, GL_FLOAT, GLsizei(depth.size() * sizeof(float)), depth.data());
        FX_GL_CHECK("scene depth read-back");
    }
    for (std::size_t i = 0; i < depth.size(); ++i) image.pixels[i] = glm::vec4(depth[i], depth[i], depth[i], 1.0f);
    return image;
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
            Impl::set_medium_spec(m.slots.back(), spec);
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
            void operator()(const fx::VolumeParams& p) const { static_cast<fx::Volume&>(e).set_params(p); }
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
void SceneRenderer::set_parallel_for(const fx::ParallelFor& parallel_for) {
    impl_->parallel_for = parallel_for;
    for (Slot& s : impl_->slots)
        if (s.renderer) s.renderer->set_parallel_for(parallel_for ? parallel_for : fx::default_parallel_for());
}
double SceneRenderer::time() const { return impl_->time; }
void SceneRenderer::set_time(double seconds) {
    if (!std::isfinite(seconds)) throw fx::Error("scene: the time is not finite");
    impl_->time = seconds;
}

void SceneRenderer::set_fx_scale(double scale) {
    if (!valid_fx_scale(scale))
        throw fx::Error("scene: fx scale " + std::to_string(scale) + ": must be 1, 0.5 or 0.25 (full, half, quarter resolution)");
    impl_->scene.fx_scale = scale;
}
double SceneRenderer::fx_scale() const { return impl_->scene.fx_scale; }
void SceneRenderer::set_medium_method(fx::MediumMethod method) { impl_->scene.medium = method; }
fx::MediumMethod SceneRenderer::medium_method() const { return impl_->scene.medium; }

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

std::vector<SceneRenderer::DrawnVolume> SceneRenderer::drawn_volumes() const {
    std::vector<DrawnVolume> out;
    for (const Slot& s : impl_->slots) {
        if (!s.simulated || s.effect->mesh().cell_count() == 0) continue;
        out.push_back({s.name, s.effect.get(), s.path, in_medium(s), medium_volume(s)});
    }
    return out;
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

} // namespace cellfx::terrain
