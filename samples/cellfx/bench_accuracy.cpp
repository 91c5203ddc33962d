// Based on: Roettger & Ertl 2003 (pcp, mip; §5 fog), Max, Williams & Silva 2000 (sorted
// absorption) and Wilhelms, Tarantino & Van Gelder 1995 (the scan-line reference).
//
// `cellfx bench accuracy`: what accuracy costs in time. A fixed set of scenes is rendered with
// every render path and flavour whose optical model fits the scene, each frame is timed and
// compared with the scan-line reference of the same view and model, rendered at 4×4 the size
// and box-filtered down (the picture an ideal anti-aliased renderer would give). Each flavour
// is compared with the reference of its own optical model:
//   pcp, pcp-exact                   emission            (∫ c·σ ds)
//   mip                              maximum             (max c·σ)
//   pcp-exact + fog, absorption,     emission–absorption (the volume density model)
//   absorption-exact (× every sort)
//   scanline (1 sample per pixel)    each of the three   (what point sampling alone costs)
// Errors are of the picture a user sees — the premultiplied frame composited over the scene's
// background, RGB, linear, 1 = white: RMSE, max |difference| and PSNR = 10·log10(1 / MSE). A
// second RMSE is against the reference at 1 sample per pixel, the same pixel centres the GPU
// samples: the path's own error without the aliasing every point-sampled path shares.
//
// Times: ms per frame is the median over --frames frames of the wall time of
// CellRenderer::render() with a GL_TIME_ELAPSED query around its GL work (render() waits for
// the result, so the frame's CPU work and GPU work are both in it); the query's GPU ms is a
// column of its own. Every frame is the same view; per-view work (sorts, classic projection,
// batches) is redone by every render() call. The first frame (shader compilation, a sort's
// per-mesh state, tables) is timed apart and left out of the median. Scanline: wall time of
// ScanlineRenderer::render() on all cores.
//
// Verified after timing: every frame finite and not empty where the reference is not, or the
// bench fails (a broken path cannot look fast or accurate).
//
// The night valley (content/scenes/fog_valley_night.json) is a scene of several volumes, drawn
// through terrain::SceneRenderer as one medium and compared with the scan-line reference of the
// volumes as intersecting grids: a row per path with the exact medium, then the froxel grid and
// the reduced resolutions (run_night_valley); the fog valley's scene (fog_valley.json) the same
// way at each resolution (run_fog_valley_scene).
//
// Writes into --out (default out/accuracy): accuracy.csv, accuracy.md (a table per scene),
// accuracy.png (time against error, one panel per scene, one labelled point per flavour, log
// axes; drawn by gnuplot from accuracy_plot.dat and accuracy.gp, both kept) and each scene's
// reference image (<scene>_reference_<model>.png).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>

#include "bench_support.hpp"
#include "commands.hpp"
#include "fx/camera.hpp"
#include "fx/cell_renderer.hpp"
#include "fx/effect.hpp"
#include "fx/error.hpp"
#include "harness/headless_context.hpp"
#include "fx/image.hpp"
#include "fx/mesh_io.hpp"
#include "fx/scanline_renderer.hpp"
#include "harness/synthetic_meshes.hpp"
#include "fx/transfer_function.hpp"
#include "fx/visibility_sort.hpp"
#include "io/output_file.hpp"
#include "options.hpp"
#include "terrain/continuous_lod.hpp"
#include "terrain/fog_layer.hpp"
#include "terrain/scene.hpp"
#include "terrain/scene_reference.hpp"
#include "terrain/scene_renderer.hpp"
#include "verify/image_difference.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {
namespace {

constexpr int kSupersample = 4; // the reference: 4×4 samples per pixel, box-filtered

// ---- scenes -------------------------------------------------------------------------------------

const fx::OpticalModel kModels[] = {fx::OpticalModel::Emission, fx::OpticalModel::Maximum,
                                    fx::OpticalModel::EmissionAbsorption};

const char* model_name(fx::OpticalModel m) {
    switch (m) {
    case fx::OpticalModel::Emission: return "emission";
    case fx::OpticalModel::Maximum: return "maximum";
    case fx::OpticalModel::EmissionAbsorption: return "emission-absorption";
    }
    return "?";
}
const char* model_short(fx::OpticalModel m) {
    switch (m) {
    case fx::OpticalModel::Emission: return "E";
    case fx::OpticalModel::Maximum: return "max";
    case fx::OpticalModel::EmissionAbsorption: return "EA";
    }
    return "?";
}

struct BenchScene {
    std::string id;   // for --scenes and file names
    std::string name; // for tables
    std::string note; // one line: what it is, how it was made
    fx::CellMesh mesh;
    std::string field;
    fx::Camera camera;
    int width = 256, height = 256;
    glm::dvec3 background{0.0};
    // Transfer function per optical model (index = kModels order); a model without one does not
    // fit the scene and is not compared.
    std::optional<fx::TransferFunction> tf[3];
    // Models whose colours are scaled after a first reference frame so that the reference peaks
    // at this value (emission: classic pcp's 8-bit target must not saturate; maximum: a bright
    // picture). 0: as given.
    double auto_peak[3] = {0.0, 0.0, 0.0};
};

int model_index(fx::OpticalModel m) {
    for (int i = 0; i < 3; ++i)
        if (kModels[i] == m) return i;
    return 0;
}

// Blue haze, green, then a denser red: extinction k per world unit at the top (normalized).
fx::TransferFunction glow(double k) {
    return fx::TransferFunction({{0.0, {0.10, 0.25, 0.90}, 0.1 * k},
                                 {0.5, {0.20, 0.90, 0.40}, 0.4 * k},
                                 {1.0, {1.00, 0.25, 0.10}, 1.0 * k}},
                                /*normalized=*/true);
}

fx::TransferFunction scale_colours(const fx::TransferFunction& tf, double k) {
    std::vector<fx::TransferPoint> points = tf.points();
    for (fx::TransferPoint& p : points) p.color *= k;
    return fx::TransferFunction(points, tf.normalized());
}

// The shipped blunt fin; quick mode keeps every other node along each axis (4,500 cells).
BenchScene blunt_fin_scene(const std::string& dir, bool quick) {
    BenchScene s;
    s.id = "blunt-fin";
    s.name = "blunt fin";
    fx::CellMesh full = fx::read_mesh(dir + "/bluntfinxyz.bin", dir + "/bluntfinq.bin");
    if (quick) {
        // A structured block, i fastest: keep nodes (2i, 2j, 2k) clamped to the last one.
        const std::array<std::uint32_t, 3> d = full.blocks.at(0).dims;
        const fx::ScalarField& q = *full.find_scalar("density");
        std::array<std::uint32_t, 3> n;
        for (int a = 0; a < 3; ++a) n[a] = (d[a] + 2) / 2;
        auto node = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
            i = std::min(2 * i, d[0] - 1), j = std::min(2 * j, d[1] - 1), k = std::min(2 * k, d[2] - 1);
            return std::size_t(k) * d[0] * d[1] + std::size_t(j) * d[0] + i;
        };
        fx::CellMesh coarse;
        fx::ScalarField density{"density", {}};
        for (std::uint32_t k = 0; k < n[2]; ++k)
            for (std::uint32_t j = 0; j < n[1]; ++j)
                for (std::uint32_t i = 0; i < n[0]; ++i) {
                    coarse.points.push_back(full.points[node(i, j, k)]);
                    density.values.push_back(q.values[node(i, j, k)]);
                }
        coarse.scalars.push_back(std::move(density));
        coarse.begin_block("blunt fin (every other node)", n);
        auto id = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) {
            return std::uint32_t((k * n[1] + j) * n[0] + i);
        };
        for (std::uint32_t k = 0; k + 1 < n[2]; ++k)
            for (std::uint32_t j = 0; j + 1 < n[1]; ++j)
                for (std::uint32_t i = 0; i + 1 < n[0]; ++i) {
                    const std::uint32_t v[8] = {id(i, j, k),     id(i + 1, j, k),     id(i + 1, j + 1, k),
                                                id(i, j + 1, k), id(i, j, k + 1),     id(i + 1, j, k + 1),
                                                id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)};
                    coarse.add_cell(fx::CellType::Hexahedron, v);
                }
        s.mesh = std::move(coarse);
    } else {
        s.mesh = std::move(full);
    }
    char note[160];
    std::snprintf(note, sizeof note, "NASA blunt fin (PLOT3D), %zu hexahedra%s, density", s.mesh.cell_count(),
                  quick ? " (every other node)" : "");
    s.note = note;
    s.field = "density";
    const fx::Bounds b = fx::mesh_bounds(s.mesh);
    s.camera = fx::Camera::framing(b.lo, b.hi, 40.0);
    s.width = quick ? 64 : 320, s.height = quick ? 40 : 200;
    const fx::TransferFunction base = glow(5.0 / glm::length(b.size())); // optical depth up to ~5 across
    for (int m = 0; m < 3; ++m) s.tf[m] = base;
    s.auto_peak[model_index(fx::OpticalModel::Emission)] = 0.8;
    s.auto_peak[model_index(fx::OpticalModel::Maximum)] = 0.9;
    return s;
}

// A finite-element-like mesh of ~`cells` tetrahedra: fx::make_curved_duct's duct cut into
// consistent tetrahedra. Non-convex: the view looks into the sector's gap, so rays cross one
// arm, leave the mesh and enter the far side.
BenchScene fem_scene(int cells) {
    BenchScene s;
    s.id = "fem";
    s.mesh = fx::make_curved_duct(std::size_t(cells), /*tetrahedra=*/true);
    const std::array<std::uint32_t, 3> nodes = s.mesh.blocks.front().dims;
    const std::uint32_t na = nodes[0] - 1, nr = nodes[1] - 1, nz = nodes[2] - 1;
    char text[200];
    std::snprintf(text, sizeof text, "FEM duct, %zu tetrahedra", s.mesh.cell_count());
    s.name = text;
    std::snprintf(text, sizeof text,
                  "240-degree curved duct, %ux%ux%u hexahedra cut into %zu consistent tetrahedra, smooth field",
                  na, nr, nz, s.mesh.cell_count());
    s.note = text;
    s.field = "temperature";
    s.camera.eye = {0.6, -4.6, 2.6};
    s.camera.target = {0.0, 0.25, 0.35};
    s.camera.up = {0, 0, 1};
    s.camera.fov_y_degrees = 40.0;
    s.camera.near_distance = 0.05;
    s.camera.far_distance = 100.0;
    s.width = s.height = cells < 100000 ? 48 : 256;
    const fx::TransferFunction base = glow(3.0); // optical depth ~2 through an arm, ~5 through both
    for (int m = 0; m < 3; ++m) s.tf[m] = base;
    s.auto_peak[model_index(fx::OpticalModel::Emission)] = 0.8;
    s.auto_peak[model_index(fx::OpticalModel::Maximum)] = 0.9;
    return s;
}

// The fog of content/scenes/fog_valley.json: the prisms terrain::SceneRenderer builds for the
// camera (the same LOD, fog map and density), rendered by every path directly, without the
// terrain surface (which the reference cannot draw and which is the same in every path).
// Emission–absorption uses that scene's transfer function, maximum that of
// fog_valley_mip.json (the same fog). Emission alone does not fit: the fog's optical depth
// reaches ~10 along these rays, and light that grows with τ without bound is not fog.
BenchScene fog_scene(bool inside, bool quick) {
    const std::string dir = std::string(CELLFX_SOURCE_DIR) + "/content/scenes/";
    const terrain::Scene scene = terrain::load_scene(dir + "fog_valley.json");
    const terrain::Scene mip_scene = terrain::load_scene(dir + "fog_valley_mip.json");
    if (!scene.fog || !mip_scene.fog) throw fx::Error("bench accuracy: the fog valley scenes have no fog");
    const terrain::FogSpec& fog = *scene.fog;
    BenchScene s;
    s.id = inside ? "fog-inside" : "fog-above";
    s.width = quick ? 64 : 320, s.height = quick ? 48 : 240;
    s.camera = scene.camera;
    if (inside) {
        // In the crater's fog, 35% of the way up the layer, looking east-north-east across it.
        const glm::dvec2 at(3950.0, 4450.0);
        const double ground = scene.ground.sample(at.x, at.y), thickness = fog.thickness.sample(at.x, at.y);
        if (!(thickness > 50.0)) throw fx::Error("bench accuracy: the fog-inside eye is not in the fog");
        s.camera.eye = {at.x, at.y, ground + 0.35 * thickness};
        s.camera.target = s.camera.eye + glm::dvec3(900.0, 450.0, -20.0);
        s.camera.up = {0, 0, 1};
    }
    terrain::ContinuousLod lod(scene.ground, fog.thickness, scene.lod);
    lod.update(terrain::LodView::from_camera(s.camera, s.height, quick ? 8.0 : scene.pixel_error));
    terrain::LodMesh lod_mesh;
    lod.extract(lod_mesh);
    s.mesh = terrain::build_layer_prisms(lod_mesh, fog.prisms);
    s.field = fog.prisms.scalar_name;
    // As SceneRenderer maps a normalized fog function: onto [0, the layer's largest density].
    if (fog.prisms.density != terrain::LayerDensity::LayerHeight)
        throw fx::Error("bench accuracy: fog_valley.json's density is expected to be layer_height");
    const double hi = fog.prisms.density_scale * fog.thickness.max_height();
    const fx::ScalarRange range{0.0f, float(hi)};
    s.tf[model_index(fx::OpticalModel::EmissionAbsorption)] =
        terrain::drawn_transfer_function(fog.transfer_function, fog.extinction_scale, range);
    s.tf[model_index(fx::OpticalModel::Maximum)] =
        terrain::drawn_transfer_function(mip_scene.fog->transfer_function, mip_scene.fog->extinction_scale, range);
    s.background = scene.background;
    s.name = inside ? "fog valley, inside" : "fog valley, from above";
    char note[200];
    std::snprintf(note, sizeof note, "fog_valley.json's fog prisms for this view (%zu prisms), %s", s.mesh.cell_count(),
                  inside ? "eye in the crater's fog, looking across it" : "the scene's camera");
    s.note = note;
    return s;
}

// One effect of a scene file (content/scenes/campfire.json's fire, searchlight.json's first
// beam) at scene time `time`, seen by the scene's camera at that time: its mesh in its own frame
// and the camera moved into that frame, as terrain::SceneRenderer draws it, without the terrain
// (the same in every path; the reference cannot draw it). The effect's transfer function, mapped
// onto its scalar range as the scene renderer maps it, serves every model: the effects are
// emissive, but their extinction is what absorb and the sorted paths would use.
BenchScene effect_scene(const std::string& id, const std::string& name, const std::string& file, double time,
                        bool quick) {
    const std::string path = std::string(CELLFX_SOURCE_DIR) + "/content/scenes/" + file;
    const terrain::Scene scene = terrain::load_scene(path);
    if (scene.effects.empty()) throw fx::Error("bench accuracy: " + path + " has no effects");
    const terrain::EffectSpec& spec = scene.effects.front();
    std::unique_ptr<fx::Effect> effect = terrain::make_effect(spec.params);
    BenchScene s;
    s.id = id;
    s.width = quick ? 64 : 320, s.height = quick ? 48 : 240;
    const fx::Camera world_camera = scene.camera_path ? scene.camera_path->at(time, scene.camera) : scene.camera;
    fx::EffectView view;
    view.camera = world_camera;
    view.viewport_width = s.width, view.viewport_height = s.height;
    view.time = time;
    effect->update(view);
    s.mesh = effect->mesh();
    if (s.mesh.cell_count() == 0) throw fx::Error("bench accuracy: " + path + ": " + spec.name + " built no cells");
    s.field = effect->scalar_name();
    s.camera = fx::camera_in_frame(world_camera, effect->transform());
    const fx::TransferFunction tf =
        terrain::drawn_transfer_function(spec.transfer_function, spec.extinction_scale, effect->scalar_range());
    for (int m = 0; m < 3; ++m) s.tf[m] = tf;
    // Scaled as on the other scenes: classic pcp's 8-bit target must not saturate, and the
    // brightest sample of the fire (2.4) or of a beam (0.08) is no picture for maximum.
    s.auto_peak[model_index(fx::OpticalModel::Emission)] = 0.8;
    s.auto_peak[model_index(fx::OpticalModel::Maximum)] = 0.9;
    s.background = scene.background;
    s.name = name;
    char text[240];
    std::snprintf(text, sizeof text, "%s's %s (%s, %zu cells) at t = %.1f s, the scene's camera", file.c_str(),
                  spec.name.c_str(), effect->type_name(), s.mesh.cell_count(), time);
    s.note = text;
    return s;
}

// ---- flavours -----------------------------------------------------------------------------------

struct Flavour {
    bool scanline = false;
    fx::RenderPath path = fx::RenderPath::PcpExact;
    bool fog = false;
    fx::SortMethod sort = fx::SortMethod::Xmpvo;
    bool sorted = false;
    fx::OpticalModel model = fx::OpticalModel::Emission;
    int family = 0; // plot colour
    std::string label() const {
        if (scanline) return std::string("scanline ") + model_short(model);
        std::string l = fx::render_path_name(path);
        if (fog) l += " fog";
        if (sorted) l += std::string(" ") + fx::sort_method_name(sort);
        return l;
    }
};

std::vector<Flavour> flavours() {
    std::vector<Flavour> list;
    for (fx::OpticalModel m : kModels) {
        Flavour f;
        f.scanline = true, f.model = m, f.family = 1;
        list.push_back(f);
    }
    auto gpu = [&](fx::RenderPath p, fx::OpticalModel m, int family, bool fog = false) {
        Flavour f;
        f.path = p, f.model = m, f.family = family, f.fog = fog;
        list.push_back(f);
    };
    gpu(fx::RenderPath::Pcp, fx::OpticalModel::Emission, 2);
    gpu(fx::RenderPath::PcpExact, fx::OpticalModel::Emission, 3);
    gpu(fx::RenderPath::PcpExact, fx::OpticalModel::EmissionAbsorption, 4, true);
    gpu(fx::RenderPath::Mip, fx::OpticalModel::Maximum, 5);
    for (fx::RenderPath p : {fx::RenderPath::Absorption, fx::RenderPath::AbsorptionExact})
        for (fx::SortMethod sort : fx::all_sort_methods()) {
            Flavour f;
            f.path = p, f.model = fx::OpticalModel::EmissionAbsorption, f.sort = sort, f.sorted = true;
            f.family = p == fx::RenderPath::Absorption ? 6 : 7;
            list.push_back(f);
        }
    return list;
}

// ---- images and errors --------------------------------------------------------------------------

fx::Image box_filter(const fx::Image& big, int factor) {
    fx::Image out(big.width / factor, big.height / factor);
    const float w = 1.0f / float(factor * factor);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) {
            glm::vec4 sum(0.0f);
            for (int j = 0; j < factor; ++j)
                for (int i = 0; i < factor; ++i) sum += big.at(x * factor + i, y * factor + j);
            out.at(x, y) = sum * w;
        }
    return out;
}

struct ImageError {
    double rmse = 0.0, max_abs = 0.0, psnr = 0.0;
    bool finite = true;
};

// The picture a user sees — both frames composited over the scene's background — compared in
// RGB (1 = white).
ImageError image_error(const fx::Image& actual, const fx::Image& reference, const glm::dvec3& background) {
    fx::Image shown = actual, expected = reference;
    fx::composite_over(shown, glm::vec3(background));
    fx::composite_over(expected, glm::vec3(background));
    verify::Options rgb;
    rgb.channels = 3;
    const verify::Difference d = verify::measure(shown, expected, rgb);
    ImageError e;
    e.rmse = d.rms, e.max_abs = d.worst.delta, e.psnr = d.psnr(), e.finite = d.nonfinite == 0;
    return e;
}

// The largest colour value (RGB).
double peak_of(const fx::Image& img) {
    verify::Options rgb;
    rgb.channels = 3;
    return verify::peak(img, rgb);
}

// Pixels the reference covers (any channel above 1e-4 of its peak) that the frame leaves at 0.
double uncovered_fraction(const fx::Image& actual, const fx::Image& reference) {
    const double floor = 1e-4 * std::max(peak_of(reference), 1e-30);
    std::size_t covered = 0, missed = 0;
    for (std::size_t i = 0; i < actual.pixels.size(); ++i) {
        const glm::vec4& r = reference.pixels[i];
        if (std::max({r.r, r.g, r.b, r.a}) <= floor) continue;
        ++covered;
        const glm::vec4& a = actual.pixels[i];
        missed += std::max({a.r, a.g, a.b, a.a}) <= 0.0f;
    }
    return covered ? double(missed) / double(covered) : 0.0;
}

// ---- results ------------------------------------------------------------------------------------

struct Row {
    std::string scene_id, scene, flavour, path, sort, model;
    int family = 0, width = 0, height = 0, frames = 0;
    std::size_t cells = 0;
    double frame_ms = 0.0, gpu_ms = -1.0, first_ms = 0.0;
    ImageError error;       // against the 4×4 reference
    ImageError point_error; // against the 1-sample reference
    double reference_peak = 0.0;
    int point = 0; // gnuplot point type (0: by the visibility sort)
};

std::string csv_number(double v) {
    if (!std::isfinite(v)) return v > 0 ? "inf" : "nan";
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return b;
}

void write_csv(const std::string& path, const std::vector<Row>& rows) {
    std::ostringstream out;
    out << "scene,flavour,path,sort,model,width,height,cells,frames,frame_ms,gpu_ms,first_frame_ms,rmse,max_abs,"
           "psnr_db,rmse_1spp,max_abs_1spp,reference_peak\n";
    for (const Row& r : rows)
        out << r.scene_id << ',' << r.flavour << ',' << r.path << ',' << r.sort << ',' << r.model << ',' << r.width
            << ',' << r.height << ',' << r.cells << ',' << r.frames << ',' << csv_number(r.frame_ms) << ','
            << (r.gpu_ms < 0.0 ? std::string() : csv_number(r.gpu_ms)) << ',' << csv_number(r.first_ms) << ','
            << csv_number(r.error.rmse) << ',' << csv_number(r.error.max_abs) << ',' << csv_number(r.error.psnr) << ','
            << csv_number(r.point_error.rmse) << ',' << csv_number(r.point_error.max_abs) << ','
            << csv_number(r.reference_peak) << '\n';
    fx::io::write_output_file(path, out.str());
}

std::string fixed(double v, int digits) {
    char b[32];
    std::snprintf(b, sizeof b, "%.*f", digits, v);
    return b;
}
std::string sci(double v) {
    if (v == 0.0) return "0";
    char b[32];
    std::snprintf(b, sizeof b, "%.2g", v);
    std::string s = b;
    // 1.2e-05 → 1.2e-5
    const std::size_t e = s.find('e');
    if (e != std::string::npos) {
        std::string mant = s.substr(0, e), exp = s.substr(e + 1);
        const bool neg = exp[0] == '-';
        exp = exp.substr(exp[0] == '-' || exp[0] == '+' ? 1 : 0);
        while (exp.size() > 1 && exp[0] == '0') exp.erase(0, 1);
        s = mant + "e" + (neg ? "-" : "") + exp;
    }
    return s;
}
std::string ms_text(double ms) { return ms >= 100.0 ? fixed(ms, 0) : ms >= 10.0 ? fixed(ms, 1) : fixed(ms, 2); }

void write_markdown(const std::string& path, const std::vector<BenchScene>& scenes, const std::vector<Row>& rows,
                    const std::string& header) {
    std::ostringstream out;
    out << header << "\n";
    for (const BenchScene& s : scenes) {
        out << "\n### " << s.name << "\n\n" << s.note << "; " << s.width << "×" << s.height << ".\n\n";
        out << "| flavour | model | ms/frame | GPU ms | first frame ms | RMSE | max abs | PSNR dB | RMSE, 1 spp |\n";
        out << "| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |\n";
        for (const Row& r : rows) {
            if (r.scene_id != s.id) continue;
            out << "| " << r.flavour << " | " << r.model << " | " << ms_text(r.frame_ms) << " | "
                << (r.gpu_ms < 0.0 ? std::string("—") : ms_text(r.gpu_ms)) << " | "
                << (r.first_ms > 0.0 ? ms_text(r.first_ms) : std::string("—")) << " | " << sci(r.error.rmse) << " | "
                << sci(r.error.max_abs) << " | " << fixed(r.error.psnr, 1) << " | " << sci(r.point_error.rmse)
                << " |\n";
        }
    }
    fx::io::write_output_file(path, out.str());
}

// gnuplot: one panel per scene, x = ms per frame, y = RMSE, both logarithmic; colour = path,
// symbol = visibility sort (absorption paths) — the four sorts of one path often land close
// together, so one label names the path beside its default sort (xmpvo). Two figures:
// accuracy.png against the 4×4 reference, accuracy_1spp.png against the 1-sample one (the
// scan-line rows are 0 there and left out).
void write_plot(const std::string& dir, const std::vector<BenchScene>& scenes, const std::vector<Row>& rows,
                const std::string& title) {
    auto point_type = [](const Row& r) {
        if (r.point != 0) return r.point;                // the effects' resolution (scene-file rows)
        if (r.path == "scanline") return 5;              // filled square
        if (r.sort.empty()) return 7;                    // filled circle
        static const char* sorts[] = {"centroid", "mpvo", "xmpvo", "power"};
        static const int types[] = {6, 4, 9, 13};        // open circle, open square, triangle, diamond
        for (int k = 0; k < 4; ++k)
            if (r.sort == sorts[k]) return types[k];
        return 7;
    };
    {
        std::ostringstream data;
        data << "# ms_per_frame rmse rmse_1spp family point_type label label_lift (one block per scene: " << scenes.size()
             << ")\n";
        for (const BenchScene& s : scenes) {
            data << "# " << s.name << "\n";
            for (const Row& r : rows) {
                if (r.scene_id != s.id) continue;
                const bool labelled = (r.sort.empty() || r.sort == "xmpvo");
                const std::string label = r.sort.empty() ? r.flavour : r.path;
                // Where exact flavours meet at the sampling floor, their labels would print on top
                // of each other: each family's label sits a little higher or lower.
                static const double lift[] = {1.0, 1.0, 1.0, 1.0, 0.78, 1.0, 1.3, 0.62, 1.0};
                data << csv_number(r.frame_ms) << ' ' << csv_number(r.error.rmse) << ' '
                     << csv_number(r.point_error.rmse) << ' ' << r.family << ' ' << point_type(r) << " \""
                     << (labelled ? label : std::string()) << "\" " << lift[r.family] << "\n";
            }
            data << "\n\n";
        }
        fx::io::write_output_file(dir + "/accuracy_plot.dat", data.str());
    }
    const int columns = scenes.size() <= 2 ? int(scenes.size()) : scenes.size() <= 4 ? 2 : 3;
    const int rows_n = int((scenes.size() + std::size_t(columns) - 1) / std::size_t(columns));
    std::ostringstream gp;
    gp << "# Written by cellfx bench accuracy; run with: gnuplot accuracy.gp (in this folder)\n"
       << "# (cellfx itself sets the two output names to temporaries, renamed once gnuplot succeeds)\n"
       << "if (!exists('accuracy_png')) accuracy_png = 'accuracy.png'\n"
       << "if (!exists('accuracy_1spp_png')) accuracy_1spp_png = 'accuracy_1spp.png'\n"
       << "set terminal pngcairo size " << 560 * columns << "," << 470 * rows_n + 40 << " font 'DejaVu Sans,10'\n"
       << "set logscale xy\nset format y '10^{%L}'\nset format x '10^{%L}'\n"
       << "set grid xtics ytics lc rgb '#dddddd'\nset xlabel 'ms per frame (median)'\n"
       << "set offsets graph 0.05, graph 0.35, graph 0.15, graph 0.15\n"
       << "set key top left font ',8' samplen 1 spacing 0.9 box opaque\n"
       << "set linetype 1 lc rgb '#000000'\n" // scanline
       << "set linetype 2 lc rgb '#d62728'\n" // pcp
       << "set linetype 3 lc rgb '#ff7f0e'\n" // pcp-exact
       << "set linetype 4 lc rgb '#8c564b'\n" // pcp-exact fog
       << "set linetype 5 lc rgb '#9467bd'\n" // mip
       << "set linetype 6 lc rgb '#1f77b4'\n" // absorption
       << "set linetype 7 lc rgb '#2ca02c'\n" // absorption-exact
       << "set linetype 8 lc rgb '#17becf'\n" // the froxel medium
       << "sorts = \"NaN w p pt 6 lc rgb 'gray40' t 'centroid', NaN w p pt 4 lc rgb 'gray40' t 'mpvo', "
          "NaN w p pt 9 lc rgb 'gray40' t 'xmpvo', NaN w p pt 13 lc rgb 'gray40' t 'power', "
          "NaN w p pt 11 lc rgb 'gray40' t 'fx scale 1/2', NaN w p pt 15 lc rgb 'gray40' t 'fx scale 1/4'\"\n";
    for (int figure = 0; figure < 2; ++figure) {
        const int column = figure == 0 ? 2 : 3;
        gp << "\nset output " << (figure == 0 ? "accuracy_png" : "accuracy_1spp_png") << "\n"
           << "set ylabel '" << (figure == 0 ? "RMSE against the 4x4 scan-line reference"
                                             : "RMSE against the 1-sample scan-line reference")
           << "'\n"
           << "set multiplot layout " << rows_n << "," << columns << " title '" << title
           << (figure == 0 ? "" : " (error at the pixel centres: scan-line rows are 0)") << "'\n";
        for (std::size_t i = 0; i < scenes.size(); ++i) {
            gp << "set title '" << scenes[i].name << " (" << scenes[i].width << "x" << scenes[i].height << ")'\n"
               << "plot 'accuracy_plot.dat' index " << i << " using 1:" << column
               << ":5:4 with points ps 1.4 lw 1.5 pt variable lc variable notitle, \\\n"
               << "     '' index " << i << " using ($1*1.15):($" << column << (figure == 0 ? "*$7" : "")
               << "):6:4 with labels left font ',8' tc variable notitle, @sorts\n";
        }
        gp << "unset multiplot\n";
    }
    fx::io::write_output_file(dir + "/accuracy.gp", gp.str());
}

std::string shell_quoted(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

// gnuplot draws the two figures into temporaries in `dir`, renamed over accuracy.png and
// accuracy_1spp.png only when it succeeded: a failed plot leaves the last good figures.
void draw_plot(const std::string& dir) {
    if (std::system("command -v gnuplot >/dev/null 2>&1") != 0)
        throw fx::Error("bench accuracy: gnuplot not found, so " + dir +
                        "/accuracy.png was not drawn (scripts/setup.sh installs gnuplot-nox)");
    fx::io::OutputFile png(dir + "/accuracy.png"), png_1spp(dir + "/accuracy_1spp.png");
    const auto name = [](const fx::io::OutputFile& f) {
        const std::string& p = f.temporary_path();
        return p.substr(p.find_last_of('/') + 1);
    };
    const std::string plot = "cd " + shell_quoted(dir) + " && gnuplot -e " +
                             shell_quoted("accuracy_png = '" + name(png) + "'; accuracy_1spp_png = '" + name(png_1spp) + "'") +
                             " accuracy.gp";
    if (std::system(plot.c_str()) != 0) throw fx::Error("bench accuracy: '" + plot + "' failed");
    png.commit();
    png_1spp.commit();
}

// ---- rendering ----------------------------------------------------------------------------------

struct Options {
    int frames = 5;
    bool quick = false;
    std::string out = "out/accuracy";
    std::string blunt_fin;
    int fem_cells = 1000000;
    std::string scenes = "blunt-fin,fem,fog-above,fog-inside,campfire,searchlight,night-valley,fog-valley-scales";
    bool images = false; // every flavour's last frame as <scene>_<flavour>.png
    std::string command;
};

struct References {
    std::optional<fx::Image> supersampled[3], point[3]; // by model index
};

void run_scene(BenchScene& s, const Options& o, std::vector<Row>& rows, bool& failed) {
    std::printf("\n%s: %s; %dx%d\n", s.name.c_str(), s.note.c_str(), s.width, s.height);
    const fx::ScalarField* field = s.mesh.find_scalar(s.field);
    if (!field) throw fx::Error("bench accuracy: scene " + s.id + " has no field " + s.field);
    const fx::ScanlineRenderer scanline(s.mesh);
    References refs;
    for (int m = 0; m < 3; ++m) {
        if (!s.tf[m]) continue;
        fx::ScanlineOptions so;
        so.model = kModels[m];
        if (s.auto_peak[m] > 0.0) {
            const double peak = peak_of(scanline.render(s.camera, s.width, s.height, *field, *s.tf[m], so));
            if (!(peak > 0.0)) throw fx::Error("bench accuracy: scene " + s.id + " shows nothing with " + model_name(kModels[m]));
            s.tf[m] = scale_colours(*s.tf[m], s.auto_peak[m] / peak);
        }
        const auto t0 = Clock::now();
        const fx::Image big =
            scanline.render(s.camera, kSupersample * s.width, kSupersample * s.height, *field, *s.tf[m], so);
        refs.supersampled[m] = box_filter(big, kSupersample);
        std::printf("  reference %-19s %dx%d in %.1f s, peak %.3f\n", model_name(kModels[m]), kSupersample * s.width,
                    kSupersample * s.height, ms_since(t0) * 1e-3, peak_of(*refs.supersampled[m]));
        fx::Image shown = *refs.supersampled[m];
        fx::composite_over(shown, s.background);
        fx::write_png(shown, o.out + "/" + s.id + "_reference_" + model_short(kModels[m]) + ".png");
    }
    std::printf("  %-26s %-20s %9s %9s %9s %10s %10s %8s %10s\n", "flavour", "model", "ms/frame", "gpu ms", "first ms",
                "rmse", "max abs", "psnr dB", "rmse 1spp");

    std::optional<fx::CellRenderer> renderer;
    int renderer_tf = -1;
    for (const Flavour& f : flavours()) {
        const int m = model_index(f.model);
        if (!s.tf[m]) continue;
        Row row;
        row.scene_id = s.id, row.scene = s.name, row.flavour = f.label(), row.family = f.family;
        row.path = f.scanline ? "scanline" : fx::render_path_name(f.path);
        row.sort = f.sorted ? fx::sort_method_name(f.sort) : "";
        row.model = model_name(f.model);
        row.width = s.width, row.height = s.height, row.cells = s.mesh.cell_count(), row.frames = o.frames;
        fx::Image image;
        std::vector<double> wall, gpu;
        if (f.scanline) {
            fx::ScanlineOptions so;
            so.model = f.model;
            for (int i = 0; i < o.frames; ++i) {
                fx::ScanlineStats stats;
                image = scanline.render(s.camera, s.width, s.height, *field, *s.tf[m], so, &stats);
                wall.push_back(1e3 * stats.seconds_total);
            }
            refs.point[m] = image;
        } else {
            if (!renderer) renderer.emplace(s.mesh, s.field, *s.tf[m]);
            else if (renderer_tf != m) renderer->set_transfer_function(*s.tf[m]);
            renderer_tf = m;
            fx::CellRenderOptions options;
            options.fog = f.fog;
            options.sort = f.sort;
            options.timing = true;
            fx::CellRenderStats stats;
            renderer->render_to_image(s.camera, s.width, s.height, f.path, options, &stats); // first frame
            row.first_ms = stats.cpu_ms;
            for (int i = 0; i < o.frames; ++i) {
                image = renderer->render_to_image(s.camera, s.width, s.height, f.path, options, &stats);
                wall.push_back(stats.cpu_ms); // render(): CPU work + GL work, waited for by the query
                gpu.push_back(stats.gpu_ms);
            }
        }
        row.frame_ms = median(wall);
        row.gpu_ms = gpu.empty() ? -1.0 : median(gpu);
        row.error = image_error(image, *refs.supersampled[m], s.background);
        // The 1-sample reference of this model: the scan-line rows come first in flavours().
        row.point_error = image_error(image, refs.point[m] ? *refs.point[m] : image, s.background);
        row.reference_peak = peak_of(*refs.supersampled[m]);
        if (o.images) {
            fx::Image shown = image;
            fx::composite_over(shown, s.background);
            std::string name = row.flavour;
            std::replace(name.begin(), name.end(), ' ', '_');
            fx::write_png(shown, o.out + "/" + s.id + "_" + name + ".png");
        }
        // Verify after timing.
        const double missed = uncovered_fraction(image, *refs.supersampled[m]);
        const bool ok = row.error.finite && peak_of(image) > 0.0 && missed < 0.5;
        std::printf("  %-26s %-20s %9s %9s %9s %10.3g %10.3g %8.1f %10.3g%s\n", row.flavour.c_str(), row.model.c_str(),
                    ms_text(row.frame_ms).c_str(), row.gpu_ms < 0.0 ? "-" : ms_text(row.gpu_ms).c_str(),
                    row.first_ms > 0.0 ? ms_text(row.first_ms).c_str() : "-", row.error.rmse, row.error.max_abs,
                    row.error.psnr, row.point_error.rmse, ok ? "" : "   FAILED verification");
        if (!ok) {
            std::printf("    (finite %d, peak %.3g, %.0f%% of the reference's covered pixels left empty)\n",
                        int(row.error.finite), peak_of(image), 100.0 * missed);
            failed = true;
        }
        std::fflush(stdout);
        rows.push_back(std::move(row));
    }
}

// ---- scene files through terrain::SceneRenderer: the one medium and the effects' resolution ------

// A scene file at t = 0 from its camera through terrain::SceneRenderer (the terrain not drawn:
// the reference cannot draw it), against the scan-line reference of the same volumes as
// intersecting grids (terrain/scene_reference.hpp) with each path's optical model — pcp emission,
// mip maximum; pcp-exact the one medium as the scene declares it (fire and beam emissive only);
// the sorted paths the one medium with every volume absorbing, as they draw it.
//   night valley (content/scenes/fog_valley_night.json): fog, campfire, smoke and search light —
//     every path with the exact medium, then pcp-exact with the froxel grid and at the reduced
//     resolutions (fx_scale 1/2, 1/4) with either medium;
//   fog valley (content/scenes/fog_valley.json): its fog alone (no medium) with pcp-exact at
//     each resolution.
struct SceneRow {
    fx::RenderPath path;
    fx::MediumMethod medium;
    double fx_scale;
    const char* model;
    int family;
};

std::string scale_suffix(double scale) { return scale == 1.0 ? "" : scale == 0.5 ? " 1/2" : " 1/4"; }

void run_scene_file(const Options& o, const std::string& id, const std::string& name, const std::string& file,
                    const std::vector<SceneRow>& flavours, std::vector<BenchScene>& scenes, std::vector<Row>& rows, bool& failed) {
    BenchScene s;
    s.id = id;
    s.name = name;
    s.width = o.quick ? 64 : 320, s.height = o.quick ? 48 : 240;
    const terrain::Scene scene = terrain::load_scene(std::string(CELLFX_SOURCE_DIR) + "/content/scenes/" + file);
    const fx::Camera camera = scene.camera_path ? scene.camera_path->at(0.0, scene.camera) : scene.camera;
    s.background = scene.background;
    terrain::SceneRenderer r(scene);
    r.set_terrain_drawn(false);
    r.set_time(0.0);
    r.update(0.0, camera, s.width, s.height);
    std::size_t cells = 0;
    std::string volumes;
    for (const terrain::SceneRenderer::DrawnVolume& v : r.drawn_volumes()) {
        cells += v.effect->mesh().cell_count();
        volumes += (volumes.empty() ? "" : ", ") + v.name;
    }
    char note[320];
    std::snprintf(note, sizeof note,
                  "%s at t = 0: %s (%zu cells), one path for all, terrain not drawn; reference: the volumes as intersecting "
                  "grids; \"froxel\": the bounded medium, \"1/2\", \"1/4\": the effects' resolution (fx_scale)",
                  file.c_str(), volumes.c_str(), cells);
    s.note = note;
    std::printf("\n%s: %s; %dx%d\n", s.name.c_str(), s.note.c_str(), s.width, s.height);

    // The reference for the model `path` draws (its 4×4 and 1-sample frames).
    struct Reference {
        fx::Image supersampled, point;
    };
    auto reference = [&](fx::RenderPath path, const char* label) {
        for (const std::string& effect : r.effect_names()) r.set_path(effect, path);
        r.update(0.0, camera, s.width, s.height); // the meshes of this size's LOD
        Reference ref;
        const auto t0 = Clock::now();
        ref.supersampled = box_filter(terrain::render_scene_reference(r, camera, kSupersample * s.width, kSupersample * s.height),
                                      kSupersample);
        std::printf("  reference %-30s %dx%d in %.1f s, peak %.3f\n", label, kSupersample * s.width, kSupersample * s.height,
                    ms_since(t0) * 1e-3, peak_of(ref.supersampled));
        fx::Image shown = ref.supersampled;
        fx::composite_over(shown, s.background);
        fx::write_png(shown, o.out + "/" + s.id + "_reference_" + fx::render_path_name(path) + ".png");
        return ref;
    };
    std::printf("  %-26s %-20s %9s %9s %9s %10s %10s %8s %10s\n", "flavour", "model", "ms/frame", "gpu ms", "first ms",
                "rmse", "max abs", "psnr dB", "rmse 1spp");
    std::map<std::string, Reference> references; // by model: the sorted paths share theirs
    for (const SceneRow& p : flavours) {
        const bool sorted = p.path == fx::RenderPath::Absorption || p.path == fx::RenderPath::AbsorptionExact;
        if (!references.count(p.model)) {
            Reference ref = reference(p.path, p.model);
            // The scan-line reference at one sample per pixel, timed, as its own row.
            Row row;
            row.scene_id = s.id, row.scene = s.name, row.family = 1, row.path = "scanline", row.model = p.model;
            row.flavour = p.path == fx::RenderPath::Pcp ? "scanline E" : p.path == fx::RenderPath::Mip ? "scanline max"
                          : sorted ? "scanline EA (all absorb)" : "scanline EA";
            row.width = s.width, row.height = s.height, row.cells = cells, row.frames = o.frames;
            std::vector<double> wall;
            for (int i = 0; i < o.frames; ++i) {
                const auto t0 = Clock::now();
                ref.point = terrain::render_scene_reference(r, camera, s.width, s.height);
                wall.push_back(ms_since(t0));
            }
            row.frame_ms = median(wall);
            row.error = image_error(ref.point, ref.supersampled, s.background);
            row.reference_peak = peak_of(ref.supersampled);
            std::printf("  %-26s %-20s %9s %9s %9s %10.3g %10.3g %8.1f %10.3g\n", row.flavour.c_str(), row.model.c_str(),
                        ms_text(row.frame_ms).c_str(), "-", "-", row.error.rmse, row.error.max_abs, row.error.psnr, 0.0);
            rows.push_back(row);
            references[p.model] = std::move(ref);
        }
        const Reference& ref = references[p.model];
        Row row;
        row.scene_id = s.id, row.scene = s.name, row.family = p.family, row.path = fx::render_path_name(p.path);
        row.model = p.model;
        row.point = p.fx_scale == 1.0 ? 7 : p.fx_scale == 0.5 ? 11 : 15; // circle, triangle down, pentagon
        row.width = s.width, row.height = s.height, row.cells = cells, row.frames = o.frames;
        for (const std::string& effect : r.effect_names()) r.set_path(effect, p.path);
        r.set_medium_method(p.medium);
        r.set_fx_scale(p.fx_scale);
        r.set_timing(true);
        terrain::FrameStats stats;
        auto t0 = Clock::now();
        fx::Image image = r.render_to_image(camera, s.width, s.height, &stats); // first frame
        row.first_ms = ms_since(t0);
        std::vector<double> wall, gpu;
        for (int i = 0; i < o.frames; ++i) {
            t0 = Clock::now();
            image = r.render_to_image(camera, s.width, s.height, &stats);
            wall.push_back(ms_since(t0));
            gpu.push_back(stats.gpu_ms);
        }
        r.set_timing(false);
        // Named by what ran: "froxel" where the grid integrated overlapping volumes.
        const bool froxel = stats.medium.pixels > 0 && stats.medium.method == fx::MediumMethod::Froxel;
        row.flavour = row.path + (froxel ? " froxel" : "") + scale_suffix(p.fx_scale);
        // The frame is opaque (over the background), the references premultiplied: image_error
        // compares what is displayed.
        row.frame_ms = median(wall);
        row.gpu_ms = median(gpu);
        row.error = image_error(image, ref.supersampled, s.background);
        row.point_error = image_error(image, ref.point, s.background);
        row.reference_peak = peak_of(ref.supersampled);
        if (o.images) {
            std::string file_name = row.flavour;
            std::replace(file_name.begin(), file_name.end(), ' ', '_');
            std::replace(file_name.begin(), file_name.end(), '/', '-');
            fx::write_png(image, o.out + "/" + s.id + "_" + file_name + ".png");
        }
        // Verified: finite, and the volumes there (a tenth of the pixels off the background).
        std::size_t shown = 0;
        for (const glm::vec4& px : image.pixels)
            shown += glm::length(glm::dvec3(px) - s.background) > 1e-3 ? 1 : 0;
        const bool ok = row.error.finite && shown > image.pixels.size() / 10;
        std::printf("  %-26s %-20s %9s %9s %9s %10.3g %10.3g %8.1f %10.3g%s\n", row.flavour.c_str(), row.model.c_str(),
                    ms_text(row.frame_ms).c_str(), ms_text(row.gpu_ms).c_str(), ms_text(row.first_ms).c_str(), row.error.rmse,
                    row.error.max_abs, row.error.psnr, row.point_error.rmse, ok ? "" : "   FAILED verification");
        if (!ok) failed = true;
        std::fflush(stdout);
        rows.push_back(std::move(row));
    }
    scenes.push_back(std::move(s));
}

void run_night_valley(const Options& o, std::vector<BenchScene>& scenes, std::vector<Row>& rows, bool& failed) {
    using fx::MediumMethod;
    using fx::RenderPath;
    const char* medium = "one medium";
    const char* all_absorb = "one medium (all absorb)";
    run_scene_file(o, "night-valley", "night valley", "fog_valley_night.json",
                   {{RenderPath::Pcp, MediumMethod::Exact, 1.0, "emission", 2},
                    {RenderPath::PcpExact, MediumMethod::Exact, 1.0, medium, 3},
                    {RenderPath::Mip, MediumMethod::Exact, 1.0, "maximum", 5},
                    {RenderPath::Absorption, MediumMethod::Exact, 1.0, all_absorb, 6},
                    {RenderPath::AbsorptionExact, MediumMethod::Exact, 1.0, all_absorb, 7},
                    {RenderPath::PcpExact, MediumMethod::Froxel, 1.0, medium, 8},
                    {RenderPath::AbsorptionExact, MediumMethod::Froxel, 1.0, all_absorb, 8},
                    {RenderPath::PcpExact, MediumMethod::Exact, 0.5, medium, 3},
                    {RenderPath::PcpExact, MediumMethod::Exact, 0.25, medium, 3},
                    {RenderPath::PcpExact, MediumMethod::Froxel, 0.5, medium, 8},
                    {RenderPath::PcpExact, MediumMethod::Froxel, 0.25, medium, 8}},
                   scenes, rows, failed);
}

void run_fog_valley_scene(const Options& o, std::vector<BenchScene>& scenes, std::vector<Row>& rows, bool& failed) {
    using fx::MediumMethod;
    using fx::RenderPath;
    const char* model = "emission-absorption";
    run_scene_file(o, "fog-valley-scales", "fog valley at each resolution", "fog_valley.json",
                   {{RenderPath::PcpExact, MediumMethod::Froxel, 1.0, model, 3},
                    {RenderPath::PcpExact, MediumMethod::Froxel, 0.5, model, 3},
                    {RenderPath::PcpExact, MediumMethod::Froxel, 0.25, model, 3}},
                   scenes, rows, failed);
}

std::string cpu_name() {
    std::ifstream in("/proc/cpuinfo");
    for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0) {
            const std::size_t colon = line.find(':');
            if (colon != std::string::npos) return line.substr(colon + 2);
        }
    return "unknown CPU";
}

} // namespace

int bench_accuracy(const std::vector<std::string>& args) {
    const ParsedArgs parsed = parse_args(args, {"quick", "images"});
    require_known(parsed, {"quick", "images", "frames", "out", "scenes", "blunt-fin", "fem-cells"});
    if (!parsed.positional.empty()) throw fx::Error("bench accuracy: unexpected argument '" + parsed.positional[0] + "'");
    Options o;
    o.quick = parsed.has("quick");
    o.images = parsed.has("images");
    o.frames = int_option(parsed, "bench accuracy", "frames", o.quick ? 1 : 5);
    o.fem_cells = int_option(parsed, "bench accuracy", "fem-cells", o.quick ? 20000 : 1000000);
    o.out = parsed.get("out", o.out);
    o.scenes = parsed.get("scenes", o.scenes);
    o.blunt_fin = parsed.get("blunt-fin", std::string(CELLFX_SOURCE_DIR) + "/content/meshes/blunt_fin");
    o.command = "cellfx bench accuracy";
    for (const std::string& a : args) o.command += " " + a;
    const std::vector<std::string> wanted = split_list(o.scenes);
    for (const std::string& item : wanted)
        if (item != "blunt-fin" && item != "fem" && item != "fog-above" && item != "fog-inside" && item != "campfire" &&
            item != "searchlight" && item != "night-valley" && item != "fog-valley-scales")
            throw fx::Error("bench accuracy: --scenes: unknown scene '" + item +
                            "' (expected blunt-fin, fem, fog-above, fog-inside, campfire, searchlight, night-valley, "
                            "fog-valley-scales)");
    // The folder is made and tried now, not after the run: a read-only or mistyped --out is
    // an error before the first frame.
    fx::io::create_output_folder(o.out);
    fx::io::check_output_file(o.out + "/accuracy.csv");

    const fx::HeadlessContext context;
    const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
    const std::string machine =
        context.description() + "; " + cpu_name() + ", " + std::to_string(threads) + " CPU threads";
    std::printf("accuracy against time: every path and flavour against the scan-line reference (%dx%d samples per pixel)\n"
                "  %s\n  %s, %d timed frames per flavour (median)\n",
                kSupersample, kSupersample, machine.c_str(), o.quick ? "quick mode (small meshes and images)" : "full run",
                o.frames);

    std::vector<BenchScene> scenes;
    for (const std::string& id : wanted) {
        if (id == "night-valley" || id == "fog-valley-scales") continue; // scene files: run apart, below
        const auto t0 = Clock::now();
        if (id == "blunt-fin") scenes.push_back(blunt_fin_scene(o.blunt_fin, o.quick));
        if (id == "fem") scenes.push_back(fem_scene(o.fem_cells));
        if (id == "fog-above") scenes.push_back(fog_scene(false, o.quick));
        if (id == "fog-inside") scenes.push_back(fog_scene(true, o.quick));
        if (id == "campfire") scenes.push_back(effect_scene(id, "campfire", "campfire.json", 2.0, o.quick));
        if (id == "searchlight") scenes.push_back(effect_scene(id, "search light", "searchlight.json", 2.0, o.quick));
        std::printf("  scene %s built in %.2f s\n", id.c_str(), ms_since(t0) * 1e-3);
    }
    std::vector<Row> rows;
    bool failed = false;
    for (BenchScene& s : scenes) run_scene(s, o, rows, failed);
    if (std::find(wanted.begin(), wanted.end(), "night-valley") != wanted.end()) run_night_valley(o, scenes, rows, failed);
    if (std::find(wanted.begin(), wanted.end(), "fog-valley-scales") != wanted.end())
        run_fog_valley_scene(o, scenes, rows, failed);

    std::ostringstream header;
    header << "Made by `" << o.command << "` on " << machine << "; " << o.frames
           << " timed frames per flavour (median), the first frame apart. Errors: the frame composited over the "
              "scene's background against the scan-line reference of the same model at "
           << kSupersample << "x" << kSupersample
           << " samples per pixel, box-filtered; RGB, linear, 1 = white; PSNR = 10 log10(1/MSE). \"RMSE, 1 spp\": "
              "against the reference at one sample per pixel (the pixel centres every path samples).";
    write_csv(o.out + "/accuracy.csv", rows);
    write_markdown(o.out + "/accuracy.md", scenes, rows, header.str());
    write_plot(o.out, scenes, rows,
               std::string("cellfx: ms per frame against error") + (o.quick ? " (quick mode)" : "") + " - " +
                   context.renderer());
    std::printf("\nwrote %s/accuracy.csv, accuracy.md, accuracy_plot.dat, accuracy.gp\n", o.out.c_str());
    draw_plot(o.out);
    std::printf("wrote %s/accuracy.png, accuracy_1spp.png\n", o.out.c_str());
    if (failed) throw fx::Error("bench accuracy: some frames failed verification");
    return 0;
}

} // namespace cellfx_cli
