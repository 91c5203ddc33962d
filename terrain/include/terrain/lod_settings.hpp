// cellfx terrain — the continuous LOD's settings (terrain::ContinuousLod takes them;
// continuous_lod.hpp). A value header: scenes include this, not the LOD.
#pragma once

namespace cellfx::terrain {

struct LodSettings {
    // Röttger's C (> 1): nodes closer than C times their size are always split, whatever
    // their roughness; it also fixes K = C / (2(C − 1)) for the d2 propagation.
    double min_resolution = 4.0;
    bool geomorph = true;
    // Geomorph weights move in steps of 1/morph_steps (0: continuously, every node re-examined
    // every frame). A morphing node is then looked at again only when the eye has moved far
    // enough for its weight to reach the next step, and its vertices change only then: a moving
    // camera updates a fraction of the morphing vertices per frame. A step moves a vertex by at
    // most 1/morph_steps of its node's height error, which is under 2τ pixels while it morphs: at
    // 8 steps under τ/4 pixels (τ: the LOD's pixel error bound). 0 to 4096.
    int morph_steps = 8;
};

} // namespace cellfx::terrain
