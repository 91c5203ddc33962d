// Based on: Max, Williams & Silva 2000, §III (MPVO, after Williams 1992).
//
// Per view, the plane of every shared face is evaluated once at the eye (for an orthographic
// camera: against the view direction). The eye on the outer side of cell c's face means the
// neighbour lies between the eye and c, so c is drawn first: edge c → neighbour. The counts
// of incoming edges go into one 16-bit word per cell together with the outgoing edges (one
// bit per face slot) and a few flags; the output array doubles as the FIFO queue of Kahn's
// algorithm. A face whose plane passes exactly through the eye gets no edge: its two cells
// do not overlap on screen.
//
// Cycles: when the queue runs dry with cells left, every remaining cell still waits for a
// remaining predecessor, so walking predecessors from any of them must revisit a cell; that
// cell lies on a cycle and is emitted early (counted in SortStats::cycles). Its remaining
// predecessors later skip it. Each walk is bounded by the cells left, and the scan for a
// starting cell only moves forward, so the sort always ends with every cell exactly once.
#include "face_graph.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include <glm/geometric.hpp>

#include "fx/error.hpp"
#include "frame_storage.hpp"

namespace cellfx::fx::sort_detail {
namespace {

using clock_type = std::chrono::steady_clock;

double seconds_since(clock_type::time_point t0) {
    return std::chrono::duration<double>(clock_type::now() - t0).count();
}

// Per-cell word during a sort.
constexpr std::uint16_t kCountMask = 0x000F; // incoming edges not yet released (+1 for exterior ones)
constexpr std::uint16_t kExteriorIn = 0x0010;
constexpr std::uint16_t kExteriorOut = 0x0020;
constexpr std::uint16_t kOnPath = 0x0040; // on the current predecessor walk
constexpr std::uint16_t kEmitted = 0x0080; // in the output (queued or done)
constexpr int kOutShift = 8;               // bits 8..13: outgoing edge per face slot

constexpr std::uint32_t kNone = 0xFFFFFFFFu;

// The plane of face f of cell c, outward from c (oriented by the cell's vertex centroid, so
// either winding works), relative to origin. Triangles: through their vertices. Quads: the
// Newell normal through the vertex average (exact for planar quads; a fixed compromise for
// non-planar ones, the same for both cells since it is stored once).
glm::vec4 face_plane(const CellMesh& mesh, std::uint32_t c, const CellFace& face, const glm::dvec3& cell_centroid,
                     const glm::dvec3& origin) {
    const std::uint32_t* cv = mesh.cell_vertices(c);
    glm::dvec3 p[4];
    glm::dvec3 centre(0.0);
    for (int i = 0; i < face.count; ++i) {
        p[i] = mesh.points[cv[face.v[i]]];
        centre += p[i];
    }
    centre /= double(face.count);
    glm::dvec3 n(0.0);
    if (face.count == 3) {
        n = glm::cross(p[1] - p[0], p[2] - p[0]);
    } else {
        for (int i = 0; i < 4; ++i) n += glm::cross(p[i] - centre, p[(i + 1) % 4] - centre);
    }
    if (glm::dot(n, cell_centroid - centre) > 0.0) n = -n;
    const double len = glm::length(n);
    if (!(len > 0.0) || !std::isfinite(len)) return glm::vec4(0.0f); // never gives an edge
    n /= len;
    return glm::vec4(glm::vec3(n), static_cast<float>(-glm::dot(n, centre - origin)));
}

} // namespace

void ExteriorEdges::build(std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs) {
    std::sort(pairs.begin(), pairs.end());
    pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
    assign_range_kept(by_source, pairs.begin(), pairs.end());
    resize_kept(by_target, by_source.size());
    for (std::size_t i = 0; i < by_source.size(); ++i) by_target[i] = {by_source[i].second, by_source[i].first};
    std::sort(by_target.begin(), by_target.end());
    targets.clear();
    target_first.clear();
    for (std::size_t i = 0; i < by_target.size(); ++i) {
        if (i == 0 || by_target[i].first != by_target[i - 1].first) {
            targets.push_back(by_target[i].first);
            target_first.push_back(static_cast<std::uint32_t>(i));
        }
    }
    target_first.push_back(static_cast<std::uint32_t>(by_target.size()));
}

std::size_t ExteriorEdges::memory_bytes() const {
    return (by_source.capacity() + by_target.capacity()) * sizeof(by_source[0]) +
           (targets.capacity() + target_first.capacity()) * sizeof(std::uint32_t);
}

FaceGraph::FaceGraph(const CellMesh& mesh, const FaceTopology& topology) { build(mesh, topology); }

void FaceGraph::build(const CellMesh& mesh, const FaceTopology& topology) {
    cells_ = 0;
    stride_ = 0;
    first_slot_.clear();
    neighbour_.clear();
    planes_.clear();
    if (mesh.cell_count() >= kMaxCells) {
        throw Error("visibility sort: " + std::to_string(mesh.cell_count()) + " cells; mpvo and xmpvo take at most " +
                    std::to_string(kMaxCells - 1));
    }
    cells_ = static_cast<std::uint32_t>(mesh.cell_count());
    bool uniform = cells_ > 0;
    for (std::uint32_t c = 1; c < cells_ && uniform; ++c) uniform = mesh.cell_types[c] == mesh.cell_types[0];
    if (uniform) {
        stride_ = static_cast<std::uint32_t>(cell_face_count(mesh.cell_types[0]));
    } else {
        assign_range_kept(first_slot_, topology.first_face.begin(), topology.first_face.end());
    }

    const std::size_t slots = topology.face_slot_count();
    assign_kept(neighbour_, slots, kBoundary);
    std::size_t owned = 0;
    for (std::uint32_t c = 0; c < cells_; ++c) {
        for (std::uint32_t s = topology.first_face[c]; s < topology.first_face[c + 1]; ++s) {
            const std::uint32_t ns = topology.neighbour[s];
            if (ns == FaceTopology::kBoundary) continue;
            const std::uint32_t nc = topology.slot_cell[ns];
            if (nc == c) continue; // a cell glued to itself: no edge
            neighbour_[s] = (nc << 3) | (ns - topology.first_face[nc]);
            if (nc > c) ++owned;
        }
    }

    const Bounds bounds = mesh_bounds(mesh);
    origin_ = bounds.empty() ? glm::dvec3(0.0) : bounds.center();
    reserve_kept(planes_, owned);
    for (std::uint32_t c = 0; c < cells_; ++c) {
        const CellType type = mesh.cell_types[c];
        const CellFace* faces = cell_faces(type);
        const std::uint32_t* cv = mesh.cell_vertices(c);
        glm::dvec3 centroid(0.0);
        for (int i = 0; i < cell_vertex_count(type); ++i) centroid += mesh.points[cv[i]];
        centroid /= double(cell_vertex_count(type));
        const std::uint32_t s0 = topology.first_face[c];
        for (int f = 0; f < cell_face_count(type); ++f) {
            const std::uint32_t v = neighbour_[s0 + f];
            if (v != kBoundary && (v >> 3) > c) planes_.push_back(face_plane(mesh, c, faces[f], centroid, origin_));
        }
    }
}

std::size_t FaceGraph::memory_bytes() const {
    return (first_slot_.capacity() + neighbour_.capacity()) * sizeof(std::uint32_t) +
           planes_.capacity() * sizeof(glm::vec4);
}

void FaceGraph::sort(const Camera& camera, const ExteriorEdges* exterior, std::vector<std::uint32_t>& back_to_front,
                     SortStats& stats) const {
    auto t0 = clock_type::now();
    const std::uint32_t n = cells_;
    std::vector<std::uint16_t>& state = state_;
    assign_kept(state, n, std::uint16_t(0));

    // Directions of the face edges.
    const bool ortho = camera.orthographic();
    const glm::dvec3 e = camera.eye - origin_;
    const glm::dvec3 f = camera.forward();
    std::size_t p = 0, edges = 0;
    for (std::uint32_t c = 0; c < n; ++c) {
        const std::uint32_t s0 = first_slot(c), s1 = first_slot(c + 1);
        for (std::uint32_t s = s0; s < s1; ++s) {
            const std::uint32_t v = neighbour_[s];
            if (v == kBoundary) continue;
            const std::uint32_t nc = v >> 3;
            if (nc < c) continue; // evaluated by nc
            const glm::vec4& pl = planes_[p++];
            const double side = ortho ? -(double(pl.x) * f.x + double(pl.y) * f.y + double(pl.z) * f.z)
                                      : double(pl.x) * e.x + double(pl.y) * e.y + double(pl.z) * e.z + double(pl.w);
            if (side > 0.0) { // eye outside c: the neighbour is in front, c goes first
                state[c] |= std::uint16_t(1u << (kOutShift + (s - s0)));
                ++state[nc];
                ++edges;
            } else if (side < 0.0) {
                state[nc] |= std::uint16_t(1u << (kOutShift + (v & 7u)));
                ++state[c];
                ++edges;
            }
        }
    }
    // Exterior edges: each target waits for one token, released when its last source is out.
    std::vector<std::uint32_t>& remaining = remaining_;
    if (exterior) {
        resize_kept(remaining, exterior->targets.size());
        for (std::size_t t = 0; t < exterior->targets.size(); ++t) {
            remaining[t] = exterior->target_first[t + 1] - exterior->target_first[t];
            state[exterior->targets[t]] = std::uint16_t((state[exterior->targets[t]] + 1) | kExteriorIn);
        }
        for (const auto& edge : exterior->by_source) state[edge.first] |= kExteriorOut;
    }
    stats.seconds_keys += seconds_since(t0);
    t0 = clock_type::now();

    resize_kept(back_to_front, n);
    std::uint32_t* out = back_to_front.data();
    std::uint32_t head = 0, tail = 0;
    auto release = [&](std::uint32_t c) {
        std::uint16_t& s = state[c];
        if (s & kEmitted) return; // emitted early to break a cycle
        --s;
        if ((s & kCountMask) == 0) {
            s |= kEmitted;
            out[tail++] = c;
        }
    };
    auto target_index = [&](std::uint32_t c) {
        const auto it = std::lower_bound(exterior->targets.begin(), exterior->targets.end(), c);
        return static_cast<std::size_t>(it - exterior->targets.begin());
    };
    // A remaining cell with an edge into c (kNone if there is none, which the counts rule out).
    auto predecessor = [&](std::uint32_t c) {
        for (std::uint32_t s = first_slot(c), s1 = first_slot(c + 1); s < s1; ++s) {
            const std::uint32_t v = neighbour_[s];
            if (v == kBoundary) continue;
            const std::uint16_t ns = state[v >> 3];
            if (!(ns & kEmitted) && (ns >> kOutShift) & (1u << (v & 7u))) return v >> 3;
        }
        if (state[c] & kExteriorIn) {
            const std::size_t t = target_index(c);
            for (std::uint32_t i = exterior->target_first[t]; i < exterior->target_first[t + 1]; ++i) {
                if (!(state[exterior->by_target[i].second] & kEmitted)) return exterior->by_target[i].second;
            }
        }
        return kNone;
    };

    for (std::uint32_t c = 0; c < n; ++c) {
        if ((state[c] & (kCountMask | kEmitted)) == 0) {
            state[c] |= kEmitted;
            out[tail++] = c;
        }
    }
    std::size_t cycles = 0;
    std::uint32_t scan = 0;
    std::vector<std::uint32_t>& path = path_; // kept: cycles may come back every frame
    for (;;) {
        while (head < tail) {
            const std::uint32_t c = out[head++];
            std::uint32_t bits = state[c] >> kOutShift;
            const std::uint32_t s0 = first_slot(c);
            while (bits) {
                const int i = __builtin_ctz(bits);
                bits &= bits - 1;
                release(neighbour_[s0 + i] >> 3);
            }
            if (state[c] & kExteriorOut) {
                auto it = std::lower_bound(exterior->by_source.begin(), exterior->by_source.end(),
                                           std::make_pair(c, std::uint32_t(0)));
                for (; it != exterior->by_source.end() && it->first == c; ++it) {
                    const std::size_t t = target_index(it->second);
                    if (--remaining[t] == 0) release(it->second);
                }
            }
        }
        if (tail == n) break;
        // Stuck: every remaining cell waits on a remaining one. Walk back to a cycle.
        while (state[scan] & kEmitted) ++scan;
        std::uint32_t victim = scan;
        path.clear();
        for (std::uint32_t cur = scan;;) {
            state[cur] |= kOnPath;
            path.push_back(cur);
            const std::uint32_t pred = predecessor(cur);
            if (pred == kNone) {
                victim = cur;
                break;
            }
            if (state[pred] & kOnPath) {
                victim = pred;
                break;
            }
            cur = pred;
        }
        for (std::uint32_t c : path) state[c] &= std::uint16_t(~kOnPath);
        ++cycles;
        state[victim] |= kEmitted;
        out[tail++] = victim;
    }
    stats.seconds_order += seconds_since(t0);
    stats.face_edges += edges;
    stats.cycles += cycles;
    stats.working_bytes += state.capacity() * sizeof(std::uint16_t) + remaining.capacity() * sizeof(std::uint32_t) +
                           path.capacity() * sizeof(std::uint32_t);
}

} // namespace cellfx::fx::sort_detail
