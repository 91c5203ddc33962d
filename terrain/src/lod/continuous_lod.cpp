// Based on: Röttger, Heidrich, Slusallek & Seidel 1998, "Real-Time Generation of Continuous
// Levels of Detail for Height Fields": §3 (quadtree in a matrix of node centres, refinement
// criterion f = l / (d·C·max(c·d2, 1)), d2 propagation with K = C / (2(C − 1)), triangle fans)
// and §4 (geomorphing with the refinement value). The incremental update (nodes re-examined
// only once the eye has moved far enough to change them) is ours; see continuous_lod.hpp.
#include "terrain/continuous_lod.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <limits>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include "fx/error.hpp"

namespace cellfx::terrain {

namespace {

// Node state, indexed by the node's centre sample.
enum : std::uint8_t { kLive = 1, kSplit = 2, kMorph = 4 };
// Per-update bookkeeping flags (cleared at the end of every update).
enum : std::uint8_t { kCandidate = 1, kEvaluated = 2, kVertexDirty = 4, kFanDirty = 8 };
constexpr int kLevels = 15; // half sizes 1 .. 2^14
constexpr std::int32_t kNoFan = -1;

// log2 of a half size (a power of two).
int level_of(int h) { return __builtin_ctz(unsigned(h)); }

// A sleeping node's wake-up: due once the odometer reaches `at`. The odometer bounds every
// direction of travel by the fastest, so a due node is first checked against the exact test of
// its own f — the eye's distance to its centre within (lo, hi) keeps it as it is — and, while
// that holds and the coarser nodes that constrain it cannot have changed it (the odometer under
// `constraint_at`), put back to sleep without being evaluated: on a sideways flight most due
// nodes are still far from their thresholds (their distance changed little).
struct Wake {
    double at;               // odometer value at which the node must be looked at again
    double constraint_at;    // odometer value at which its constraint may have changed it
    float lo, hi;            // the distances to its centre between which its own f keeps it
    std::uint32_t node;
    std::uint32_t generation; // stale entries (rescheduled or removed nodes) are skipped
    bool operator>(const Wake& o) const { return at > o.at; }
};

// A morphing node's wake-up: due once the odometer reaches `at`, or once the eye's distance to
// the node's centre leaves (√lo2, √hi2) — the exact interval over which its own f keeps its
// stepped blend. The distance test follows the eye itself rather than its path length, which
// bounds every direction of travel by the fastest (a sideways flight woke six times the nodes
// that changed). Scanned in order every frame, so the centre is kept here: no node is read
// until it is due.
struct MorphWake {
    double at;
    double cx, cy, cz;
    double lo2, hi2;
    std::uint32_t node;
    std::uint32_t generation;
};

// A min-heap of wake-ups on a vector whose storage is kept: cleared and compacted in place, so a
// steady frame allocates nothing for it.
struct WakeHeap {
    std::vector<Wake> items;
    bool empty() const { return items.empty(); }
    std::size_t size() const { return items.size(); }
    const Wake& top() const { return items.front(); }
    void push(const Wake& w) {
        items.push_back(w);
        std::push_heap(items.begin(), items.end(), std::greater<Wake>());
    }
    void pop() {
        std::pop_heap(items.begin(), items.end(), std::greater<Wake>());
        items.pop_back();
    }
    void clear() { items.clear(); }
    template <class Stale>
    void remove_if(Stale stale) {
        items.erase(std::remove_if(items.begin(), items.end(), stale), items.end());
        std::make_heap(items.begin(), items.end(), std::greater<Wake>());
    }
};

// One leaf's triangle fan: its centre and the ring of corners and included edge midpoints,
// counter-clockwise from above.
struct Fan {
    std::uint32_t node;
    std::uint32_t count;
    std::uint32_t ring[8];
};

} // namespace

LodView LodView::from_camera(const fx::Camera& camera, int viewport_height, double pixel_error,
                             std::size_t triangle_budget) {
    if (viewport_height <= 0) throw fx::Error("terrain LOD: viewport height must be positive");
    LodView view;
    view.eye = camera.eye;
    view.pixel_error = pixel_error;
    view.triangle_budget = triangle_budget;
    if (camera.orthographic()) {
        const double distance = glm::length(camera.target - camera.eye);
        view.projection_scale = viewport_height / camera.ortho_height * std::max(distance, 1e-9);
    } else {
        view.projection_scale = viewport_height / (2.0 * std::tan(0.5 * glm::radians(camera.fov_y_degrees)));
    }
    return view;
}

struct ContinuousLod::Impl {
    HeightField ground;
    std::optional<HeightField> layer;
    LodSettings settings;
    int n = 0;        // samples per side
    int root_h = 0;   // root half size
    std::uint32_t root = 0;
    double K = 1.0;

    // Per-sample data packed so one node (or one vertex) is one cache access: the update walks
    // the quadtree in a scattered order.
    struct Node {
        float d2 = 0.0f;
        float fe = 0.0f;                 // f_eff memo, valid when fe_frame == frame
        float blend = 0.0f;              // the morph weight of its last evaluation (blend())
        std::uint32_t fe_frame = 0;
        std::uint32_t generation = 0;    // bumped when the node is rescheduled or removed
        std::int32_t fan = kNoFan;
        std::uint32_t fan_changed = 0;   // the frame it last went into changes.fan_nodes
        std::uint16_t i = 0, j = 0;      // the sample's grid coordinates (no division by n)
        float true_h = 0.0f;             // the sample's height (a copy of its vertex's: own_f() reads it with the node)
        std::uint8_t state = 0, flags = 0;
        // Its constraint is at most constraint_base + odometer / T_N (evaluate()): +∞ until its
        // constraint chain was walked with this odometer and T_N.
        double constraint_base = std::numeric_limits<double>::infinity();
    };
    struct Vertex {
        float true_h = 0.0f, true_t = 0.0f; // the fields' samples
        float h = 0.0f, t = 0.0f;           // geomorphed height and thickness
        std::uint32_t local = std::numeric_limits<std::uint32_t>::max(); // extract(): vertex id
        std::uint32_t changed = 0;          // the frame it last went into changes.vertices
        std::uint16_t i = 0, j = 0;         // the sample's grid coordinates (read with its height)
    };
    std::vector<Node> nodes;
    mutable std::vector<Vertex> verts;
    std::vector<Fan> fans;
    std::size_t triangles = 0;
    std::size_t live = 0;
    WakeHeap wakes;
    std::vector<MorphWake> morph_wakes; // the morphing nodes' (stepped geomorphing), unordered
    std::vector<std::uint32_t> morphing, next_morphing;
    std::array<std::vector<std::uint32_t>, kLevels> candidates, vertex_dirty;
    std::vector<std::uint32_t> fan_dirty, touched;
    LodChanges changes;                   // of the last update
    std::vector<std::uint32_t> fan_changed; // per fan slot: the frame it last went into changes.fans
    std::size_t morphing_count = 0;         // split nodes with 0 < b < 1
    // A layer thinner than this is no layer: a millionth of the longest edge a triangle of the
    // field can have (build_layer_prisms' rule is relative to the triangle's own longest edge).
    double thin_layer = 0.0;

    std::uint32_t frame = 0;
    double odometer = 0.0;
    glm::dvec3 last_eye{0.0};
    bool have_state = false;
    LodView last_view;
    double c_user = 0.0, c_eff = 0.0, budget_scale = 1.0;
    LodStats* stats = nullptr;

    // ---- geometry of the quadtree ----
    int ix(std::uint32_t s) const { return nodes[s].i; }
    int jy(std::uint32_t s) const { return nodes[s].j; }
    std::uint32_t id(int i, int j) const { return std::uint32_t(j) * std::uint32_t(n) + std::uint32_t(i); }
    bool center(int i, int j) const {
        return i > 0 && j > 0 && i < n - 1 && j < n - 1 && (i & -i) == (j & -j);
    }
    int half_size(std::uint32_t s) const { const int i = ix(s); return i & -i; }
    // A vertex's coordinates, from its own record (a vertex is rarely a node looked at in the
    // same frame: reading the node's would cost a cache miss).
    int vx(std::uint32_t v) const { return verts[v].i; }
    int vy(std::uint32_t v) const { return verts[v].j; }
    float true_height(std::uint32_t s) const { return verts[s].true_h; }
    float true_thickness(std::uint32_t s) const { return verts[s].true_t; }
    glm::dvec3 center_position(std::uint32_t s) const {
        return {ground.x(ix(s)), ground.y(jy(s)), double(nodes[s].true_h)};
    }
    // Centre of the parent of node (i, j, h): the odd multiple of 2h among i ± h.
    // (i − h = 2h·k: k is odd exactly when bit 2h of i − h is set.)
    int parent_coord(int i, int h) const { return ((i - h) & (2 * h)) ? i - h : i + h; }
    // The coarser nodes a split of (i, j, h) needs split too: its parent and the parent's
    // neighbours across the two parent edges the node touches. Returns how many (≤ 3).
    int required(int i, int j, int h, std::uint32_t out[3]) const {
        const int pi = parent_coord(i, h), pj = parent_coord(j, h);
        int k = 0;
        out[k++] = id(pi, pj);
        const int qi = pi + (i > pi ? 4 * h : -4 * h), qj = pj + (j > pj ? 4 * h : -4 * h);
        if (qi > 0 && qi < n - 1) out[k++] = id(qi, pj);
        if (qj > 0 && qj < n - 1) out[k++] = id(pi, qj);
        return k;
    }
    // Same-size neighbour across side s (0 south, 1 east, 2 north, 3 west), or false at the border.
    bool neighbour(int i, int j, int h, int s, std::uint32_t& out) const {
        static const int di[4] = {0, 1, 0, -1}, dj[4] = {-1, 0, 1, 0};
        const int a = i + 2 * h * di[s], b = j + 2 * h * dj[s];
        if (a <= 0 || b <= 0 || a >= n - 1 || b >= n - 1) return false;
        out = id(a, b);
        return true;
    }

    // ---- refinement ----
    double node_scale(std::uint32_t s, int h) const { // T_N = d·C·max(c·d2, 1)
        return 2.0 * h * ground.spacing * settings.min_resolution * std::max(c_eff * double(nodes[s].d2), 1.0);
    }
    // The node's own f, given its T_N.
    double own_f(std::uint32_t s, double scale) const { return glm::length(last_eye - center_position(s)) / scale; }
    // The largest f_eff of the coarser nodes a split of s needs (0 for the root).
    double constraint(std::uint32_t s, int h) {
        double f = 0.0;
        if (s != root) {
            std::uint32_t req[3];
            const int k = required(ix(s), jy(s), h, req);
            for (int q = 0; q < k; ++q) f = std::max(f, f_eff(req[q], 2 * h));
        }
        return f;
    }
    // f_eff = max(own f, constraint), memoized per frame (`own` and `constraint` when the caller
    // has them).
    double f_eff(std::uint32_t s, int h, double own = -1.0, double constrained_by = -1.0) {
        if (nodes[s].fe_frame == frame) return nodes[s].fe;
        ++stats->nodes_evaluated;
        if (own < 0.0) own = own_f(s, node_scale(s, h));
        if (constrained_by < 0.0) constrained_by = constraint(s, h);
        nodes[s].fe = float(std::max(own, constrained_by));
        nodes[s].fe_frame = frame;
        return nodes[s].fe;
    }
    // The node's geomorph weight b = 2(1 − f_eff) in (0, 1) while it morphs, in steps of
    // 1/morph_steps (LodSettings; continuous with none), from its own last evaluation — not the
    // memo a finer node's constraint chain may have refreshed since: its vertices were computed
    // with this one.
    double morph_blend(double f) const {
        const double b = std::clamp(2.0 * (1.0 - f), 0.0, 1.0);
        if (settings.morph_steps <= 0) return b;
        return std::round(b * settings.morph_steps) / settings.morph_steps;
    }
    double blend(std::uint32_t s) const {
        const std::uint8_t st = nodes[s].state;
        if (!(st & kSplit)) return 0.0;
        if (!settings.geomorph || !(st & kMorph)) return 1.0;
        return nodes[s].blend;
    }

    void mark(std::uint32_t s, std::uint8_t flag) {
        if (!nodes[s].flags) touched.push_back(s);
        if (nodes[s].flags & flag) return;
        nodes[s].flags |= flag;
        if (flag == kFanDirty) fan_dirty.push_back(s);
        if (flag == kVertexDirty) vertex_dirty[level_of(half_size(s))].push_back(s);
        if (flag == kCandidate) {
            // A node is a candidate at most once, so a level's list never holds more than the
            // level's live nodes: room for them all (while the tree grows) keeps the frames
            // that flag the most candidates from allocating.
            std::vector<std::uint32_t>& list = candidates[level_of(half_size(s))];
            if (list.size() == list.capacity()) list.reserve(std::max<std::size_t>(2 * list.capacity(), live + 16));
            list.push_back(s);
        }
    }
    void mark_neighbours_changed(int i, int j, int h) {
        for (int side = 0; side < 4; ++side) {
            std::uint32_t m;
            if (!neighbour(i, j, h, side, m) || !(nodes[m].state & kLive)) continue;
            mark(m, kFanDirty);
            if (nodes[m].state & kSplit) mark(m, kVertexDirty); // the shared midpoint's blend changed
        }
    }

    // `own` is the node's own f and `constrained_by` the largest f_eff of the coarser nodes it
    // needs split (f = max of the two); `scale` its T_N.
    void schedule(std::uint32_t s, double scale, double f, double own, double constrained_by) {
        const bool split = nodes[s].state & kSplit;
        const bool was_morphing = nodes[s].state & kMorph;
        double margin = 0.0;
        if (split && settings.geomorph && f > 0.5) {
            nodes[s].state |= kMorph;
            if (settings.morph_steps <= 0) {
                morphing_count += was_morphing ? 0 : 1;
                next_morphing.push_back(s);
                ++nodes[s].generation; // no wake-up needed: looked at every frame
                return;
            }
            // Looked at again when b·steps may cross a half step (its rounded value changes) or f
            // may leave (0.5, 1): b = 2(1 − f), so f moves by 1/(2·steps) per step of b. The
            // blend holds while f stays in (f_lo, f_hi).
            const int steps = settings.morph_steps;
            const double x = 2.0 * (1.0 - f) * steps;
            const double x_lo = std::floor(x - 0.5) + 0.5; // the half steps either side of x
            const double f_hi = std::min(1.0, 1.0 - x_lo / (2.0 * steps));
            const double f_lo = std::max(0.5, 1.0 - (x_lo + 1.0) / (2.0 * steps));
            morphing_count += was_morphing ? 0 : 1;
            MorphWake w{0.0, 0.0, 0.0, 0.0, -1.0, std::numeric_limits<double>::infinity(), s, ++nodes[s].generation};
            if (constrained_by < own) {
                // f is its own: it holds while the eye's distance to the centre stays in
                // (f_lo·T, f_hi·T) and the constraint stays under f_hi (|Δf_eff| ≤ |Δeye| / T).
                const glm::dvec3 c = center_position(s);
                const double lo = f_lo * scale * (1.0 + 1e-6), hi = f_hi * scale * (1.0 - 1e-6);
                w.cx = c.x, w.cy = c.y, w.cz = c.z;
                w.lo2 = lo * lo, w.hi2 = hi * hi;
                w.at = odometer + std::max(f_hi - constrained_by, 0.0) * scale * (1.0 - 1e-6);
            } else {
                w.at = odometer + std::max(std::min(f - f_lo, f_hi - f), 0.0) * scale * (1.0 - 1e-6);
            }
            morph_wakes.push_back(w);
            return;
        } else {
            nodes[s].state &= std::uint8_t(~kMorph);
            margin = split ? (settings.geomorph ? 0.5 - f : 1.0 - f) : f - 1.0;
        }
        const bool now_morphing = nodes[s].state & kMorph;
        morphing_count = morphing_count + (now_morphing ? 1 : 0) - (was_morphing ? 1 : 0);
        // |Δf_eff| ≤ |Δeye| / T_N (module comment); a hair less so rounding cannot skip a crossing.
        const double travel = std::max(margin, 0.0) * scale * (1.0 - 1e-6);
        // A heap for the nodes not morphing: they may sleep for a long flight (the morphing ones,
        // due every few frames, are in a list scanned once a frame: see above and advance()).
        Wake w{odometer + travel, odometer + travel, 0.0f, std::numeric_limits<float>::infinity(), s,
               ++nodes[s].generation};
        if (split) {
            // Changes once f_eff reaches the threshold: its own f (the distance reaching
            // threshold·T) or its constraint (by the odometer).
            const double threshold = settings.geomorph ? 0.5 : 1.0;
            w.hi = float_below(threshold * scale * (1.0 - 1e-6));
            w.constraint_at = odometer + std::max(threshold - constrained_by, 0.0) * scale * (1.0 - 1e-6);
        } else if (own >= 1.0) {
            // Splits only once its own f drops under 1 (distance under T), whatever its constraint.
            w.lo = float_above(scale * (1.0 + 1e-6));
            w.constraint_at = std::numeric_limits<double>::infinity();
        } // else held unsplit by its constraint alone (the K bound failed): the odometer alone
        wakes.push(w);
    }
    // The nearest float at or beyond x, each way (a sleep interval may only shrink).
    static float float_below(double x) {
        const float f = float(x);
        return double(f) <= x ? f : std::nextafter(f, -std::numeric_limits<float>::infinity());
    }
    static float float_above(double x) {
        const float f = float(x);
        return double(f) >= x ? f : std::nextafter(f, std::numeric_limits<float>::infinity());
    }

    void evaluate(std::uint32_t s, int h) {
        if (nodes[s].flags & kEvaluated) return;
        mark(s, kEvaluated);
        ++stats->nodes_examined;
        const std::uint8_t before = nodes[s].state;
        const double blend_before = blend(s); // from its last evaluation
        // The coarser nodes' f_eff move by at most |Δeye| / T_N (module comment): while that
        // bound, from the last walk of its constraint chain, stays under its own f, f_eff is
        // its own f and the chain is not walked (an upper bound is all schedule() needs).
        const double scale = node_scale(s, h), own = own_f(s, scale);
        double constrained_by = nodes[s].constraint_base + odometer / scale;
        if (!(constrained_by < own * (1.0 - 1e-6))) {
            constrained_by = constraint(s, h);
            nodes[s].constraint_base = constrained_by - odometer / scale;
        }
        const double f = f_eff(s, h, own, constrained_by);
        nodes[s].blend = float(morph_blend(f));
        if (f > own * (1.0 + 1e-6) && f >= 0.5) ++stats->constrained;
        const bool want = f < 1.0;
        if (want && !(before & kSplit)) split(s, h);
        else if (!want && (before & kSplit)) merge(s, h);
        schedule(s, scale, f, own, constrained_by);
        const std::uint8_t after = nodes[s].state;
        if ((before & (kMorph | kSplit)) != (after & (kMorph | kSplit)) || blend(s) != blend_before)
            mark(s, kVertexDirty);
    }

    void split(std::uint32_t s, int h) {
        nodes[s].state |= kSplit;
        ++stats->splits;
        const int i = ix(s), j = jy(s);
        mark(s, kFanDirty);
        mark_neighbours_changed(i, j, h);
        if (h < 2) return; // the smallest nodes split into their full 8-triangle fan
        const int q = h / 2;
        for (int c = 0; c < 4; ++c) {
            const std::uint32_t child = id(i + ((c & 1) ? q : -q), j + ((c & 2) ? q : -q));
            nodes[child].state = kLive;
            ++live;
            mark(child, kFanDirty);
            evaluate(child, q);
        }
    }

    void merge(std::uint32_t s, int h) {
        if (nodes[s].state & kMorph) --morphing_count;
        nodes[s].state &= std::uint8_t(~(kSplit | kMorph));
        ++stats->merges;
        const int i = ix(s), j = jy(s);
        if (h >= 2) {
            const int q = h / 2;
            for (int c = 0; c < 4; ++c) remove(id(i + ((c & 1) ? q : -q), j + ((c & 2) ? q : -q)), q);
        }
        mark(s, kFanDirty);
        mark_neighbours_changed(i, j, h);
    }

    // Drops a live node and its subtree (its parent merged or the tree is rebuilt).
    void remove(std::uint32_t s, int h) {
        if (!(nodes[s].state & kLive)) return;
        const int i = ix(s), j = jy(s);
        if ((nodes[s].state & kSplit) && h >= 2) {
            const int q = h / 2;
            for (int c = 0; c < 4; ++c) remove(id(i + ((c & 1) ? q : -q), j + ((c & 2) ? q : -q)), q);
        }
        const bool was_split = nodes[s].state & kSplit;
        if (nodes[s].state & kMorph) --morphing_count;
        nodes[s].state = 0;
        --live;
        ++nodes[s].generation;
        nodes[s].constraint_base = std::numeric_limits<double>::infinity(); // the odometer restarts on a rebuild
        drop_fan(s);
        if (was_split) mark_neighbours_changed(i, j, h);
    }

    // ---- geomorphing ----
    // Returns whether the vertex changed (then it is in changes.vertices).
    bool morph_vertex(std::uint32_t v, std::uint32_t a, std::uint32_t b, double w) {
        // (1 − w)·coarse + w·true: exactly the true value at w = 1, the coarse one at w = 0.
        Vertex& x = verts[v];
        const float h = float((1.0 - w) * 0.5 * (double(verts[a].h) + verts[b].h) + w * true_height(v));
        const float t = layer ? float((1.0 - w) * 0.5 * (double(verts[a].t) + verts[b].t) + w * true_thickness(v)) : x.t;
        if (w > 0.0 && w < 1.0) ++stats->vertices_morphed;
        if (h == x.h && t == x.t) return false;
        // A prism stands on a triangle whose corners carry thickness: when this vertex's
        // thickness appears or vanishes, the fans around it say so (LodChanges).
        if (layer && (x.t > thin_layer) != (t > thin_layer)) fans_touching_changed(v);
        x.h = h, x.t = t;
        if (x.changed != frame) {
            x.changed = frame;
            changes.vertices.push_back(v);
            ++stats->vertices_changed;
        }
        return true;
    }
    void update_vertices(std::uint32_t s) {
        const int i = ix(s), j = jy(s), h = half_size(s);
        const double b = blend(s);
        static const int ci[4] = {-1, 1, 1, -1}, cj[4] = {-1, -1, 1, 1}; // SW SE NE NW
        bool changed = false;
        for (int side = 0; side < 4; ++side) {
            const int a = side, c = (side + 1) % 4; // side s runs from corner s to corner s + 1
            const std::uint32_t ka = id(i + ci[a] * h, j + cj[a] * h), kc = id(i + ci[c] * h, j + cj[c] * h);
            const std::uint32_t m = id(i + (ci[a] + ci[c]) * h / 2, j + (cj[a] + cj[c]) * h / 2);
            std::uint32_t other;
            const double bo = neighbour(i, j, h, side, other) && (nodes[other].state & kLive) ? blend(other) : 0.0;
            changed = morph_vertex(m, ka, kc, std::max(b, bo)) || changed;
        }
        // A split node's children's centres, at b = 0 too (a stepped blend rounds to 0 just
        // after the split: the centres sit where the coarse surface is).
        if (h >= 2 && (nodes[s].state & kSplit))
            for (int c = 0; c < 4; ++c) {
                const std::uint32_t k = id(i + ci[c] * h, j + cj[c] * h);
                changed = morph_vertex(id(i + ci[c] * h / 2, j + cj[c] * h / 2), s, k, b) || changed;
            }
        if (changed) mark_dependents(i, j, h);
    }
    // Every drawn fan that has sample v as its centre or in its ring, listed as changed.
    void fans_touching_changed(std::uint32_t v) {
        const int i = vx(v), j = vy(v);
        for (int h = 1; h <= root_h; h *= 2) {
            // The nodes of this size whose closed square holds v: centres at odd multiples of h
            // within h of it on both axes.
            for (int ci : {i - h, i, i + h})
                for (int cj : {j - h, j, j + h}) {
                    if (!center(ci, cj) || half_size(id(ci, cj)) != h) continue;
                    const std::int32_t f = nodes[id(ci, cj)].fan;
                    if (f == kNoFan) continue;
                    const Fan& fan = fans[std::size_t(f)];
                    bool in = fan.node == v;
                    for (std::uint32_t k = 0; k < fan.count && !in; ++k) in = fan.ring[k] == v;
                    if (in) fan_slot_changed(std::size_t(f)), fan_of_node_changed(fan.node);
                }
        }
    }
    // The nodes whose vertices blend between this node's (its edge midpoints and its children's
    // centres): its children, and each same-size neighbour's two children along the shared side.
    // Marked for their vertices to be recomputed after this node's (finer levels come later).
    void mark_dependents(int i, int j, int h) {
        if (h < 2) return;
        const int q = h / 2;
        const auto dirty = [&](int a, int b) {
            const std::uint32_t c = id(a, b);
            if ((nodes[c].state & kLive) && (nodes[c].state & kSplit)) mark(c, kVertexDirty);
        };
        for (int c = 0; c < 4; ++c) dirty(i + ((c & 1) ? q : -q), j + ((c & 2) ? q : -q));
        static const int di[4] = {0, 1, 0, -1}, dj[4] = {-1, 0, 1, 0};
        for (int side = 0; side < 4; ++side) {
            std::uint32_t other;
            if (!neighbour(i, j, h, side, other) || !(nodes[other].state & kLive) || !(nodes[other].state & kSplit)) continue;
            const int a = i + 2 * h * di[side], b = j + 2 * h * dj[side]; // other's centre
            if (di[side] != 0) dirty(a - di[side] * q, b - q), dirty(a - di[side] * q, b + q);
            else dirty(a - q, b - dj[side] * q), dirty(a + q, b - dj[side] * q);
        }
    }

    // ---- fans ----
    // Slot f holds another fan than before (LodChanges::fans, for slot-indexed consumers).
    void fan_slot_changed(std::size_t f) {
        if (fan_changed.size() <= f) fan_changed.resize(std::max(f + 1, fan_changed.size() + fan_changed.size() / 2), 0u);
        if (fan_changed[f] == frame) return;
        fan_changed[f] = frame;
        changes.fans.push_back(std::uint32_t(f));
    }
    // Node s's fan is new, different or gone (LodChanges::fan_nodes).
    void fan_of_node_changed(std::uint32_t s) {
        if (nodes[s].fan_changed == frame) return;
        nodes[s].fan_changed = frame;
        changes.fan_nodes.push_back(s);
    }
    void drop_fan(std::uint32_t s) {
        const std::int32_t f = nodes[s].fan;
        if (f == kNoFan) return;
        triangles -= fans[f].count;
        fans[f] = fans.back();
        nodes[fans[f].node].fan = f;
        fans.pop_back();
        nodes[s].fan = kNoFan;
        fan_of_node_changed(s);
        if (std::size_t(f) < fans.size()) fan_slot_changed(std::size_t(f)); // the last fan moved in
    }
    void rebuild_fan(std::uint32_t s) {
        const std::uint8_t st = nodes[s].state;
        const int h = half_size(s);
        const bool drawn = (st & kLive) && (!(st & kSplit) || h == 1);
        if (!drawn) {
            drop_fan(s);
            return;
        }
        const int i = ix(s), j = jy(s);
        Fan fan{s, 0, {}};
        static const int ci[4] = {-1, 1, 1, -1}, cj[4] = {-1, -1, 1, 1};
        for (int side = 0; side < 4; ++side) {
            fan.ring[fan.count++] = id(i + ci[side] * h, j + cj[side] * h);
            std::uint32_t other;
            const bool midpoint = (h == 1 && (st & kSplit)) ||
                                  (neighbour(i, j, h, side, other) && (nodes[other].state & kLive) && (nodes[other].state & kSplit));
            if (midpoint) {
                const int c = (side + 1) % 4;
                fan.ring[fan.count++] = id(i + (ci[side] + ci[c]) * h / 2, j + (cj[side] + cj[c]) * h / 2);
            }
        }
        if (nodes[s].fan == kNoFan) {
            nodes[s].fan = std::int32_t(fans.size());
            fans.push_back(fan);
        } else {
            Fan& old = fans[nodes[s].fan];
            if (old.count == fan.count && std::equal(fan.ring, fan.ring + fan.count, old.ring)) return; // as it was
            triangles -= old.count;
            old = fan;
        }
        ++stats->fans_rebuilt;
        triangles += fan.count;
        fan_slot_changed(std::size_t(nodes[s].fan));
        fan_of_node_changed(s);
    }

    // ---- storage ----
    // Room for the most a frame of this tree can list (a steady frame allocates nothing however
    // its work varies): a node is a candidate and has a wake-up once, a live node touches at most
    // 8 vertices and 1 fan. Grown with the tree only.
    std::size_t reserved_live = 0;
    void reserve_for_tree() {
        const std::size_t tree = std::max(live, std::size_t(1024));
        if (tree <= reserved_live) return;
        reserved_live = tree + tree / 2;
        for (auto& list : candidates) list.reserve(reserved_live);
        morph_wakes.reserve(3 * reserved_live); // up to the compaction threshold and a frame's pushes
        changes.vertices.reserve(8 * reserved_live);
        changes.vertex_heights.reserve(8 * reserved_live);
        changes.vertex_thicknesses.reserve(8 * reserved_live);
        changes.fans.reserve(reserved_live);
        changes.fan_nodes.reserve(reserved_live);
    }

    // ---- one update ----
    void finish_update() {
        for (int l = kLevels - 1; l >= 0; --l) {
            for (std::size_t k = 0; k < vertex_dirty[l].size(); ++k) {
                const std::uint32_t s = vertex_dirty[l][k];
                if (nodes[s].state & kLive) update_vertices(s);
            }
            vertex_dirty[l].clear();
        }
        for (std::uint32_t s : fan_dirty) rebuild_fan(s);
        fan_dirty.clear();
        for (std::uint32_t s : touched) nodes[s].flags = 0;
        touched.clear();
        morphing.swap(next_morphing);
        next_morphing.clear();
    }

    void rebuild() {
        remove(root, root_h);
        wakes.clear();
        morph_wakes.clear();
        morphing.clear();
        next_morphing.clear();
        odometer = 0.0;
        ++frame;
        stats->full_rebuild = true;
        changes.full = true;
        nodes[root].state = kLive;
        ++live;
        mark(root, kFanDirty);
        evaluate(root, root_h);
        finish_update();
    }

    void advance(const glm::dvec3& eye) {
        odometer += glm::length(eye - last_eye);
        last_eye = eye;
        ++frame;
        const auto wake = [&](std::uint32_t node, std::uint32_t generation) {
            if (generation == nodes[node].generation && (nodes[node].state & kLive) && !(nodes[node].flags & kCandidate)) {
                mark(node, kCandidate);
                ++stats->nodes_woken;
            }
        };
        while (!wakes.empty() && wakes.top().at <= odometer) {
            Wake w = wakes.top();
            wakes.pop();
            if (w.generation != nodes[w.node].generation) continue; // stale
            if (odometer < w.constraint_at) {
                // Its own f still keeps it while the distance to its centre stays in (lo, hi):
                // back to sleep for as far as the eye must travel to leave that interval.
                const double d = glm::length(eye - center_position(w.node));
                const double left = std::min(d - double(w.lo), double(w.hi) - d);
                if (left > 0.0 && odometer + left > odometer) {
                    w.at = std::min(w.constraint_at, odometer + left);
                    wakes.push(w);
                    continue;
                }
            }
            wake(w.node, w.generation);
        }
        // The morphing nodes' wake-ups: those due are woken (and rescheduled by evaluate()) or
        // dropped if stale, the rest kept in place without reading their nodes. The list is
        // unordered: a due entry takes the last one's place, so the kept ones are not copied.
        for (std::size_t k = 0; k < morph_wakes.size();) {
            const MorphWake& w = morph_wakes[k];
            const double dx = eye.x - w.cx, dy = eye.y - w.cy, dz = eye.z - w.cz;
            const double d2 = dx * dx + dy * dy + dz * dz;
            if (w.at <= odometer || !(d2 > w.lo2 && d2 < w.hi2)) {
                wake(w.node, w.generation);
                morph_wakes[k] = morph_wakes.back();
                morph_wakes.pop_back();
            } else {
                ++k;
            }
        }
        // Stale entries (nodes rescheduled early or removed) wait for their own condition: drop
        // them now and then.
        if (morph_wakes.size() > morphing_count + live / 2 + 1024)
            morph_wakes.erase(std::remove_if(morph_wakes.begin(), morph_wakes.end(),
                                             [&](const MorphWake& w) {
                                                 return w.generation != nodes[w.node].generation || !(nodes[w.node].state & kLive);
                                             }),
                              morph_wakes.end());
        for (std::uint32_t s : morphing)
            if (nodes[s].state & kLive) mark(s, kCandidate);
        for (int l = kLevels - 1; l >= 0; --l) {
            // evaluate() may split and append finer candidates' children; index, do not iterate.
            for (std::size_t k = 0; k < candidates[l].size(); ++k) {
                const std::uint32_t s = candidates[l][k];
                if (nodes[s].state & kLive) evaluate(s, 1 << l);
            }
            candidates[l].clear();
        }
        // Stale heap entries pile up when nodes are rescheduled often: compact now and then.
        const std::size_t most_wakes = 4 * live + 1024;
        if (wakes.size() > most_wakes)
            wakes.remove_if([&](const Wake& w) { return w.generation != nodes[w.node].generation || !(nodes[w.node].state & kLive); });
        // Room for the heap to fill up to the compaction threshold, and as much again for one
        // frame's pushes: it grows only when the tree does, not whenever stale entries pile up.
        if (wakes.items.capacity() < 2 * most_wakes) wakes.items.reserve(3 * most_wakes);
        finish_update();
    }

    void init(HeightField g, std::optional<HeightField> l, const LodSettings& s) {
        if (!is_lod_size(g.size) || g.heights.size() != std::size_t(g.size) * std::size_t(g.size))
            throw fx::Error("terrain LOD: the height field must have (2^n + 1)² samples, 3 ≤ 2^n + 1 ≤ 16385");
        if (!(s.min_resolution > 1.0) || !std::isfinite(s.min_resolution))
            throw fx::Error("terrain LOD: min_resolution (C) must be finite and greater than 1");
        if (s.morph_steps < 0 || s.morph_steps > 4096)
            throw fx::Error("terrain LOD: morph_steps must be 0 (continuous) to 4096, got " + std::to_string(s.morph_steps));
        for (std::size_t k = 0; k < g.heights.size(); ++k)
            if (!std::isfinite(g.heights[k]))
                throw fx::Error("terrain LOD: the height at sample (" + std::to_string(k % g.size) + ", " +
                                std::to_string(k / g.size) + ") is not finite");
        if (l) {
            require_same_grid(g, *l, "terrain LOD: the layer thickness map");
            for (std::size_t k = 0; k < l->heights.size(); ++k)
                if (!(l->heights[k] >= 0.0f) || !std::isfinite(l->heights[k]))
                    throw fx::Error("terrain LOD: the layer thickness at sample (" + std::to_string(k % g.size) + ", " +
                                    std::to_string(k / g.size) + ") is negative or not finite");
        }
        ground = std::move(g);
        layer = std::move(l);
        settings = s;
        n = ground.size;
        root_h = (n - 1) / 2;
        root = id(root_h, root_h);
        K = s.min_resolution / (2.0 * (s.min_resolution - 1.0));
        const std::size_t count = std::size_t(n) * std::size_t(n);
        nodes.assign(count, Node{});
        for (std::size_t k = 0; k < count; ++k) {
            nodes[k].i = std::uint16_t(k % std::size_t(n)), nodes[k].j = std::uint16_t(k / std::size_t(n));
            nodes[k].true_h = ground.heights[k];
        }
        verts.assign(count, Vertex{});
        for (std::size_t k = 0; k < count; ++k) {
            verts[k].true_h = verts[k].h = ground.heights[k];
            verts[k].true_t = verts[k].t = layer ? layer->heights[k] : 0.0f;
            verts[k].i = nodes[k].i, verts[k].j = nodes[k].j;
        }
        compute_roughness();
        if (layer) {
            const double across = 2.0 * root_h * ground.spacing * std::sqrt(2.0);
            const double rise = double(ground.max_height()) - ground.min_height() + layer->max_height();
            thin_layer = 1e-6 * std::sqrt(across * across + rise * rise);
        }
    }

    // d2 bottom-up (§3): the node's own error over its 3×3 samples, then at least K times that
    // of every finer node that needs it split (its children, and the nodes whose parent it neighbours).
    void compute_roughness() {
        const double spacing = ground.spacing;
        auto error_at = [&](const std::vector<float>& z, std::uint32_t v, std::uint32_t a, std::uint32_t b) {
            return std::abs(double(z[v]) - 0.5 * (double(z[a]) + double(z[b])));
        };
        std::vector<float> top;
        if (layer) {
            top.resize(ground.heights.size());
            for (std::size_t k = 0; k < top.size(); ++k) top[k] = ground.heights[k] + layer->heights[k];
        }
        for (int h = 1; h <= root_h; h *= 2) {
            for (int j = h; j < n - 1; j += 2 * h) {
                for (int i = h; i < n - 1; i += 2 * h) {
                    const std::uint32_t s = id(i, j);
                    const std::uint32_t sw = id(i - h, j - h), se = id(i + h, j - h), ne = id(i + h, j + h),
                                        nw = id(i - h, j + h);
                    const std::uint32_t ms = id(i, j - h), me = id(i + h, j), mn = id(i, j + h), mw = id(i - h, j);
                    double e = 0.0;
                    for (const std::vector<float>* z : {&ground.heights, layer ? &top : nullptr}) {
                        if (!z) continue;
                        e = std::max({e, error_at(*z, ms, sw, se), error_at(*z, me, se, ne), error_at(*z, mn, ne, nw),
                                      error_at(*z, mw, nw, sw), error_at(*z, s, sw, ne), error_at(*z, s, se, nw)});
                    }
                    double r = std::max(double(nodes[s].d2), e / (2.0 * h * spacing));
                    nodes[s].d2 = float(r);
                    if (h == root_h) continue;
                    std::uint32_t req[3];
                    const int k = required(i, j, h, req);
                    for (int q = 0; q < k; ++q) nodes[req[q]].d2 = std::max(nodes[req[q]].d2, float(K * r));
                }
            }
        }
    }
};

ContinuousLod::ContinuousLod(HeightField ground, const LodSettings& settings) : impl_(std::make_unique<Impl>()) {
    impl_->init(std::move(ground), std::nullopt, settings);
}

ContinuousLod::ContinuousLod(HeightField ground, HeightField layer_thickness, const LodSettings& settings)
    : impl_(std::make_unique<Impl>()) {
    impl_->init(std::move(ground), std::move(layer_thickness), settings);
}

ContinuousLod::~ContinuousLod() = default;
ContinuousLod::ContinuousLod(ContinuousLod&&) noexcept = default;
ContinuousLod& ContinuousLod::operator=(ContinuousLod&&) noexcept = default;

LodStats ContinuousLod::update(const LodView& view) {
    Impl& m = *impl_;
    if (!std::isfinite(view.eye.x) || !std::isfinite(view.eye.y) || !std::isfinite(view.eye.z))
        throw fx::Error("terrain LOD: the eye position is not finite");
    if (!(view.projection_scale > 0.0) || !std::isfinite(view.projection_scale))
        throw fx::Error("terrain LOD: projection scale must be finite and positive");
    if (!(view.pixel_error > 0.0) || !std::isfinite(view.pixel_error))
        throw fx::Error("terrain LOD: the pixel error bound must be finite and positive");
    const auto start = std::chrono::steady_clock::now();
    LodStats stats;
    m.stats = &stats;
    m.changes.full = false;
    m.changes.fans_before = m.fans.size();
    m.changes.fans.clear();
    m.changes.fan_nodes.clear();
    m.changes.vertices.clear();
    m.changes.vertex_heights.clear();
    m.changes.vertex_thicknesses.clear();
    m.reserve_for_tree();

    const bool same_view = m.have_state && view.projection_scale == m.last_view.projection_scale &&
                           view.pixel_error == m.last_view.pixel_error &&
                           view.triangle_budget == m.last_view.triangle_budget;
    if (!same_view) m.budget_scale = 1.0;
    m.c_user = view.projection_scale / (view.pixel_error * m.settings.min_resolution);
    m.c_eff = m.c_user * m.budget_scale;
    if (same_view) {
        m.advance(view.eye);
    } else {
        m.last_eye = view.eye;
        m.rebuild();
    }
    m.last_view = view;
    m.have_state = true;

    const std::size_t budget = view.triangle_budget;
    if (budget > 0) {
        while (m.triangles > budget && stats.budget_adjustments < 12 && m.budget_scale > 1e-9) {
            const double ratio = std::sqrt(double(budget) / double(m.triangles));
            m.budget_scale *= std::clamp(0.95 * ratio, 0.1, 0.95);
            m.c_eff = m.c_user * m.budget_scale;
            m.rebuild();
            ++stats.budget_adjustments;
        }
        if (m.triangles > budget) {
            stats.over_budget = true;
        } else if (m.triangles < budget / 2 && m.budget_scale < 1.0) {
            const double previous = m.budget_scale;
            m.budget_scale = std::min(1.0, m.budget_scale * 1.25);
            m.c_eff = m.c_user * m.budget_scale;
            m.rebuild();
            ++stats.budget_adjustments;
            if (m.triangles > budget) {
                m.budget_scale = previous;
                m.c_eff = m.c_user * m.budget_scale;
                m.rebuild();
                ++stats.budget_adjustments;
            }
        }
    }

    // The changed vertices' values, read while their records are still in the cache.
    for (std::uint32_t v : m.changes.vertices) {
        m.changes.vertex_heights.push_back(m.verts[v].h);
        m.changes.vertex_thicknesses.push_back(m.layer ? std::max(m.verts[v].t, 0.0f) : 0.0f);
    }
    stats.triangles = m.triangles;
    stats.live_nodes = m.live;
    stats.morphing_nodes = m.morphing_count;
    stats.error_scale = m.budget_scale;
    m.stats = nullptr;
    stats.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return stats;
}

void ContinuousLod::reset() {
    Impl& m = *impl_;
    LodStats scratch;
    m.stats = &scratch;
    m.remove(m.root, m.root_h);
    for (std::uint32_t s : m.fan_dirty) m.rebuild_fan(s);
    m.fan_dirty.clear();
    for (std::uint32_t s : m.touched) m.nodes[s].flags = 0;
    m.touched.clear();
    for (auto& v : m.vertex_dirty) v.clear();
    m.wakes.clear();
    m.morph_wakes.clear();
    m.morphing.clear();
    for (Impl::Vertex& v : m.verts) v.h = v.true_h, v.t = v.true_t;
    m.have_state = false;
    m.morphing_count = 0;
    m.changes.full = true;
    m.stats = nullptr;
}

void ContinuousLod::extract(LodMesh& out) const {
    const Impl& m = *impl_;
    out.clear();
    // Room to spare, so that a mesh growing by a few triangles from frame to frame does not
    // reallocate every time (a steady frame allocates nothing). A fan mesh has at most about
    // one vertex per two triangles, plus the border.
    const std::size_t vertices = m.triangles / 2 + 4 * std::size_t(m.n);
    if (out.triangles.capacity() < m.triangles) out.triangles.reserve(m.triangles + m.triangles / 4);
    if (out.positions.capacity() < vertices) {
        out.positions.reserve(vertices + vertices / 4);
        out.thickness.reserve(vertices + vertices / 4);
        out.grid_index.reserve(vertices + vertices / 4);
    }
    auto local = [&](std::uint32_t s) {
        Impl::Vertex& vertex = m.verts[s];
        if (vertex.local == std::numeric_limits<std::uint32_t>::max()) {
            vertex.local = std::uint32_t(out.grid_index.size());
            out.grid_index.push_back(s);
            out.positions.emplace_back(m.ground.x(vertex.i), m.ground.y(vertex.j), double(vertex.h));
            out.thickness.push_back(std::max(vertex.t, 0.0f));
        }
        return vertex.local;
    };
    for (const Fan& f : m.fans) {
        const std::uint32_t c = local(f.node);
        for (std::uint32_t k = 0; k < f.count; ++k)
            out.triangles.push_back({c, local(f.ring[k]), local(f.ring[(k + 1) % f.count])});
    }
    for (std::uint32_t s : out.grid_index) m.verts[s].local = std::numeric_limits<std::uint32_t>::max();
}

const LodChanges& ContinuousLod::changes() const { return impl_->changes; }
std::size_t ContinuousLod::fan_count() const { return impl_->fans.size(); }

bool ContinuousLod::fan_of(std::uint32_t node, LodFan& out) const {
    if (node >= impl_->nodes.size() || impl_->nodes[node].fan == kNoFan) return false;
    out = fan(std::size_t(impl_->nodes[node].fan));
    return true;
}

LodFan ContinuousLod::fan(std::size_t slot) const {
    const Fan& f = impl_->fans[slot];
    LodFan out;
    out.center = f.node;
    out.count = f.count;
    for (std::uint32_t k = 0; k < f.count; ++k) out.ring[k] = f.ring[k];
    return out;
}

glm::dvec3 ContinuousLod::vertex_position(std::uint32_t sample) const {
    const Impl& m = *impl_;
    const Impl::Vertex& v = m.verts[sample];
    return {m.ground.x(v.i), m.ground.y(v.j), double(v.h)};
}

float ContinuousLod::vertex_thickness(std::uint32_t sample) const {
    return impl_->layer ? std::max(impl_->verts[sample].t, 0.0f) : 0.0f;
}

LodMesh ContinuousLod::mesh() const {
    LodMesh mesh;
    extract(mesh);
    return mesh;
}

std::size_t ContinuousLod::triangle_count() const { return impl_->triangles; }
std::size_t ContinuousLod::full_resolution_triangles() const {
    const std::size_t cells = std::size_t(impl_->n - 1);
    return 2 * cells * cells;
}
const HeightField& ContinuousLod::ground() const { return impl_->ground; }
const HeightField* ContinuousLod::layer() const { return impl_->layer ? &*impl_->layer : nullptr; }
const LodSettings& ContinuousLod::settings() const { return impl_->settings; }

std::size_t ContinuousLod::memory_bytes() const {
    const Impl& m = *impl_;
    const std::size_t count = m.nodes.size();
    std::size_t bytes = count * (sizeof(Impl::Node) + sizeof(Impl::Vertex) + sizeof(float) /*ground copy*/);
    if (m.layer) bytes += count * sizeof(float);
    bytes += m.fans.capacity() * sizeof(Fan) + m.wakes.size() * sizeof(Wake);
    return bytes;
}

bool ContinuousLod::is_node_center(int i, int j) const { return impl_->center(i, j); }
bool ContinuousLod::is_split(int i, int j) const {
    return impl_->center(i, j) && (impl_->nodes[impl_->id(i, j)].state & kSplit);
}
double ContinuousLod::roughness(int i, int j) const { return impl_->center(i, j) ? impl_->nodes[impl_->id(i, j)].d2 : 0.0; }
float ContinuousLod::morphed_height(int i, int j) const { return impl_->verts[impl_->id(i, j)].h; }
float ContinuousLod::morphed_thickness(int i, int j) const {
    return impl_->layer ? impl_->verts[impl_->id(i, j)].t : 0.0f;
}

} // namespace cellfx::terrain
