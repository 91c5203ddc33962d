#version 450 core
// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2.4 (integrate between consecutive
// crossings, front to back) — the medium compositor's resolve (fx/internal/medium/medium_compositor.hpp): per
// pixel of the mask, the segments of every volume swept in depth order; each span between
// consecutive boundaries is integrated through the media inside it with fx/medium.hpp's model
// (emission tables per volume, mixing, pieces of bounded optical depth, single scattering of
// beams and point lights), then composited over the `behind` image.
//
// The bulk volume (the ground fog: one colour, many segments per pixel) is not sorted: its
// segments are integrated into the bins between the other volumes' boundaries, the chords of
// the point lights and, between the first and last of those, its own segments' ends; inside a
// bin it is a uniform medium of the bin's optical depth and emission. Exact where it is alone
// (one colour); elsewhere its density is taken as even over each bin, which the bins keep short.
//
// Drawn as one full-screen triangle (fullscreen.vert) with the scissor on the region, blending
// off: it replaces what the ordinary paths drew where the mask is set, and leaves the rest.
#include "medium_lists.glsl"
#include "medium_lights.glsl"

const int kSorted = 96;  // MediumCompositor::kSortedSegments
const int kActive = 16;  // MediumCompositor::kActiveSegments
const int kMaxVolumes = MEDIUM_VOLUMES;
const int kBulkBounds = 64; // the bulk's own segment ends among the other volumes and chords
const int kBounds = 2 * kSorted + 3 * kMaxPointLights + kBulkBounds; // bin boundaries
const int kTableSize = 4096;
const float kMaxPieceDepth = 0.25; // fx::kMaxPieceDepth
const float kInfinity = 3.4e38;

// Texture unit 0: every volume's emission tables, rows 2v (cumulative E rgb, T = ∫σ a) and
// 2v + 1 (c·σ rgb, σ a), 4096 samples each (fx::build_emission_table, as project.glsl's).
layout(binding = 0) uniform sampler2D u_tables;
layout(binding = 1) uniform sampler2D u_mask;   // 1 where the medium is resolved (viewport texels)
layout(binding = 2) uniform sampler2D u_behind; // premultiplied, texel = gl_FragCoord

layout(location = UNIFORM_MEDIUM_BULK) uniform int u_bulk; // the bulk volume, −1: none
// The pixel's ray in the eye-relative world frame (the eye at the origin).
// Perspective: the ray of ndc (x, y) runs along u_forward + x·u_right + y·u_up (the near
// plane's points: an explicit, off-axis projection too); orthographic: from x·u_right + y·u_up
// along u_forward (unit).
layout(location = UNIFORM_MEDIUM_FORWARD) uniform vec3 u_forward;
layout(location = UNIFORM_MEDIUM_RIGHT) uniform vec3 u_right;
layout(location = UNIFORM_MEDIUM_UP) uniform vec3 u_up;
layout(location = UNIFORM_MEDIUM_ORTHO) uniform int u_ortho;
layout(location = UNIFORM_MEDIUM_VIEWPORT) uniform vec4 u_viewport; // x, y, width, height in the framebuffer

layout(location = UNIFORM_MEDIUM_TABLE) uniform vec4 u_table[kMaxVolumes];             // s_lo, s_hi, samples per unit s, colour varies (0/1)
layout(location = UNIFORM_MEDIUM_MEDIUM) uniform vec4 u_medium[kMaxVolumes];           // absorbs, albedo, beam (0/1), beam g
layout(location = UNIFORM_MEDIUM_BEAM_ORIGIN) uniform vec4 u_beam_origin[kMaxVolumes]; // lens (eye-relative), apex distance (0: parallel)
layout(location = UNIFORM_MEDIUM_BEAM_AXIS) uniform vec4 u_beam_axis[kMaxVolumes];     // unit axis, strength per scalar
layout(location = UNIFORM_MEDIUM_BEAM_COLOR) uniform vec4 u_beam_color[kMaxVolumes];   // rgb

layout(location = 0) in vec2 v_uv;
layout(location = 0) out vec4 o_color;

// ---- one volume's tables (project.glsl's functions, per volume) ------------------------------
float table_x(int v, float s) { return (s - u_table[v].x) * u_table[v].z; }
vec4 row_texel(int v, int row, int i) { return texelFetch(u_tables, ivec2(i, 2 * v + row), 0); }

vec4 emission_at(int v, float s) {
    int n = kTableSize;
    float x = clamp(table_x(v, s), 0.0, float(n - 1));
    int i = min(int(x), n - 2);
    return mix(row_texel(v, 1, i), row_texel(v, 1, i + 1), x - float(i));
}
vec4 cumulative_at(int v, float s) {
    int n = kTableSize;
    float x = table_x(v, s);
    if (x <= 0.0) return row_texel(v, 0, 0) + row_texel(v, 1, 0) * (s - u_table[v].x);
    if (x >= float(n - 1)) return row_texel(v, 0, n - 1) + row_texel(v, 1, n - 1) * (s - u_table[v].y);
    int i = int(x);
    return mix(row_texel(v, 0, i), row_texel(v, 0, i + 1), x - float(i));
}
int table_cell(int v, float s) {
    float x = table_x(v, s);
    int n = kTableSize;
    return x < 0.0 ? -1 : (x >= float(n - 1) ? n - 1 : int(x));
}
vec4 cell_slope(int v, int i) {
    int n = kTableSize;
    if (i < 0) return row_texel(v, 1, 0);
    if (i >= n - 1) return row_texel(v, 1, n - 1);
    return (row_texel(v, 0, i + 1) - row_texel(v, 0, i)) * u_table[v].z;
}
// Emission (rgb) and optical depth (a) of length l with the scalar linear from s_f to s_b
// (project.glsl's segment_integral: no subtraction of nearly equal values).
vec4 segment_integral(int v, float s_f, float s_b, float l) {
    int cf = table_cell(v, s_f), cb = table_cell(v, s_b);
    if (cf == cb) return cell_slope(v, cf) * l;
    if (abs(cf - cb) == 1) {
        int lower = min(cf, cb);
        float x_lo = table_x(v, min(s_f, s_b)), x_hi = table_x(v, max(s_f, s_b));
        float w = clamp((float(lower + 1) - x_lo) / max(x_hi - x_lo, 1e-30), 0.0, 1.0);
        return (cell_slope(v, lower) * w + cell_slope(v, lower + 1) * (1.0 - w)) * l;
    }
    // Beyond the table its end values hold. Each part is weighted by its share of l before the
    // sum, so that an end far beyond the table (a held value times a huge run of s) cannot
    // overflow it while the segment's integral is finite.
    float lo = min(s_f, s_b), hi = max(s_f, s_b), per_s = l / (hi - lo);
    float a = clamp(lo, u_table[v].x, u_table[v].y), b = clamp(hi, u_table[v].x, u_table[v].y);
    return row_texel(v, 1, 0) * ((a - lo) * per_s) + (cumulative_at(v, b) - cumulative_at(v, a)) * per_s +
           row_texel(v, 1, kTableSize - 1) * ((hi - b) * per_s);
}

// ---- segments ---------------------------------------------------------------------------------
float seg_t_in(uint i) { return uintBitsToFloat(medium_data[segment_base(i)]); }
float seg_t_out(uint i) { return uintBitsToFloat(medium_data[segment_base(i) + 1u]); }
uint seg_next(uint i) { return medium_data[segment_base(i) + 4u] >> kVolumeBits; } // index + 1, 0 = end
int seg_volume(uint i) { return int(medium_data[segment_base(i) + 4u] & ((1u << kVolumeBits) - 1u)); }
// The scalar of segment i at ray parameter t (linear along the segment).
float seg_scalar(uint i, float t) {
    uint b = segment_base(i);
    float t0 = uintBitsToFloat(medium_data[b]), t1 = uintBitsToFloat(medium_data[b + 1u]);
    float s0 = uintBitsToFloat(medium_data[b + 2u]), s1 = uintBitsToFloat(medium_data[b + 3u]);
    float f = t1 > t0 ? clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 0.0;
    return mix(s0, s1, f);
}

// ---- lights --------------------------------------------------------------------------------

vec3 g_origin, g_dir; // this pixel's ray

// The direction a beam's light travels at x.
vec3 beam_direction(int v, vec3 x) {
    vec4 o = u_beam_origin[v];
    vec3 axis = u_beam_axis[v].xyz;
    return o.w > 0.0 ? normalize(x - (o.xyz - axis * o.w)) : axis;
}

// A scattering medium over the current span: an active segment, or the bulk (kBulk) with the
// bin's even extinction.
const uint kBulk = 0xFFFFFFFFu;
float bulk_sigma = 0.0;
float medium_sigma(uint m, int vm, float t) { return m == kBulk ? bulk_sigma : emission_at(vm, seg_scalar(m, t)).a; }

// ∫ over [a, b] of σ_m · (beam k's strength) · 4π·p, dimmed by the span's own optical depth `tau`
// from a to t (spread evenly): σ and the strength linear in t across the span, the phase and the
// dimming slowly varying: Simpson's rule (exact for the linear product).
float beam_scatter(int vk, uint k, int vm, uint m, float a, float b, float tau) {
    float strength = u_beam_axis[vk].w;
    float g = u_medium[vk].w;
    float sum = 0.0;
    for (int j = 0; j < 3; ++j) {
        float f = 0.5 * float(j);
        float t = mix(a, b, f);
        vec3 x = g_origin + g_dir * t;
        float light = max(seg_scalar(k, t), 0.0) * strength;
        float p = relative_phase(g, dot(beam_direction(vk, x), -g_dir));
        sum += (j == 1 ? 4.0 : 1.0) * medium_sigma(m, vm, t) * light * p * exp(-tau * f);
    }
    return sum * (b - a) / 6.0;
}

// The medium point_light_scatter (medium_lights.glsl) weighs by: set before each call.
uint scatter_m = kBulk;
int scatter_vm = 0;
float scatter_sigma(float t) { return medium_sigma(scatter_m, scatter_vm, t); }

// ---- the sweep -------------------------------------------------------------------------------
uint active_segment[kActive];
float active_out[kActive];
int active_count = 0;
vec3 light_sum = vec3(0.0);
float transmittance = 1.0;
bool colour_varies = false; // some medium of the last span_media() changes colour with its scalar

// Emission (rgb) and absorbing optical depth (a) over [a, b] of the active media and of the
// bulk's share (bulk: its emission and optical depth there, spread evenly); in `light` the light
// the absorbing ones scatter towards the eye from the beams among them and every point light,
// already dimmed by the span's own depth from a to where it is scattered.
vec4 span_media(float a, float b, vec4 bulk, out vec3 light) {
    float l = b - a;
    vec3 e = bulk.rgb;
    bool with_bulk = u_bulk >= 0 && bulk.a > 0.0;
    float tau = with_bulk && u_medium[u_bulk].x > 0.5 ? bulk.a : 0.0;
    colour_varies = with_bulk && u_table[u_bulk].w > 0.5;
    for (int i = 0; i < active_count; ++i) {
        uint k = active_segment[i];
        int v = seg_volume(k);
        vec4 m = segment_integral(v, seg_scalar(k, a), seg_scalar(k, b), l);
        e += m.rgb;
        if (u_medium[v].x > 0.5) tau += m.a;
        colour_varies = colour_varies || u_table[v].w > 0.5;
    }
    light = vec3(0.0);
    bulk_sigma = with_bulk ? bulk.a / l : 0.0;
    // Scatterers: the active segments, then (i = active_count) the bulk.
    for (int i = 0; i <= active_count; ++i) {
        uint m = i < active_count ? active_segment[i] : kBulk;
        int vm = i < active_count ? seg_volume(m) : u_bulk;
        if (m == kBulk && !with_bulk) continue;
        float albedo = u_medium[vm].y;
        if (!(u_medium[vm].x > 0.5 && albedo > 0.0)) continue;
        for (int j = 0; j < active_count; ++j) {
            uint k = active_segment[j];
            int vk = seg_volume(k);
            if (j == i || u_medium[vk].z < 0.5) continue;
            light += albedo * u_beam_color[vk].rgb * beam_scatter(vk, k, vm, m, a, b, tau);
        }
        scatter_m = m, scatter_vm = vm;
        for (int p = 0; p < u_point_count; ++p)
            light += albedo * point_light_scatter(p, g_origin, g_dir, a, b, tau) * u_point_color[p].rgb;
    }
    return vec4(e, tau);
}

// Front to back: the span's emission spread evenly through its absorption, its scattered light
// (already dimmed inside it), then its transmittance.
void composite(vec4 m, vec3 light) {
    float tau = m.a;
    // (1 − e^−τ)/τ without cancellation for small τ.
    float g = tau < 1e-3 ? 1.0 - tau * (0.5 - tau / 6.0) : (1.0 - exp(-tau)) / tau;
    light_sum += transmittance * (m.rgb * g + light);
    transmittance *= exp(-tau);
}

// [a, b] with the active media and the bulk's share `bulk` (emission rgb, optical depth a).
void integrate(float a, float b, vec4 bulk) {
    if (!(b > a)) return;
    vec3 light;
    vec4 m = span_media(a, b, bulk, light);
    // One medium of one colour, or thin: E·(1 − e^−τ)/τ is exact, or nearly.
    int media = active_count + (bulk.a > 0.0 ? 1 : 0);
    if (m.a <= kMaxPieceDepth || (!colour_varies && media == 1)) {
        composite(m, light);
        return;
    }
    // Optically thick and more than one colour: pieces of depth ≤ kMaxPieceDepth.
    int pieces = min(int(ceil(m.a / kMaxPieceDepth)), 64);
    for (int p = 0; p < pieces; ++p) {
        m = span_media(mix(a, b, float(p) / float(pieces)), mix(a, b, float(p + 1) / float(pieces)), bulk / float(pieces), light);
        composite(m, light);
    }
}

// The non-bulk segments in order of entry: a sorted local array, or (more than kSorted of them)
// repeated selection of the next (t_in, index) over the whole list, the bulk's segments then
// swept like the others.
float sorted_t[kSorted];
uint sorted_index[kSorted];
int sorted_count = 0, cursor = 0;
bool selecting = false;
uint head = 0u;
float last_t = -kInfinity;
uint last_index = 0u;

bool next_segment(out uint index, out float t_in) {
    if (!selecting) {
        if (cursor >= sorted_count) return false;
        index = sorted_index[cursor], t_in = sorted_t[cursor];
        ++cursor;
        return true;
    }
    bool found = false;
    for (uint it = head; it != 0u; it = seg_next(it - 1u)) {
        uint i = it - 1u;
        float t = seg_t_in(i);
        bool after = t > last_t || (t == last_t && i > last_index);
        if (after && (!found || t < t_in || (t == t_in && i < index))) index = i, t_in = t, found = true;
    }
    if (found) last_t = t_in, last_index = index;
    return found;
}

// Sweeps the segments in order, integrating between consecutive boundaries (no bulk bins).
void sweep() {
    uint pending;
    float pending_t;
    bool has_pending = next_segment(pending, pending_t);
    float t = has_pending ? pending_t : 0.0;
    while (transmittance > 1e-7) {
        while (has_pending && pending_t <= t) { // segments starting here join the active set
            if (seg_t_out(pending) > t && active_count < kActive) {
                active_segment[active_count] = pending;
                active_out[active_count] = seg_t_out(pending);
                ++active_count;
            }
            has_pending = next_segment(pending, pending_t);
        }
        if (active_count == 0) {
            if (!has_pending) break;
            t = pending_t;
            continue;
        }
        float t_next = has_pending ? pending_t : kInfinity;
        for (int i = 0; i < active_count; ++i) t_next = min(t_next, active_out[i]);
        integrate(t, t_next, vec4(0.0));
        t = t_next;
        for (int i = active_count - 1; i >= 0; --i) {
            if (active_out[i] <= t) {
                --active_count;
                active_segment[i] = active_segment[active_count];
                active_out[i] = active_out[active_count];
            }
        }
    }
}

// Bins between the boundaries of the non-bulk segments and the point lights' chords: bin j is
// [bounds[j − 1], bounds[j]) (bin 0 from −∞, bin bound_count to +∞), with the bulk's emission
// and optical depth inside it.
float bounds[kBounds];
int bound_count = 0;
vec4 bins[kBounds + 1];

void add_bound(float t) {
    if (bound_count == kBounds) return;
    int j = bound_count++;
    for (; j > 0 && bounds[j - 1] > t; --j) bounds[j] = bounds[j - 1];
    bounds[j] = t;
}
// Index of the bin holding t: the number of boundaries ≤ t.
int bin_of(float t) {
    int lo = 0, hi = bound_count;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (bounds[mid] <= t) lo = mid + 1;
        else hi = mid;
    }
    return lo;
}
void bin_bulk_segment(uint i) {
    uint b = segment_base(i);
    float t0 = uintBitsToFloat(medium_data[b]), t1 = uintBitsToFloat(medium_data[b + 1u]);
    float s0 = uintBitsToFloat(medium_data[b + 2u]), s1 = uintBitsToFloat(medium_data[b + 3u]);
    if (!(t1 > t0)) return;
    for (int j = bin_of(t0); j <= bound_count; ++j) {
        float lo = j == 0 ? t0 : max(t0, bounds[j - 1]);
        float hi = j == bound_count ? t1 : min(t1, bounds[j]);
        if (lo >= t1) break;
        if (hi > lo) bins[j] += segment_integral(u_bulk, mix(s0, s1, (lo - t0) / (t1 - t0)), mix(s0, s1, (hi - t0) / (t1 - t0)), hi - lo);
    }
}
// The bins front to back, each with the non-bulk segments active in it.
void sweep_bins() {
    uint pending;
    float pending_t;
    bool has_pending = next_segment(pending, pending_t);
    for (int j = 0; j <= bound_count && transmittance > 1e-7; ++j) {
        float lo = j == 0 ? -kInfinity : bounds[j - 1], hi = j == bound_count ? kInfinity : bounds[j];
        for (int i = active_count - 1; i >= 0; --i) { // segments that ended
            if (active_out[i] <= lo) {
                --active_count;
                active_segment[i] = active_segment[active_count];
                active_out[i] = active_out[active_count];
            }
        }
        while (has_pending && pending_t <= lo) { // segments that start here
            if (seg_t_out(pending) > lo && active_count < kActive) {
                active_segment[active_count] = pending;
                active_out[active_count] = seg_t_out(pending);
                ++active_count;
            }
            has_pending = next_segment(pending, pending_t);
        }
        if (j == 0 || j == bound_count) {
            composite(bins[j], vec3(0.0)); // the bulk alone, outside every boundary and chord
        } else {
            integrate(lo, hi, bins[j]);
        }
    }
}

void main() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    if (texelFetch(u_mask, p - ivec2(u_viewport.xy), 0).r < 0.5) discard; // the ordinary paths' pixel
    head = medium_data[region_pixel(p - ivec2(u_viewport.xy))];
    vec4 behind = texelFetch(u_behind, p, 0);
    if (head == 0u) {
        o_color = behind;
        return;
    }
    // The pixel's ray, as pixel_ray() in project.glsl: from the eye (perspective) or the eye plane.
    vec2 ndc = (gl_FragCoord.xy - u_viewport.xy) / u_viewport.zw * 2.0 - 1.0;
    if (u_ortho != 0) {
        g_origin = ndc.x * u_right + ndc.y * u_up;
        g_dir = u_forward;
    } else {
        g_origin = vec3(0.0);
        g_dir = normalize(u_forward + ndc.x * u_right + ndc.y * u_up);
    }

    // The non-bulk segments sorted by entry (insertion); the bulk's counted.
    int bulk_count = 0;
    for (uint it = head; it != 0u; it = seg_next(it - 1u)) {
        uint i = it - 1u;
        if (seg_volume(i) == u_bulk) {
            ++bulk_count;
            continue;
        }
        if (sorted_count == kSorted) {
            selecting = true;
            break;
        }
        float t = seg_t_in(i);
        int j = sorted_count++;
        for (; j > 0 && (sorted_t[j - 1] > t || (sorted_t[j - 1] == t && sorted_index[j - 1] > i)); --j) {
            sorted_t[j] = sorted_t[j - 1];
            sorted_index[j] = sorted_index[j - 1];
        }
        sorted_t[j] = t;
        sorted_index[j] = i;
    }

    if (selecting || bulk_count == 0) {
        sweep(); // every segment in order (selection walks the bulk's too)
    } else {
        for (int i = 0; i < sorted_count; ++i) {
            add_bound(sorted_t[i]);
            add_bound(seg_t_out(sorted_index[i]));
        }
        for (int l = 0; l < u_point_count; ++l) { // the chord of each point light's reach, and its middle
            vec3 c = u_point_position[l].xyz;
            float R = u_point_color[l].w, tc = dot(c - g_origin, g_dir);
            vec3 closest = g_origin + g_dir * tc - c;
            float h2 = dot(closest, closest);
            if (h2 >= R * R) continue;
            float w = sqrt(R * R - h2);
            add_bound(tc - w), add_bound(tc), add_bound(tc + w);
        }
        // Where the others or a light are, the bulk's own segment ends bound bins too (up to
        // kBulkBounds of them), so it is placed exactly there: inside [first, last] of the
        // boundaries so far.
        float first = bound_count > 0 ? bounds[0] : kInfinity, last = bound_count > 0 ? bounds[bound_count - 1] : -kInfinity;
        int extra = 0;
        for (uint it = head; it != 0u && extra < kBulkBounds; it = seg_next(it - 1u)) {
            if (seg_volume(it - 1u) != u_bulk) continue;
            float t0 = seg_t_in(it - 1u), t1 = seg_t_out(it - 1u);
            if (t0 > first && t0 < last) add_bound(t0), ++extra;
            if (t1 > first && t1 < last && extra < kBulkBounds) add_bound(t1), ++extra;
        }
        for (int j = 0; j <= bound_count; ++j) bins[j] = vec4(0.0);
        for (uint it = head; it != 0u; it = seg_next(it - 1u))
            if (seg_volume(it - 1u) == u_bulk) bin_bulk_segment(it - 1u);
        sweep_bins();
    }
    // The volumes (premultiplied: light_sum, 1 − transmittance) over what lies behind them.
    o_color = vec4(light_sum + transmittance * behind.rgb, 1.0 - transmittance + transmittance * behind.a);
}
