// The parametric effects' change bookkeeping and update (fx/parametric_effect.hpp).
#include "fx/parametric_effect.hpp"

#include <limits>
#include <utility>

namespace cellfx::fx {

const char* parameter_cost_name(ParameterCost cost) {
    switch (cost) {
    case ParameterCost::Pose: return "pose";
    case ParameterCost::Scalars: return "scalars";
    case ParameterCost::Rebuild: return "rebuild";
    }
    return "?";
}

ParametricEffect::ParametricEffect(std::string scalar_name)
    : Effect(std::move(scalar_name)), sampled_time_(std::numeric_limits<double>::quiet_NaN()) {}

void ParametricEffect::parameters_changed(ParameterCost cost) {
    if (cost == ParameterCost::Rebuild) dirty_mesh_ = true;
    if (cost >= ParameterCost::Scalars) dirty_scalars_ = true;
}

EffectChanges ParametricEffect::simulate(const EffectView& view) {
    EffectChanges changes;
    if (dirty_mesh_) {
        build_mesh();
        mesh_.scalars.clear();
        mesh_.scalars.push_back({scalar_name(), std::vector<float>(mesh_.points.size(), 0.0f)});
        count_build();
        dirty_mesh_ = false;
        dirty_scalars_ = true;
        changes.mesh = true;
    }
    if (dirty_scalars_ || (scalars_follow_time() && view.time != sampled_time_)) {
        evaluate_scalars(view.time);
        sampled_time_ = view.time;
        dirty_scalars_ = false;
        if (!changes.mesh) {
            changes.scalars = true;
            count_scalar_update();
        }
    }
    return changes;
}

} // namespace cellfx::fx
