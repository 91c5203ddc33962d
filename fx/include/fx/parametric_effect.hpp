// cellfx — the shared half of the effects built from a parameter struct (fx::Campfire,
// fx::SearchLight, fx::LaserCone, fx::Volume): what a parameter change costs and the update
// that does only that.
//
// A parametric effect's set_params() checks the new parameters, tells this base what the change
// costs (fx::change_cost, read from the parameter table of fx/effect_parameters.hpp: any changed
// field whose cost is `rebuild` rebuilds, else any whose cost is `scalars` re-evaluates, else the
// change is a pose) and stores them. Its next update() then runs, in this order:
//   rebuild    build_mesh() — the mesh's points and cells, counted as a build; the effect's
//              scalar field is added here (zeros, one per point)
//   scalars    evaluate_scalars(time) — after a rebuild, after a change that costs scalars, and
//              whenever the time advanced and scalars_follow_time() (counted as a scalar update
//              unless it follows a rebuild)
//   pose       nothing here: Effect::update() compares the transform
// so an effect supplies only those two hooks, and the steady frame of a still effect does
// nothing at all. Nothing here allocates after the first build.
#pragma once

#include <string>

#include "fx/effect.hpp"

namespace cellfx::fx {

// What a parameter change costs at the next update, cheapest first (the order is the one
// change_cost takes the largest of).
enum class ParameterCost {
    Pose = 0,    // only the transform: nothing rebuilt or uploaded
    Scalars = 1, // the scalars are re-evaluated on the same cells
    Rebuild = 2, // the mesh is built again (and its scalars evaluated)
};
const char* parameter_cost_name(ParameterCost cost); // "pose", "scalars", "rebuild"

class ParametricEffect : public Effect {
public:
    // Time of the scalars in mesh() (NaN before the first evaluation).
    double sampled_time() const { return sampled_time_; }

protected:
    explicit ParametricEffect(std::string scalar_name);

    // For set_params(): the next update() does what `cost` asks (on top of anything still
    // pending). Call it after the new parameters were checked, before storing them.
    void parameters_changed(ParameterCost cost);

    // Builds mesh_'s points and cells from the parameters (scalars it carries are replaced).
    virtual void build_mesh() = 0;
    // Writes mesh_.scalars[0] (one value per point) for the parameters at `time`.
    virtual void evaluate_scalars(double time) = 0;
    // True when the scalars depend on the time (animated noise); a pose that moves with time
    // (a sweep) does not count.
    virtual bool scalars_follow_time() const { return false; }

private:
    EffectChanges simulate(const EffectView& view) final;

    bool dirty_mesh_ = true, dirty_scalars_ = true;
    double sampled_time_;
};

} // namespace cellfx::fx
