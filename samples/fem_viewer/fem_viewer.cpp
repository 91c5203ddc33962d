// The fem_viewer sample: a finite-element mesh (any file fx::read_mesh reads: VTK legacy,
// AVS UCD, PLOT3D with its solution) drawn with fx::CellRenderer, a transfer function and a
// choice of scalar field; default the NASA blunt fin shipped in content/meshes. The camera
// orbits the mesh slowly (±20° over 30 s).
#include <chrono>
#include <ctime>
#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include <epoxy/gl.h>

#include "fx/cell_renderer.hpp"
#include "fx/error.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "fx/transfer_function.hpp"
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
        renderer_->set_mesh(mesh_, mesh_.scalars[field_].name);
        renderer_->set_transfer_function(current_tf());
        return true;
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
    bool volume_ = true, absorb_ = false;
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
