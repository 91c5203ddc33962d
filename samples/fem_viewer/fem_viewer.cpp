// The fem_viewer sample: a finite-element mesh (any file fx::read_mesh reads: VTK legacy,
// AVS UCD, PLOT3D with its solution) drawn with fx::CellRenderer, a transfer function and a
// choice of scalar field; default the NASA blunt fin shipped in content/meshes. The camera
// orbits the mesh slowly (±20° over 30 s). The panel tunes the path, the field, the transfer
// function and its density; the accuracy check compares the frame with the scan-line reference
// of the same mesh, field and transfer function.
#include <chrono>
#include <ctime>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include <epoxy/gl.h>
#include <thread>

#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/scanline_renderer.hpp"
#include "fx/transfer_function.hpp"
#include "gl/gl_object.hpp"
#include "sample.hpp"
#include "scene_content.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

namespace {

std::string source_file(const std::string& relative) { return std::string(CELLFX_SOURCE_DIR) + "/" + relative; }

struct NamedTf {
    std::string name;
    fx::TransferFunction tf; // as read (normalized ones mapped onto the field when used)
};

class MeshContent : public SampleContent {
public:
    explicit MeshContent(const SampleOptions& options) : time_(options.start_time) {
        const bool default_mesh = options.positional.empty();
        const std::string file = default_mesh ? source_file("content/meshes/blunt_fin/bluntfinxyz.bin") : options.positional[0];
        const std::string q = default_mesh ? source_file("content/meshes/blunt_fin/bluntfinq.bin")
                                           : options.positional.size() > 1 ? options.positional[1] : "";
        mesh_ = fx::read_mesh(file, q);
        name_ = std::filesystem::path(file).filename().string();
        if (mesh_.cell_count() == 0) throw fx::Error(file + ": the mesh has no volume cells to draw");
        if (mesh_.scalars.empty()) throw fx::Error(file + ": the mesh has no point scalar field to draw");
        fx::check_renderable(mesh_, file);
        const auto it = options.values.find("scalar");
        const std::string scalar = it != options.values.end() ? it->second : default_mesh ? "density" : mesh_.scalars[0].name;
        field_ = mesh_.scalars.size();
        for (std::size_t i = 0; i < mesh_.scalars.size(); ++i)
            if (mesh_.scalars[i].name == scalar) field_ = i;
        if (field_ == mesh_.scalars.size()) {
            std::string names;
            for (const fx::ScalarField& f : mesh_.scalars) names += (names.empty() ? "" : ", ") + f.name;
            throw fx::Error("--scalar: no field '" + scalar + "' in " + file + " (it has: " + names + ")");
        }
        fx::check_scalar_field(mesh_, mesh_.scalars[field_], file);
        if (options.values.count("tf")) tfs_.push_back({std::filesystem::path(options.values.at("tf")).stem().string(),
                                                        fx::TransferFunction::read_json(options.values.at("tf"))});
        for (const char* shipped : {"cool_warm", "fire", "fog", "step"})
            tfs_.push_back({shipped, fx::TransferFunction::read_json(source_file(std::string("content/transfer_functions/") + shipped + ".json"))});
        if (options.values.count("density")) {
            char* end = nullptr;
            density_ = std::strtod(options.values.at("density").c_str(), &end);
            if (*end != '\0' || !(density_ >= 0.0) || !std::isfinite(density_))
                throw fx::Error("--density: expected a non-negative number, got '" + options.values.at("density") + "'");
        }
        // The README's view of the blunt fin from 1.3× as far (its picture is 16:10, a window 4:3);
        // any other mesh framed from its diagonal.
        const fx::Bounds b = fx::mesh_bounds(mesh_);
        camera_ = default_mesh ? fx::Camera::parse("eye=3.56,-22.06,19.96,target=3.3,4.2,2.8,up=0,0,1,fov=40") : fx::Camera::framing(b.lo, b.hi);
        const double size = glm::length(b.hi - b.lo);
        camera_.near_distance = 1e-3 * size;
        camera_.far_distance = 1e2 * size + glm::length(camera_.eye - 0.5 * (b.lo + b.hi));
        renderer_.emplace(mesh_, mesh_.scalars[field_].name, current_tf());
    }

    // The function in use, normalized ones mapped onto the field's range, extinction × density.
    fx::TransferFunction current_tf() const {
        fx::TransferFunction tf = tfs_[tf_].tf;
        if (tf.normalized()) {
            const fx::ScalarRange r = fx::scalar_range(mesh_.scalars[field_]);
            tf = tf.rescaled(r.lo, std::max(double(r.hi), r.lo + 1e-6 * std::max(1.0, std::abs(double(r.lo)))));
        }
        return tf.scaled_extinction(density_);
    }

    glm::vec3 background() const override { return {0.06f, 0.065f, 0.08f}; }
    fx::Camera scripted_camera(double t) const override { return orbit_camera(camera_, 0.35 * std::sin(2.0 * M_PI * t / 30.0)); }
    double time() const override { return time_; }
    void set_time(double seconds) override { time_ = seconds; }
    void update(double dt, const fx::Camera& camera, int, int) override {
        time_ += dt;
        view_ = camera;
    }
    void render(unsigned framebuffer, const fx::Viewport& viewport, unsigned depth_texture) override {
        if (!volume_) {
            stats_ = {};
            return;
        }
        const auto t0 = std::chrono::steady_clock::now();
        timespec cpu0{}, cpu1{};
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu0);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, framebuffer);
        fx::CellRenderOptions options;
        options.scene_depth = depth_texture;
        options.fog = absorb_ && path_ == fx::RenderPath::PcpExact;
        options.timing = gpu_timing_;
        stats_ = renderer_->render(view_, viewport, path_, options);
        render_ms_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        clock_gettime(CLOCK_THREAD_CPUTIME_ID, &cpu1);
        cpu_ms_ = double(cpu1.tv_sec - cpu0.tv_sec) * 1e3 + double(cpu1.tv_nsec - cpu0.tv_nsec) * 1e-6;
    }

    std::vector<fx::RenderPath> paths() const override { return {std::begin(fx::kRenderPaths), std::end(fx::kRenderPaths)}; }
    void set_path(fx::RenderPath path) override { path_ = path; }
    std::string path_label() const override { return fx::render_path_name(path_); }
    std::vector<std::string> toggle_names() const override { return {"volume", "absorb"}; }
    bool toggled(std::size_t i) const override { return i == 0 ? volume_ : absorb_; }
    void toggle(std::size_t i) override { (i == 0 ? volume_ : absorb_) = !(i == 0 ? volume_ : absorb_); }
    bool key(char letter) override {
        if (letter == 'N') field_ = (field_ + 1) % mesh_.scalars.size();
        else if (letter == 'T') tf_ = (tf_ + 1) % tfs_.size();
        else return false;
        apply_field_and_tf();
        return true;
    }
    void apply_field_and_tf() {
        renderer_->set_mesh(mesh_, mesh_.scalars[field_].name);
        renderer_->set_transfer_function(current_tf());
    }

    void set_gpu_timing(bool on) override { gpu_timing_ = on; }
    void gpu_stages(std::vector<StageTime>& out) const override {
        out.clear();
        if (stats_.gpu_ms >= 0.0) out.push_back({"volume", stats_.gpu_ms});
    }

    std::vector<ControlGroup> controls() const override {
        ControlGroup g{"mesh", name_, {}};
        Control c;
        c.name = "volume", c.kind = Control::Kind::Toggle, c.toggle = volume_;
        g.controls.push_back(c);
        c = Control{};
        c.name = "path", c.kind = Control::Kind::Choice, c.choice = fx::render_path_name(path_);
        for (fx::RenderPath p : fx::kRenderPaths) c.choices.push_back(fx::render_path_name(p));
        g.controls.push_back(c);
        c = Control{};
        c.name = "absorb", c.kind = Control::Kind::Toggle, c.toggle = absorb_, c.note = "pcp-exact: emission and absorption";
        g.controls.push_back(c);
        c = Control{};
        c.name = "field", c.kind = Control::Kind::Choice, c.choice = mesh_.scalars[field_].name, c.choices = field_names();
        g.controls.push_back(c);
        c = Control{};
        c.name = "transfer_function", c.kind = Control::Kind::Choice, c.choice = tfs_[tf_].name, c.choices = tf_names();
        g.controls.push_back(c);
        c = Control{};
        // TransferFunction::scaled_extinction takes any finite factor ≥ 0.
        c.name = "density", c.kind = Control::Kind::Number, c.number = density_, c.range = {0.0, fx::kMaxCoordinate, false};
        c.note = "the transfer function's extinction × this";
        g.controls.push_back(c);
        return {g};
    }
    void set_control(const std::string& group, const Control& c) override {
        if (group != "mesh") return SampleContent::set_control(group, c); // throws: no such group
        const auto index_of = [&](const std::vector<std::string>& names) {
            for (std::size_t i = 0; i < names.size(); ++i)
                if (names[i] == c.choice) return i;
            throw fx::Error(c.name + ": no '" + c.choice + "'");
        };
        if (c.name == "volume") volume_ = c.toggle;
        else if (c.name == "absorb") absorb_ = c.toggle;
        else if (c.name == "path") {
            if (!fx::parse_render_path(c.choice, path_)) throw fx::Error("path: unknown render path '" + c.choice + "'");
        } else if (c.name == "field") {
            field_ = index_of(field_names());
            apply_field_and_tf();
        } else if (c.name == "transfer_function") {
            tf_ = index_of(tf_names());
            apply_field_and_tf();
        } else if (c.name == "density") {
            if (!(c.number >= 0.0 && std::isfinite(c.number))) throw fx::Error("density must be ≥ 0");
            density_ = c.number;
            apply_field_and_tf();
        } else {
            SampleContent::set_control(group, c);
        }
    }
    std::vector<std::string> field_names() const {
        std::vector<std::string> names;
        for (const fx::ScalarField& f : mesh_.scalars) names.push_back(f.name);
        return names;
    }
    std::vector<std::string> tf_names() const {
        std::vector<std::string> names;
        for (const NamedTf& t : tfs_) names.push_back(t.name);
        return names;
    }

    // The frame of the mesh alone in a float target over the background, and the scan-line
    // reference of the same mesh, field, transfer function and optical model.
    std::optional<ReferenceJob> reference_job(const fx::Camera& camera, int width, int height) override {
        if (!volume_) return std::nullopt;
        ReferenceJob job;
        job.background = glm::dvec3(background());
        job.frame = gpu_frame(camera, width, height, job.background);
        fx::ScanlineOptions so;
        so.model = path_ == fx::RenderPath::Mip ? fx::OpticalModel::Maximum
                   : path_ == fx::RenderPath::Absorption || path_ == fx::RenderPath::AbsorptionExact ||
                           (path_ == fx::RenderPath::PcpExact && absorb_)
                       ? fx::OpticalModel::EmissionAbsorption
                       : fx::OpticalModel::Emission;
        const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
        so.threads = cores > 1 ? cores - 1 : 1; // one core left to the window
        auto mesh = std::make_shared<const fx::CellMesh>(mesh_);
        const std::string field = mesh_.scalars[field_].name;
        const fx::TransferFunction tf = current_tf();
        job.reference = [mesh, field, tf, so, camera, width, height](fx::ScanlineProgress& progress) {
            fx::ScanlineOptions o = so;
            o.progress = &progress;
            return fx::ScanlineRenderer(*mesh).render(camera, width, height, *mesh->find_scalar(field), tf, o);
        };
        job.what = name_ + ", " + field + ", " + fx::render_path_name(path_);
        return job;
    }

    fx::Image gpu_frame(const fx::Camera& camera, int width, int height, const glm::dvec3& bg) {
        const fx::gl::Framebuffer fb = fx::gl::Framebuffer::create();
        const fx::gl::Texture color = fx::gl::Texture::create(GL_TEXTURE_2D);
        glTextureStorage2D(color.id(), 1, GL_RGBA32F, width, height);
        glNamedFramebufferTexture(fb.id(), GL_COLOR_ATTACHMENT0, color.id(), 0);
        const float clear[4] = {float(bg.r), float(bg.g), float(bg.b), 1.0f};
        glClearNamedFramebufferfv(fb.id(), GL_COLOR, 0, clear);
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fb.id());
        fx::CellRenderOptions options; // no scene depth: nothing in front of the mesh
        options.fog = absorb_ && path_ == fx::RenderPath::PcpExact;
        renderer_->render(camera, fx::Viewport{0, 0, width, height}, path_, options);
        fx::Image image(width, height);
        glGetTextureImage(color.id(), 0, GL_RGBA, GL_FLOAT, GLsizei(image.pixels.size() * sizeof(glm::vec4)), image.pixels.data());
        glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        for (glm::vec4& p : image.pixels) p.a = 1.0f;
        return image;
    }
    std::vector<std::string> key_help() const override {
        return {"N  next scalar field   T  next transfer function   (F2 absorb: pcp-exact with absorption)"};
    }

    std::string stats_line() const override {
        const fx::ScalarRange r = fx::scalar_range(mesh_.scalars[field_]);
        char range[96];
        std::snprintf(range, sizeof range, " [%.3g, %.3g]", double(r.lo), double(r.hi));
        return name_ + ": " + std::to_string(mesh_.cell_count()) + " cells  |  " + mesh_.scalars[field_].name + range +
               "  |  tf " + tfs_[tf_].name + "  |  cpu " + std::to_string(int(std::lround(stats_.cpu_ms))) + " ms";
    }
    std::size_t cells_drawn() const override { return stats_.cells_drawn; }
    double update_ms() const override { return 0.0; }
    double render_ms() const override { return render_ms_; }
    double update_cpu_ms() const override { return 0.0; }
    double render_cpu_ms() const override { return cpu_ms_; }

private:
    fx::CellMesh mesh_;
    std::string name_;
    std::size_t field_ = 0, tf_ = 0;
    std::vector<NamedTf> tfs_;
    double density_ = 1.0;
    fx::Camera camera_, view_;
    std::optional<fx::CellRenderer> renderer_;
    fx::RenderPath path_ = fx::RenderPath::AbsorptionExact; // emission and absorption, sorted: what FEM fields need
    bool volume_ = true, absorb_ = false, gpu_timing_ = false;
    double time_ = 0.0, render_ms_ = 0.0, cpu_ms_ = 0.0;
    fx::CellRenderStats stats_;
};

} // namespace

SampleInfo fem_viewer_sample() {
    SampleInfo info;
    info.usage.name = "fem_viewer";
    info.usage.summary = "A finite-element mesh with a transfer function and a choice of scalar field (default: the NASA blunt fin).";
    info.usage.positional = "[MESH [Q_FILE]]";
    info.usage.max_positional = 2;
    info.usage.options = {{"--scalar NAME", "point field to draw (default: density for the blunt fin, else the first)"},
                          {"--tf FILE", "transfer function JSON (default: content/transfer_functions/cool_warm.json)"},
                          {"--density K", "multiply the transfer function's extinction by K (default 1)"}};
    info.animated = true;
    info.make = [](const SampleOptions& options) -> std::unique_ptr<SampleContent> { return std::make_unique<MeshContent>(options); };
    return info;
}

} // namespace cellfx_samples
