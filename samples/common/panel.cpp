// The tuning panel with Dear ImGui (panel.hpp): Debian's libimgui-dev and its GLFW and OpenGL 3
// backends (compiled into its libimgui.a).
#include "panel.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

#include <epoxy/gl.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>

#include "frame_loop.hpp"
#include "fx/error.hpp"
#include "gl/gl_object.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

namespace {

constexpr float kPanelWidth = 400.0f; // pixels at scale 1

// An fx::Image (bottom row first, linear floats in [0, 1]) as an RGBA8 texture ImGui can show.
fx::gl::Texture image_texture(const fx::Image& image) {
    std::vector<unsigned char> rgba(image.pixels.size() * 4);
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
        for (int c = 0; c < 4; ++c)
            rgba[4 * i + std::size_t(c)] = static_cast<unsigned char>(std::lround(std::clamp(image.pixels[i][c], 0.0f, 1.0f) * 255.0f));
    fx::gl::Texture t = fx::gl::Texture::create(GL_TEXTURE_2D);
    glTextureStorage2D(t.id(), 1, GL_RGBA8, image.width, image.height);
    glTextureParameteri(t.id(), GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(t.id(), GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTextureSubImage2D(t.id(), 0, 0, 0, image.width, image.height, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    return t;
}

ImTextureID texture_id(const fx::gl::Texture& t) { return reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(t.id())); }

// Shows an image bottom row first (fx::Image's order) the right way up.
void show_image(const fx::gl::Texture& t, float width, float height) {
    ImGui::Image(texture_id(t), ImVec2(width, height), ImVec2(0.0f, 1.0f), ImVec2(1.0f, 0.0f));
}

ImU32 series_colour(const std::string& name, std::size_t index) {
    if (name == "cellfx CPU") return IM_COL32(255, 160, 40, 255);
    if (name == "update") return IM_COL32(240, 230, 90, 255);
    if (name == "driver") return IM_COL32(150, 150, 150, 255);
    if (name == "frame") return IM_COL32(90, 90, 110, 255);
    if (name == "gpu total") return IM_COL32(80, 220, 255, 255);
    static const ImU32 stages[] = {IM_COL32(90, 140, 255, 255), IM_COL32(120, 230, 120, 255), IM_COL32(220, 110, 240, 255),
                                   IM_COL32(255, 110, 110, 255), IM_COL32(110, 230, 210, 255), IM_COL32(200, 200, 255, 255)};
    return stages[index % (sizeof stages / sizeof stages[0])];
}

std::string range_text(const Control& c) {
    if (c.kind == Control::Kind::Number || c.kind == Control::Kind::Integer)
        return c.range.requirement(c.kind == Control::Kind::Integer);
    if (c.kind == Control::Kind::Direction) return "must be finite and non-zero";
    if (c.kind == Control::Kind::Vector) return "each component " + c.range.requirement(false);
    return "";
}

class ImGuiPanel final : public Panel {
public:
    explicit ImGuiPanel(GLFWwindow* window) : window_(window) {
        IMGUI_CHECKVERSION();
        context_ = ImGui::CreateContext();
        ImGui::SetCurrentContext(context_);
        ImGuiIO& io = ImGui::GetIO();
        io.IniFilename = nullptr; // no imgui.ini left in the user's folder
        io.LogFilename = nullptr;
        ImGui::StyleColorsDark();
        ImGui::GetStyle().WindowRounding = 0.0f;
        ImGui::GetStyle().Colors[ImGuiCol_WindowBg].w = 0.88f;
        if (window_ && !ImGui_ImplGlfw_InitForOpenGL(window_, true)) throw fx::Error("panel: ImGui's GLFW backend failed to start");
        if (!ImGui_ImplOpenGL3_Init("#version 450")) throw fx::Error("panel: ImGui's OpenGL 3 backend failed to start");
    }
    ~ImGuiPanel() override {
        ImGui::SetCurrentContext(context_);
        ImGui_ImplOpenGL3_Shutdown();
        if (window_) ImGui_ImplGlfw_Shutdown();
        ImGui::DestroyContext(context_);
    }
    ImGuiPanel(const ImGuiPanel&) = delete;
    ImGuiPanel& operator=(const ImGuiPanel&) = delete;

    bool wants_mouse() const override { return wants_mouse_; }
    bool wants_keyboard() const override { return wants_keyboard_; }
    double accuracy_scale() const override { return kScales[scale_index_]; }

    void draw(FrameLoop& loop, int width, int height) override {
        ImGui::SetCurrentContext(context_);
        ImGuiIO& io = ImGui::GetIO();
        if (window_) {
            ImGui_ImplGlfw_NewFrame();
        } else {
            io.DisplaySize = ImVec2(float(width), float(height));
            io.DeltaTime = 1.0f / 30.0f;
        }
        ImGui_ImplOpenGL3_NewFrame();
        ImGui::NewFrame();
        const float scale = width >= 1600 ? 2.0f : 1.0f;
        io.FontGlobalScale = scale;
        const float panel_width = std::min(kPanelWidth * scale, 0.45f * float(width));
        if (!placed_ || last_width_ != width || last_height_ != height) {
            // Docked to the right edge, full height; the user may collapse it (or Tab hides it).
            ImGui::SetNextWindowPos(ImVec2(float(width) - panel_width, 0.0f), ImGuiCond_Always);
            ImGui::SetNextWindowSize(ImVec2(panel_width, float(height)), ImGuiCond_Always);
            placed_ = true, last_width_ = width, last_height_ = height;
        }
        if (heat_over_frame_ && heat_) {
            // The heat map over the picture, behind the panel.
            ImGui::GetBackgroundDrawList()->AddImage(texture_id(*heat_), ImVec2(0.0f, 0.0f), ImVec2(float(width), float(height)),
                                                     ImVec2(0.0f, 1.0f), ImVec2(1.0f, 0.0f), IM_COL32(255, 255, 255, 230));
        }
        const std::string title = "cellfx " + loop.name() + "###panel";
        if (ImGui::Begin(title.c_str(), nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize)) {
            header(loop);
            graph(loop);
            accuracy(loop);
            const std::vector<ControlGroup> groups = loop.controls();
            // Open at first: the first effect with parameters of its own (more than on/off, path,
            // absorb and extinction), else the first effect.
            if (opened_effect_.empty() && groups.size() > 2) {
                opened_effect_ = groups[1].name;
                for (std::size_t i = groups.size() - 1; i-- > 1;)
                    if (groups[i].controls.size() > 4) opened_effect_ = groups[i].name;
            }
            for (const ControlGroup& g : groups) group(loop, g);
        }
        ImGui::End();
        ImGui::Render();
        ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
        wants_mouse_ = io.WantCaptureMouse;
        wants_keyboard_ = io.WantCaptureKeyboard;
    }

private:
    static constexpr double kScales[] = {1.0, 0.5, 0.25};

    void header(FrameLoop& loop) {
        ImGui::Text("%.1f fps   frame %.1f ms   t %.2f s", loop.fps(), loop.last_wall_ms(), loop.content().time());
        ImGui::TextDisabled("Tab hides the panel, H prints the keys");
        if (!loop.save_path().empty()) {
            if (ImGui::Button("Save")) {
                try {
                    loop.save();
                } catch (const fx::Error& e) {
                    loop.set_message(e.what());
                }
            }
            ImGui::SameLine();
            ImGui::TextDisabled("to %s (Ctrl+S)", loop.save_path().c_str());
        } else {
            ImGui::TextDisabled("--save FILE: Save writes the tuned scene there");
        }
        if (!loop.message().empty()) ImGui::TextWrapped("%s", loop.message().c_str());
    }

    // Frame time: a line per series over the last FrameHistory::kFrames frames, the budgets dashed.
    void graph(FrameLoop& loop) {
        if (!ImGui::CollapsingHeader("Frame time", ImGuiTreeNodeFlags_DefaultOpen)) return;
        const FrameHistory& h = loop.history();
        const std::size_t n = FrameHistory::kFrames;
        float top = float(std::max(loop.cpu_budget_ms(), loop.gpu_budget_ms())) * 1.5f;
        for (const FrameHistory::Series& s : h.series())
            if (s.name != "frame" && (!s.gpu || loop.gpu_timing()))
                for (float v : s.values)
                    if (std::isfinite(v)) top = std::max(top, v * 1.1f);
        const ImVec2 size(ImGui::GetContentRegionAvail().x, 120.0f * ImGui::GetIO().FontGlobalScale);
        const ImVec2 p0 = ImGui::GetCursorScreenPos(), p1(p0.x + size.x, p0.y + size.y);
        ImDrawList* dl = ImGui::GetWindowDrawList();
        dl->AddRectFilled(p0, p1, IM_COL32(20, 22, 28, 255));
        const auto y_of = [&](double ms) { return p1.y - float(ms / top) * size.y; };
        // The budget lines, their labels side by side (the lines may lie close together).
        float label_x = p0.x + 2.0f;
        const auto dashed = [&](double ms, ImU32 colour, const char* label) {
            const float y = y_of(ms);
            for (float x = p0.x; x < p1.x; x += 8.0f) dl->AddLine(ImVec2(x, y), ImVec2(std::min(x + 4.0f, p1.x), y), colour);
            dl->AddText(ImVec2(label_x, std::max(y - ImGui::GetTextLineHeight(), p0.y)), colour, label);
            label_x += ImGui::CalcTextSize(label).x + 12.0f;
        };
        char label[64];
        std::snprintf(label, sizeof label, "CPU budget %.3g ms", loop.cpu_budget_ms());
        dashed(loop.cpu_budget_ms(), series_colour("cellfx CPU", 0), label);
        std::snprintf(label, sizeof label, "GPU budget %.3g ms", loop.gpu_budget_ms());
        dashed(loop.gpu_budget_ms(), series_colour("gpu total", 0), label);
        std::size_t stage = 0;
        for (const FrameHistory::Series& s : h.series()) {
            const ImU32 colour = series_colour(s.name, s.gpu ? stage++ : 0);
            if (s.name == "frame") continue; // the whole frame's time: in the legend only
            for (std::size_t age = 0; age + 1 < h.frames(); ++age) {
                const float a = h.at(s, age), b = h.at(s, age + 1);
                if (!std::isfinite(a) || !std::isfinite(b)) continue;
                const float xa = p1.x - float(age) * size.x / float(n - 1), xb = p1.x - float(age + 1) * size.x / float(n - 1);
                dl->AddLine(ImVec2(xa, std::max(y_of(a), p0.y)), ImVec2(xb, std::max(y_of(b), p0.y)), colour,
                            s.name == "cellfx CPU" || s.name == "gpu total" ? 2.0f : 1.0f);
            }
        }
        std::snprintf(label, sizeof label, top >= 100.0f ? "%.0f ms" : "%.3g ms", double(top));
        dl->AddText(ImVec2(p1.x - ImGui::CalcTextSize(label).x - 2.0f, p0.y), IM_COL32(200, 200, 200, 255), label);
        ImGui::Dummy(size);
        // Legend: each series with its last value.
        stage = 0;
        bool first = true;
        for (const FrameHistory::Series& s : h.series()) {
            const ImU32 colour = series_colour(s.name, s.gpu ? stage++ : 0);
            const float v = h.at(s, 0);
            if (!std::isfinite(v)) continue;
            if (!first) ImGui::SameLine();
            if (ImGui::GetContentRegionAvail().x < 120.0f * ImGui::GetIO().FontGlobalScale) ImGui::NewLine();
            first = false;
            ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(colour), "%s %.2f", s.name.c_str(), double(v));
        }
        if (!loop.gpu_timing()) ImGui::TextDisabled("GPU per stage: view > gpu_timing");
        std::vector<float> cells(n);
        for (std::size_t age = 0; age < n; ++age) {
            const float v = h.at(h.cells(), n - 1 - age);
            cells[age] = std::isfinite(v) ? v : 0.0f;
        }
        std::snprintf(label, sizeof label, "cells drawn %.0f", double(std::isfinite(h.at(h.cells(), 0)) ? h.at(h.cells(), 0) : 0.0f));
        ImGui::PlotLines("##cells", cells.data(), int(n), 0, label, 0.0f, FLT_MAX,
                         ImVec2(ImGui::GetContentRegionAvail().x, 40.0f * ImGui::GetIO().FontGlobalScale));
    }

    void accuracy(FrameLoop& loop) {
        if (!ImGui::CollapsingHeader("Accuracy", ImGuiTreeNodeFlags_DefaultOpen)) return;
        const AccuracyCheck& check = loop.accuracy();
        if (check.running()) {
            ImGui::ProgressBar(float(check.progress()), ImVec2(-80.0f * ImGui::GetIO().FontGlobalScale, 0.0f));
            ImGui::SameLine();
            if (ImGui::Button("Cancel")) loop.cancel_accuracy();
            ImGui::TextDisabled("the scan-line reference renders in the background");
        } else {
            if (ImGui::Button("Compare with the reference (R)")) loop.request_accuracy(accuracy_scale());
            ImGui::SameLine();
            ImGui::SetNextItemWidth(-1.0f);
            const char* sizes[] = {"full size", "half size", "quarter size"};
            ImGui::Combo("##size", &scale_index_, sizes, 3);
        }
        if (loop.accuracy_results() != shown_result_) {
            shown_result_ = loop.accuracy_results();
            const AccuracyResult& r = *loop.accuracy_result();
            frame_ = image_texture(r.frame);
            reference_ = image_texture(r.reference);
            heat_ = image_texture(r.heat);
        }
        const std::optional<AccuracyResult>& r = loop.accuracy_result();
        if (!r || !heat_) return;
        ImGui::Text("mean %.3g%%   worst %.3g%% of peak %.3g", r->mean_percent(), r->worst_percent(), r->peak);
        ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyle().Colors[ImGuiCol_TextDisabled]);
        ImGui::TextWrapped("%s, %dx%d, reference in %.1f s", r->what.c_str(), r->width, r->height, r->seconds);
        ImGui::PopStyleColor();
        const float w = (ImGui::GetContentRegionAvail().x - 2.0f * ImGui::GetStyle().ItemSpacing.x) / 3.0f;
        const float h = w * float(r->height) / float(std::max(r->width, 1));
        show_image(*frame_, w, h);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("the GPU's frame of the effects");
        ImGui::SameLine();
        show_image(*reference_, w, h);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("the scan-line reference");
        ImGui::SameLine();
        show_image(*heat_, w, h);
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("the difference: black 0, white the worst pixel");
        // The heat map's scale.
        const ImVec2 p0 = ImGui::GetCursorScreenPos();
        const float bar = ImGui::GetContentRegionAvail().x;
        for (int i = 0; i < 64; ++i) {
            const glm::vec3 c = heat_colour(i / 63.0);
            ImGui::GetWindowDrawList()->AddRectFilled(ImVec2(p0.x + bar * float(i) / 64.0f, p0.y),
                                                      ImVec2(p0.x + bar * float(i + 1) / 64.0f, p0.y + 6.0f),
                                                      ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, 1.0f)));
        }
        ImGui::Dummy(ImVec2(bar, 8.0f));
        ImGui::TextDisabled("0");
        ImGui::SameLine(bar - ImGui::CalcTextSize("worst 00.0%").x);
        ImGui::TextDisabled("worst %.3g%%", r->worst_percent());
        ImGui::Checkbox("heat map over the picture", &heat_over_frame_);
    }

    void group(FrameLoop& loop, const ControlGroup& g) {
        // The scene's own group and the first effect's open at first; the others a click away.
        const bool first_effect = g.name != "scene" && g.name != "view" && !opened_effect_.empty() ? g.name == opened_effect_ : false;
        const ImGuiTreeNodeFlags open = g.name == "scene" || g.name == "mesh" || first_effect ? ImGuiTreeNodeFlags_DefaultOpen : 0;
        const std::string header = g.title + "###" + g.name;
        if (!ImGui::CollapsingHeader(header.c_str(), open)) return;
        ImGui::PushID(g.name.c_str());
        // Room for the group's longest name right of the widgets (ImGui's default cuts it).
        float label_width = 0.0f;
        for (const Control& c : g.controls) label_width = std::max(label_width, ImGui::CalcTextSize(c.name.c_str()).x);
        const float room = label_width + 2.0f * ImGui::GetStyle().ItemInnerSpacing.x;
        ImGui::PushItemWidth(-std::min(room, 0.55f * ImGui::GetContentRegionAvail().x));
        for (const Control& c : g.controls) {
            Control changed = c;
            if (widget(changed)) {
                try {
                    loop.set_control(g.name, changed);
                } catch (const std::exception& e) {
                    loop.set_message(g.name + "." + c.name + ": " + e.what());
                }
            }
            if (ImGui::IsItemHovered()) {
                std::string tip = g.name + "." + c.name;
                if (!c.unit.empty()) tip += " (" + c.unit + ")";
                if (!c.note.empty()) tip += "\n" + c.note;
                const std::string range = range_text(c);
                if (!range.empty()) tip += "\n" + range;
                ImGui::SetTooltip("%s", tip.c_str());
            }
        }
        ImGui::PopItemWidth();
        ImGui::PopID();
    }

    // One control's widget; true (and `c` holds the new value) when the user changed it.
    static bool widget(Control& c) {
        const char* label = c.name.c_str();
        switch (c.kind) {
        case Control::Kind::Toggle: return ImGui::Checkbox(label, &c.toggle);
        case Control::Kind::Choice: {
            bool changed = false;
            if (ImGui::BeginCombo(label, c.choice.empty() ? "(mixed)" : c.choice.c_str())) {
                for (const std::string& choice : c.choices)
                    if (ImGui::Selectable(choice.c_str(), choice == c.choice) && choice != c.choice) {
                        c.choice = choice;
                        changed = true;
                    }
                ImGui::EndCombo();
            }
            return changed;
        }
        case Control::Kind::Integer: {
            std::int64_t v = std::int64_t(c.number);
            const std::int64_t lo = std::int64_t(std::ceil(c.range.lo + (c.range.lo_open ? 0.5 : 0.0)));
            const std::int64_t hi = std::int64_t(c.range.hi);
            const bool changed = hi - lo <= 4096 ? ImGui::SliderScalar(label, ImGuiDataType_S64, &v, &lo, &hi, "%lld", ImGuiSliderFlags_AlwaysClamp)
                                                 : ImGui::DragScalar(label, ImGuiDataType_S64, &v, 1.0f, &lo, &hi, "%lld", ImGuiSliderFlags_AlwaysClamp);
            c.number = double(v);
            return changed;
        }
        case Control::Kind::Number: {
            // The library's range exactly: an open lower end is the next double above it.
            const double lo = c.range.lo_open ? std::nextafter(c.range.lo, std::numeric_limits<double>::infinity()) : c.range.lo;
            const double hi = c.range.hi;
            // A slider for a closed, short range (degrees, fractions); a drag otherwise.
            if (!c.range.lo_open && hi - c.range.lo <= 360.0)
                return ImGui::SliderScalar(label, ImGuiDataType_Double, &c.number, &lo, &hi, "%.4g", ImGuiSliderFlags_AlwaysClamp);
            const float speed = float(std::max(std::abs(c.number), 1e-2) * 0.005);
            return ImGui::DragScalar(label, ImGuiDataType_Double, &c.number, speed, &lo, &hi, "%.4g", ImGuiSliderFlags_AlwaysClamp);
        }
        case Control::Kind::Vector:
        case Control::Kind::Direction: {
            const double lo = c.range.lo_open ? std::nextafter(c.range.lo, std::numeric_limits<double>::infinity()) : c.range.lo;
            const double hi = c.range.hi;
            const double largest = std::max({std::abs(c.vector.x), std::abs(c.vector.y), std::abs(c.vector.z), 1e-2});
            return ImGui::DragScalarN(label, ImGuiDataType_Double, &c.vector.x, 3, float(largest * 0.005), &lo, &hi, "%.4g",
                                      ImGuiSliderFlags_AlwaysClamp);
        }
        }
        return false;
    }

    GLFWwindow* window_;
    ImGuiContext* context_ = nullptr;
    bool wants_mouse_ = false, wants_keyboard_ = false;
    bool placed_ = false;
    int last_width_ = 0, last_height_ = 0;
    int scale_index_ = 1; // half size: a reference four times as fast as full size
    std::uint64_t shown_result_ = 0;
    std::optional<fx::gl::Texture> frame_, reference_, heat_;
    bool heat_over_frame_ = false;
    std::string opened_effect_; // the first effect's group, open at first
};

} // namespace

std::unique_ptr<Panel> make_panel(void* glfw_window) { return std::make_unique<ImGuiPanel>(static_cast<GLFWwindow*>(glfw_window)); }

bool panel_built() { return true; }

} // namespace cellfx_samples
