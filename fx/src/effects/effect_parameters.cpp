// The effects' parameter tables (fx/effect_parameters.hpp): the one place each range is written.
#include "fx/effect_parameters.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "fx/error.hpp"

namespace cellfx::fx {

namespace {

using Kind = ParameterKind;
using Cost = ParameterCost;

// Ranges by what they say.
constexpr ParameterRange kAny{};                              // finite, within ±kMaxCoordinate
constexpr ParameterRange kPositive{0.0, kMaxCoordinate, true}; // a length, a rate, a frequency
constexpr ParameterRange kNonNegative{0.0, kMaxCoordinate};
constexpr ParameterRange in(double lo, double hi) { return {lo, hi, false}; }

// One entry per field: the accessors are captureless lambdas, so the tables are plain data.
#define CELLFX_FIELD(P, field) [](P& p) { return &p.field; }

template <class P>
Parameter<P> number(const char* name, double* (*field)(P&), ParameterRange range, Cost cost, const char* unit, const char* what,
                    bool (*applies)(const P&) = nullptr) {
    Parameter<P> p{name, Kind::Number, range, cost, unit, what};
    p.number = field;
    p.applies = applies;
    return p;
}
template <class P>
Parameter<P> integer(const char* name, int* (*field)(P&), ParameterRange range, Cost cost, const char* unit, const char* what,
                     bool (*applies)(const P&) = nullptr) {
    Parameter<P> p{name, Kind::Integer, range, cost, unit, what};
    p.integer = field;
    p.applies = applies;
    return p;
}
template <class P>
Parameter<P> seed(const char* name, std::uint32_t* (*field)(P&), Cost cost, const char* what,
                  bool (*applies)(const P&) = nullptr) {
    Parameter<P> p{name, Kind::Seed, in(0.0, 4294967295.0), cost, "", what};
    p.seed = field;
    p.applies = applies;
    return p;
}
template <class P>
Parameter<P> vector(const char* name, Kind kind, glm::dvec3* (*field)(P&), ParameterRange range, Cost cost, const char* unit,
                    const char* what, bool (*applies)(const P&) = nullptr) {
    Parameter<P> p{name, kind, range, cost, unit, what};
    p.vector = field;
    p.applies = applies;
    return p;
}

std::string format(double v) {
    std::ostringstream out;
    out << v;
    return out.str();
}

} // namespace

bool ParameterRange::contains(double v) const {
    return std::isfinite(v) && std::abs(v) <= kMaxCoordinate && (lo_open ? v > lo : v >= lo) && v <= hi;
}

std::string ParameterRange::requirement(bool integer) const {
    if (integer) return "must be in " + format(lo) + ".." + format(hi);
    if (lo == 0.0 && hi == kMaxCoordinate) return lo_open ? "must be positive" : "must be ≥ 0";
    if (lo == -kMaxCoordinate && hi == kMaxCoordinate) return "must be finite and within ±1e18";
    return std::string("must be in ") + (lo_open ? "(" : "[") + format(lo) + ", " + format(hi) + "]";
}

void set_parameter_value(double* number, int* integer, std::uint32_t* seed, double value) {
    if (number) *number = value;
    if (integer) *integer = int(std::lround(std::clamp(value, -2147483648.0, 2147483647.0)));
    if (seed) *seed = std::uint32_t(std::llround(std::clamp(value, 0.0, 4294967295.0)));
}

std::string parameter_problem(ParameterKind kind, const ParameterRange& range, double value) {
    if (range.contains(value)) return {};
    std::string what = std::abs(value) > kMaxCoordinate && std::isfinite(value)
                           ? "must be within ±1e18 (the coordinates and sizes cellfx renders)"
                           : range.requirement(kind == ParameterKind::Integer);
    return what + " (got " + format(value) + ")";
}

void check_parameter(const char* effect, const char* name, ParameterKind kind, const ParameterRange& range, double value) {
    const std::string problem = parameter_problem(kind, range, value);
    if (!problem.empty()) throw Error(std::string(effect) + ": " + name + " " + problem);
}

std::string parameter_problem(ParameterKind kind, const ParameterRange& range, const glm::dvec3& value) {
    bool finite = true, zero = true, in_range = true;
    for (int k = 0; k < 3; ++k) {
        finite = finite && std::isfinite(value[k]) && std::abs(value[k]) <= kMaxCoordinate;
        zero = zero && value[k] == 0.0;
        in_range = in_range && range.contains(value[k]);
    }
    const char* what = nullptr;
    if (kind == ParameterKind::Vector && !finite) what = "must be finite and within ±1e18 (the coordinates cellfx renders)";
    if (kind == ParameterKind::Direction && (!finite || zero)) what = "must be finite and non-zero";
    if (kind == ParameterKind::Extents && !in_range) what = "must be three positive extents";
    if (!what) return {};
    return std::string(what) + " (got " + format(value.x) + ", " + format(value.y) + ", " + format(value.z) + ")";
}

void check_parameter(const char* effect, const char* name, ParameterKind kind, const ParameterRange& range,
                     const glm::dvec3& value) {
    const std::string problem = parameter_problem(kind, range, value);
    if (!problem.empty()) throw Error(std::string(effect) + ": " + name + " " + problem);
}

template <>
const std::vector<Parameter<CampfireParams>>& parameter_table<CampfireParams>() {
    using P = CampfireParams;
    static const std::vector<Parameter<P>> table = {
        vector<P>("position", Kind::Vector, CELLFX_FIELD(P, position), kAny, Cost::Pose, "m",
                  "centre of the base"),
        number<P>("base_radius", CELLFX_FIELD(P, base_radius), kPositive, Cost::Rebuild, "m",
                  "flame radius at the base"),
        number<P>("height", CELLFX_FIELD(P, height), kPositive, Cost::Rebuild, "m",
                  "tip above the base"),
        number<P>("taper", CELLFX_FIELD(P, taper), kNonNegative, Cost::Rebuild, "",
                  "0 a column, 1 a cone, > 1 a spike"),
        integer<P>("cells_across", CELLFX_FIELD(P, cells_across), in(2, 256), Cost::Rebuild, "cells",
                  "hexahedra along x and along y"),
        integer<P>("cells_up", CELLFX_FIELD(P, cells_up), in(1, 256), Cost::Rebuild, "cells",
                  "hexahedra along z"),
        number<P>("intensity", CELLFX_FIELD(P, intensity), kNonNegative, Cost::Scalars, "",
                  "envelope gain; > 1 saturates the core"),
        number<P>("turbulence", CELLFX_FIELD(P, turbulence), kNonNegative, Cost::Scalars, "",
                  "how far the noise breaks the envelope up (gaps where turbulence·n < −1)"),
        number<P>("noise_frequency", CELLFX_FIELD(P, noise_frequency), kPositive, Cost::Scalars, "cycles/m",
                  "the noise's first octave, across"),
        number<P>("noise_stretch", CELLFX_FIELD(P, noise_stretch), kPositive, Cost::Scalars, "",
                  "tongues: noise features this much taller than wide"),
        integer<P>("noise_octaves", CELLFX_FIELD(P, noise_octaves), in(1, 8), Cost::Scalars, "",
                  "octaves of the noise"),
        number<P>("rise_speed", CELLFX_FIELD(P, rise_speed), kAny, Cost::Scalars, "m/s",
                  "the flicker rises through the envelope"),
        number<P>("flicker_rate", CELLFX_FIELD(P, flicker_rate), kAny, Cost::Scalars, "cells/s",
                  "the shapes change (the noise's time axis)"),
        seed<P>("seed", CELLFX_FIELD(P, seed), Cost::Scalars, "a different fire"),
    };
    return table;
}

template <>
const std::vector<Parameter<SearchLightParams>>& parameter_table<SearchLightParams>() {
    using P = SearchLightParams;
    static const std::vector<Parameter<P>> table = {
        vector<P>("position", Kind::Vector, CELLFX_FIELD(P, position), kAny, Cost::Pose, "m",
                  "lens centre"),
        vector<P>("direction", Kind::Direction, CELLFX_FIELD(P, direction), kAny, Cost::Pose, "",
                  "beam axis (any length)"),
        number<P>("range", CELLFX_FIELD(P, range), kPositive, Cost::Rebuild, "m",
                  "where the beam has faded to 0"),
        number<P>("spread_degrees", CELLFX_FIELD(P, spread_degrees), in(0, 60), Cost::Rebuild, "degrees",
                  "half-angle of the cone"),
        number<P>("lens_radius", CELLFX_FIELD(P, lens_radius), kPositive, Cost::Rebuild, "m",
                  "beam radius at the lens"),
        number<P>("intensity", CELLFX_FIELD(P, intensity), kNonNegative, Cost::Scalars, "",
                  "scalar on the axis at the lens"),
        integer<P>("segments", CELLFX_FIELD(P, segments), in(3, 256), Cost::Rebuild, "cells",
                  "cells around the axis"),
        integer<P>("rings", CELLFX_FIELD(P, rings), in(1, 64), Cost::Rebuild, "cells",
                  "cells from the axis to the rim"),
        integer<P>("slices", CELLFX_FIELD(P, slices), in(1, 1024), Cost::Rebuild, "cells",
                  "cells along the beam"),
        // The axis may be zero while nothing sweeps (SearchLight checks it against the amplitude).
        vector<P>("sweep.axis", Kind::Vector, CELLFX_FIELD(P, sweep.axis), kAny, Cost::Pose, "",
                  "the sweep turns the beam about it; non-zero when it sweeps"),
        number<P>("sweep.amplitude_degrees", CELLFX_FIELD(P, sweep.amplitude_degrees), in(0, 180), Cost::Pose, "degrees",
                  "how far the beam swings (0: no sweep)"),
        number<P>("sweep.period", CELLFX_FIELD(P, sweep.period), kPositive, Cost::Pose, "s",
                  "one swing there and back"),
        number<P>("sweep.phase_degrees", CELLFX_FIELD(P, sweep.phase_degrees), kAny, Cost::Pose, "degrees",
                  "where in the swing it starts"),
    };
    return table;
}

template <>
const std::vector<Parameter<LaserConeParams>>& parameter_table<LaserConeParams>() {
    using P = LaserConeParams;
    static const std::vector<Parameter<P>> table = {
        vector<P>("position", Kind::Vector, CELLFX_FIELD(P, position), kAny, Cost::Pose, "m",
                  "emitter"),
        vector<P>("direction", Kind::Direction, CELLFX_FIELD(P, direction), kAny, Cost::Pose, "",
                  "beam axis (any length)"),
        number<P>("range", CELLFX_FIELD(P, range), kPositive, Cost::Rebuild, "m",
                  "length of the beam"),
        number<P>("radius", CELLFX_FIELD(P, radius), kPositive, Cost::Rebuild, "m",
                  "beam radius at the emitter"),
        number<P>("divergence_degrees", CELLFX_FIELD(P, divergence_degrees), in(0, 10), Cost::Rebuild, "degrees",
                  "half-angle of the cone"),
        number<P>("intensity", CELLFX_FIELD(P, intensity), kNonNegative, Cost::Scalars, "",
                  "scalar on the axis"),
        number<P>("end_fade", CELLFX_FIELD(P, end_fade), in(0, 1), Cost::Scalars, "",
                  "fraction of the range over which it fades out (0: a hard end)"),
        integer<P>("segments", CELLFX_FIELD(P, segments), in(3, 64), Cost::Rebuild, "cells",
                  "cells around the axis"),
        integer<P>("slices", CELLFX_FIELD(P, slices), in(1, 4096), Cost::Rebuild, "cells",
                  "cells along the beam"),
        number<P>("dust_amount", CELLFX_FIELD(P, dust_amount), in(0, 1), Cost::Scalars, "",
                  "0 a clean beam … 1 visible only in the dust"),
        number<P>("dust_frequency", CELLFX_FIELD(P, dust_frequency), kPositive, Cost::Scalars, "cycles/m",
                  "the dust's first octave"),
        integer<P>("dust_octaves", CELLFX_FIELD(P, dust_octaves), in(1, 8), Cost::Scalars, "",
                  "octaves of the dust"),
        vector<P>("dust_drift", Kind::Vector, CELLFX_FIELD(P, dust_drift), kAny, Cost::Scalars, "m/s",
                  "the dust's wind, in the beam's frame (z along the beam)"),
        seed<P>("seed", CELLFX_FIELD(P, seed), Cost::Scalars, "a different dust"),
    };
    return table;
}

template <>
const std::vector<Parameter<VolumeParams>>& parameter_table<VolumeParams>() {
    using P = VolumeParams;
    constexpr auto box = [](const P& p) { return p.shape == VolumeShape::Box; };
    constexpr auto sphere = [](const P& p) { return p.shape == VolumeShape::Sphere; };
    constexpr auto not_mesh = [](const P& p) { return p.shape != VolumeShape::Mesh; };
    constexpr auto noisy = [](const P& p) { return p.density_mode == VolumeDensity::Noise; };
    static const std::vector<Parameter<P>> table = {
        vector<P>("position", Kind::Vector, CELLFX_FIELD(P, position), kAny, Cost::Pose, "m",
                  "centre of the box or sphere, origin of a mesh"),
        vector<P>("rotation_degrees", Kind::Vector, CELLFX_FIELD(P, rotation_degrees), kAny, Cost::Pose, "degrees",
                  "about x, then y, then z"),
        vector<P>("size", Kind::Extents, CELLFX_FIELD(P, size), kPositive, Cost::Rebuild, "m",
                  "a box's full extents, centred on position", box),
        number<P>("radius", CELLFX_FIELD(P, radius), kPositive, Cost::Rebuild, "m",
                  "a sphere's radius", sphere),
        // 0: automatic (1 for a constant box, 16 otherwise).
        integer<P>("cells", CELLFX_FIELD(P, cells), in(0, 256), Cost::Rebuild, "cells",
                  "cells across the largest extent of a box or sphere; 0 automatic (1 for a constant box without edge fade, 16 otherwise)", not_mesh),
        number<P>("density", CELLFX_FIELD(P, density), kNonNegative, Cost::Scalars, "",
                  "the scalar's scale (see the formulas)"),
        number<P>("edge_fade", CELLFX_FIELD(P, edge_fade), in(0, 1), Cost::Scalars, "",
                  "a box's or sphere's soft rim, as a fraction of the half extent", not_mesh),
        number<P>("noise.frequency", CELLFX_FIELD(P, noise.frequency), kPositive, Cost::Scalars, "cycles/m",
                  "noise density: the first octave", noisy),
        integer<P>("noise.octaves", CELLFX_FIELD(P, noise.octaves), in(1, 8), Cost::Scalars, "",
                  "noise density: octaves", noisy),
        number<P>("noise.coverage", CELLFX_FIELD(P, noise.coverage), in(0, 1), Cost::Scalars, "",
                  "noise density: the density where the noise is 0, as a fraction of density", noisy),
        number<P>("noise.contrast", CELLFX_FIELD(P, noise.contrast), kNonNegative, Cost::Scalars, "",
                  "noise density: how far the noise moves it", noisy),
        vector<P>("noise.drift", Kind::Vector, CELLFX_FIELD(P, noise.drift), kAny, Cost::Scalars, "m/s",
                  "noise density: the wind, in the volume's frame", noisy),
        number<P>("noise.evolve", CELLFX_FIELD(P, noise.evolve), kAny, Cost::Scalars, "cells/s",
                  "noise density: boiling (the noise's time axis)", noisy),
        seed<P>("noise.seed", CELLFX_FIELD(P, noise.seed), Cost::Scalars, "noise density: a different field", noisy),
    };
    return table;
}

#undef CELLFX_FIELD

} // namespace cellfx::fx
