// cellfx — the effects' parameters described once: for each field of fx::CampfireParams,
// fx::SearchLightParams, fx::LaserConeParams and fx::VolumeParams its name (the scene file's key),
// its kind, the range the effect accepts, its unit and what changing it costs.
//
// The effects' constructors and set_params() check their parameters against these tables
// (check_parameters), so a tool that reads them offers exactly what the library accepts: the
// samples' tuning panel builds its sliders from them, the scene writer its keys.
//
//     for (const fx::Parameter<fx::CampfireParams>& p : fx::parameter_table<fx::CampfireParams>())
//         if (p.kind == fx::ParameterKind::Number)
//             slider(p.name, fx::parameter_value(p, params), p.range.lo, p.range.hi);
//
// Checks that tie parameters together (a sweep's axis only when it sweeps, a mesh volume's
// field, the effect-cells budget) stay in each effect's own constructor.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "fx/campfire.hpp"
#include "fx/cell_mesh.hpp"
#include "fx/laser_cone.hpp"
#include "fx/search_light.hpp"
#include "fx/volume.hpp"

namespace cellfx::fx {

enum class ParameterKind {
    Number,    // a double within `range`
    Integer,   // an int within `range`
    Seed,      // a std::uint32_t: any value
    Vector,    // a dvec3, each component finite and within ±kMaxCoordinate (positions, drifts)
    Direction, // a dvec3, finite and not zero (any length)
    Extents,   // a dvec3 of lengths, each within `range`
};

// What a change costs at the effect's next update: fx::ParameterCost (fx/parametric_effect.hpp).

// The values a Number, Integer or Extents component may take: lo ≤ v ≤ hi (lo < v with
// lo_open), and always finite within ±kMaxCoordinate.
struct ParameterRange {
    double lo = -kMaxCoordinate, hi = kMaxCoordinate;
    bool lo_open = false;
    bool contains(double v) const;
    // "must be positive", "must be ≥ 0", "must be in [0, 60]", "must be in 2..256" (integer),
    // "must be finite and within ±1e18".
    std::string requirement(bool integer) const;
};

template <class Params>
struct Parameter {
    const char* name;     // the scene file's key; "sweep.period": key "period" of the object "sweep"
    ParameterKind kind;
    ParameterRange range; // Number, Integer; each component of Extents
    ParameterCost cost;
    const char* unit;     // "m", "degrees", "cells", "m/s", ... ("" for a pure number)
    const char* what;     // what it does, for people (the docs' tables, a tool's tooltip)
    // The field: `number` for Number, `integer` for Integer, `seed` for Seed, `vector` otherwise.
    double* (*number)(Params&) = nullptr;
    int* (*integer)(Params&) = nullptr;
    std::uint32_t* (*seed)(Params&) = nullptr;
    glm::dvec3* (*vector)(Params&) = nullptr;
    // Whether the parameter means anything for these parameters (a volume's size only for a box,
    // its noise only with noise density); nullptr: always. Checked all the same.
    bool (*applies)(const Params&) = nullptr;

    bool applies_to(const Params& p) const { return !applies || applies(p); }
    bool scalar() const { return kind == ParameterKind::Number || kind == ParameterKind::Integer || kind == ParameterKind::Seed; }
};

// The table of each parameter type, in the order of its struct (effect_parameters.cpp).
template <class Params>
const std::vector<Parameter<Params>>& parameter_table();
template <>
const std::vector<Parameter<CampfireParams>>& parameter_table<CampfireParams>();
template <>
const std::vector<Parameter<SearchLightParams>>& parameter_table<SearchLightParams>();
template <>
const std::vector<Parameter<LaserConeParams>>& parameter_table<LaserConeParams>();
template <>
const std::vector<Parameter<VolumeParams>>& parameter_table<VolumeParams>();

// The entry named `name`, or nullptr.
template <class Params>
const Parameter<Params>* find_parameter(const std::string& name) {
    for (const Parameter<Params>& p : parameter_table<Params>())
        if (name == p.name) return &p;
    return nullptr;
}

// A Number, Integer or Seed as a double (exact for every int and std::uint32_t).
template <class Params>
double parameter_value(const Parameter<Params>& p, const Params& params) {
    Params& v = const_cast<Params&>(params); // the accessors only point into it
    return p.number ? *p.number(v) : p.integer ? double(*p.integer(v)) : p.seed ? double(*p.seed(v)) : 0.0;
}
// Sets a Number, Integer or Seed (integers rounded to the nearest; nothing is checked: see
// check_parameters).
void set_parameter_value(double* number, int* integer, std::uint32_t* seed, double value);
template <class Params>
void set_parameter_value(const Parameter<Params>& p, Params& params, double value) {
    set_parameter_value(p.number ? p.number(params) : nullptr, p.integer ? p.integer(params) : nullptr,
                        p.seed ? p.seed(params) : nullptr, value);
}
template <class Params>
glm::dvec3 parameter_vector(const Parameter<Params>& p, const Params& params) {
    return p.vector ? *p.vector(const_cast<Params&>(params)) : glm::dvec3(0.0);
}

// Whether `p`'s field differs between two parameter sets (exact comparison).
template <class Params>
bool parameter_differs(const Parameter<Params>& p, const Params& a, const Params& b) {
    if (p.vector) return parameter_vector(p, a) != parameter_vector(p, b);
    return parameter_value(p, a) != parameter_value(p, b);
}

// What changing `from` into `to` costs: the largest cost of the table's fields that differ
// (Pose when none does). Fields the table does not describe (a volume's shape, mesh, field or
// density mode) are the effect's own to compare.
template <class Params>
ParameterCost change_cost(const Params& from, const Params& to) {
    ParameterCost cost = ParameterCost::Pose;
    for (const Parameter<Params>& p : parameter_table<Params>())
        if (p.cost > cost && parameter_differs(p, from, to)) cost = p.cost;
    return cost;
}

// What is wrong with a value for a parameter of this kind and range ("must be positive (got
// 0)", "must be finite and non-zero (got 0, 0, 0)"), or "" when it is fine: the one wording of
// the effects' checks and the scene parser's.
std::string parameter_problem(ParameterKind kind, const ParameterRange& range, double value);
std::string parameter_problem(ParameterKind kind, const ParameterRange& range, const glm::dvec3& value);

// Throws fx::Error("<effect>: <name> must be ... (got <value>)") for the first parameter
// outside its table's range.
void check_parameter(const char* effect, const char* name, ParameterKind kind, const ParameterRange& range, double value);
void check_parameter(const char* effect, const char* name, ParameterKind kind, const ParameterRange& range,
                     const glm::dvec3& value);
template <class Params>
void check_parameters(const Params& params, const char* effect) {
    for (const Parameter<Params>& p : parameter_table<Params>()) {
        if (p.vector) check_parameter(effect, p.name, p.kind, p.range, parameter_vector(p, params));
        else if (p.number) check_parameter(effect, p.name, p.kind, p.range, parameter_value(p, params));
        else if (p.integer) check_parameter(effect, p.name, p.kind, p.range, parameter_value(p, params));
    }
}

} // namespace cellfx::fx
