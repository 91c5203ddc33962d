#include "mesh_input.hpp"

#include <chrono>

#include "fx/error.hpp"
#include "fx/mesh_io.hpp"
#include "fx/mesh_validation.hpp"
#include "cellfx_names.hpp"

namespace cellfx_cli {

MeshInput read_mesh_input(const ParsedArgs& parsed) {
    if (parsed.positional.empty() || parsed.positional.size() > 2) throw fx::Error("expected FILE [Q_FILE]");
    MeshInput in;
    in.files = parsed.positional;
    const auto start = std::chrono::steady_clock::now();
    in.mesh = fx::read_mesh(in.files[0], in.files.size() > 1 ? in.files[1] : "");
    in.load_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    if (in.mesh.cell_count() == 0) throw fx::Error(in.files[0] + ": the mesh has no volume cells to render");
    fx::check_renderable(in.mesh, in.files[0]);
    if (in.mesh.scalars.empty()) throw fx::Error(in.files[0] + ": the mesh has no point scalar field to render");
    in.field = parsed.get("scalar", in.mesh.scalars.front().name);
    if (!in.mesh.find_scalar(in.field)) {
        std::string names;
        for (const fx::ScalarField& f : in.mesh.scalars) names += (names.empty() ? "" : ", ") + f.name;
        throw fx::Error("--scalar: no field '" + in.field + "' (the mesh has: " + names + ")");
    }
    // PLOT3D fields come from the q file: a bad value there is the q file's.
    fx::check_scalar_field(in.mesh, *in.mesh.find_scalar(in.field), in.files.back());
    return in;
}

fx::TransferFunction default_transfer_function() {
    return fx::TransferFunction({{0.0, {0.10, 0.25, 0.90}, 0.02},
                                 {0.5, {0.20, 0.90, 0.40}, 0.10},
                                 {1.0, {1.00, 0.25, 0.10}, 0.40}},
                                /*normalized=*/true);
}

fx::TransferFunction transfer_function_option(const ParsedArgs& parsed, const char* command, const fx::ScalarField& field,
                                              const fx::TransferFunction& fallback) {
    const double k = number_option(parsed, command, "density", 1.0);
    fx::TransferFunction tf = parsed.has("tf") ? fx::TransferFunction::read_json(parsed.get("tf")) : fallback;
    if (tf.normalized()) {
        const fx::ScalarRange r = fx::scalar_range(field);
        tf = tf.rescaled(r.lo, r.hi);
    }
    if (parsed.has("density")) {
        try {
            tf = tf.scaled_extinction(k);
        } catch (const fx::Error& e) {
            throw fx::Error("--density " + format_number(k) + ": " + e.what());
        }
    }
    return tf;
}

} // namespace cellfx_cli
