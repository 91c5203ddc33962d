// The samples' command line (sample.hpp: parse_options).
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "fx/error.hpp"
#include "fx/resource_limits.hpp"
#include "sample.hpp"
#include "cellfx_names.hpp"

namespace cellfx_samples {

namespace {

int parse_int(const std::string& flag, const std::string& text, int lo, int hi) {
    char* end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi)
        throw fx::Error(flag + ": expected a whole number in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got '" + text + "'");
    return int(v);
}

double parse_double(const std::string& flag, const std::string& text, double lo, double hi) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(text.c_str(), &end);
    if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v) || v < lo || v > hi) {
        std::ostringstream range;
        range << lo << ".." << hi;
        throw fx::Error(flag + ": expected a number in " + range.str() + ", got '" + text + "'");
    }
    return v;
}

std::vector<std::string> split(const std::string& list) {
    std::vector<std::string> out;
    std::stringstream in(list);
    for (std::string item; std::getline(in, item, ',');)
        if (!item.empty()) out.push_back(item);
    return out;
}

} // namespace

std::string usage_text(const SampleUsage& usage) {
    std::ostringstream out;
    out << "usage: " << usage.name << (usage.positional.empty() ? "" : " " + usage.positional) << " [options]\n"
        << "  " << usage.summary << "\n"
        << "  Opens a window (OpenGL 4.5 core, GLFW); keys are printed on start (H prints them again).\n"
        << "  --headless           no window: an offscreen framebuffer in an EGL context, same frame loop\n"
        << "  --frames N           render N frames, then exit (needed with --headless)\n"
        << "  --out DIR            write DIR/frame_0000.png, ... (the framebuffer read back after each frame)\n"
        << "  --width W --height H frame size in pixels (default: the scene's)\n"
        << "  --path NAME          draw every effect with this render path (keys 1.. switch it)\n"
        << "  --dt S               scene seconds per frame with --frames (default 0.0333)\n"
        << "  --time T             scene clock of the first frame (default 0)\n"
        << "  --disable A,B        start with these effects switched off\n"
        << "  --no-overlay         leave out the frame-stats lines\n"
        << "  --no-props           leave out the sample's own opaque geometry\n"
        << "  --panel / --no-panel the tuning panel (default: shown in a window, not headless; Tab toggles it)\n"
        << "  --set G.NAME=VALUE   set a panel control at start (repeatable), e.g. --set fire.base_radius=0.8\n"
        << "  --save FILE          where the panel's Save (Ctrl+S) writes the tuned scene file; with --frames\n"
        << "                       also written after the last frame\n"
        << "  --accuracy           compare the first frame's effects with the scan-line reference (in the\n"
        << "                       background) and print the error; with --frames the run waits for it\n"
        << "  --limit NAME=N       change a resource limit (repeatable; `cellfx limits` lists them)\n";
    for (const auto& [flag, help] : usage.options) {
        std::string f = "  " + flag;
        if (f.size() < 23) f.resize(23, ' ');
        else f += " ";
        out << f << help << "\n";
    }
    return out.str();
}

std::optional<SampleOptions> parse_options(const std::vector<std::string>& args, const SampleUsage& usage) {
    SampleOptions o;
    const auto sample_flag = [&](const std::string& flag) {
        for (const auto& [spec, help] : usage.options)
            if (spec == flag || spec.rfind(flag + " ", 0) == 0) return true;
        return false;
    };
    for (std::size_t i = 0; i < args.size(); ++i) {
        const std::string& a = args[i];
        const auto value = [&]() -> const std::string& {
            if (i + 1 >= args.size()) throw fx::Error(a + ": needs a value");
            return args[++i];
        };
        if (a == "--help" || a == "-h") {
            std::fputs(usage_text(usage).c_str(), stdout);
            return std::nullopt;
        } else if (a == "--headless") {
            o.headless = true;
        } else if (a == "--frames") {
            o.frames = parse_int(a, value(), 1, 1000000);
        } else if (a == "--out") {
            o.out = value();
            if (o.out.empty()) throw fx::Error("--out: needs a folder name");
        } else if (a == "--width") {
            o.width = parse_int(a, value(), 1, 16384);
        } else if (a == "--height") {
            o.height = parse_int(a, value(), 1, 16384);
        } else if (a == "--path") {
            const std::string& name = value();
            fx::RenderPath path;
            if (!fx::parse_render_path(name, path)) {
                std::string names;
                for (fx::RenderPath p : fx::kRenderPaths) names += (names.empty() ? "" : ", ") + std::string(fx::render_path_name(p));
                throw fx::Error("--path: unknown render path '" + name + "' (expected " + names + ")");
            }
            o.path = path;
        } else if (a == "--dt") {
            o.dt = parse_double(a, value(), 0.0, 3600.0);
        } else if (a == "--time") {
            o.start_time = parse_double(a, value(), -1e6, 1e6);
        } else if (a == "--disable") {
            o.disable = split(value());
        } else if (a == "--no-overlay") {
            o.overlay = false;
        } else if (a == "--no-props") {
            o.props = false;
        } else if (a == "--panel" || a == "--no-panel") {
            o.panel = a == "--panel";
        } else if (a == "--set") {
            const std::string& setting = value();
            const std::size_t dot = setting.find('.'), equals = setting.find('=');
            if (dot == 0 || dot == std::string::npos || equals == std::string::npos || equals < dot + 2)
                throw fx::Error("--set: expected GROUP.NAME=VALUE (e.g. fire.base_radius=0.8), got '" + setting + "'");
            o.set.push_back(setting);
        } else if (a == "--save") {
            o.save = value();
            if (o.save.empty()) throw fx::Error("--save: needs a file name");
        } else if (a == "--accuracy") {
            o.accuracy = true;
        } else if (a == "--limit") {
            fx::ResourceLimits limits = fx::resource_limits();
            fx::apply_limit(limits, value());
            fx::set_resource_limits(limits);
        } else if (a.rfind("--", 0) == 0 && sample_flag(a)) {
            o.values[a.substr(2)] = value();
        } else if (a.rfind("-", 0) == 0 && a.size() > 1) {
            throw fx::Error("unknown option '" + a + "' (" + usage.name + " --help lists them)");
        } else {
            if (o.positional.size() >= usage.max_positional)
                throw fx::Error(usage.max_positional == 0 ? "unexpected argument '" + a + "'"
                                                          : "too many arguments at '" + a + "' (expected " + usage.positional + ")");
            o.positional.push_back(a);
        }
    }
    if ((o.width > 0) != (o.height > 0)) throw fx::Error("--width and --height go together");
    if (o.headless && o.frames == 0) throw fx::Error("--headless needs --frames N");
    if (!o.out.empty() && o.frames == 0) throw fx::Error("--out needs --frames N (the frames to write)");
    return o;
}

} // namespace cellfx_samples
