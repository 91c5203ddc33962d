// Based on: Wilhelms, Tarantino & Van Gelder 1995, §2.2 (X-buckets in depth order)
//
// Private to the scan-line renderer: a crossing of a triangle with a pixel ray, and the
// per-pixel sort that puts a pixel's crossings in depth order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cellfx::fx::scanline {

// One crossing of a triangle with a pixel ray: Table 2's depth and data value (q, the scalar
// times w), with what the pixel walk needs to know about the triangle (its code breaks
// depth ties; grid, whether it toggles inside/outside, and whether the ray enters the cell
// there, which the walk uses to see overlapping cells).
struct Fragment {
    double z, q;
    std::uint32_t id;
    std::uint32_t grid : 30;
    std::uint32_t toggles : 1;
    std::uint32_t enters : 1;
};

// Depth order with ties broken by triangle code: the same order whichever thread or chunk
// produced the fragments.
inline bool depth_order(const Fragment& a, const Fragment& b) { return a.z < b.z || (a.z == b.z && a.id < b.id); }

// Sorts k[0, n) by depth_order(); `scratch` and `runs` are reused buffers. Fragments with
// equal (z, id) would keep no particular order (a triangle crosses a pixel ray once, so they
// do not occur).
inline void sort_by_depth(Fragment* k, std::size_t n, std::vector<Fragment>& scratch,
                          std::vector<std::uint32_t>& runs) {
    // Insertion sort inside runs of at least kMinRun; a scan line cuts its triangles nearest
    // (by their centroids) first, so a pixel's fragments arrive nearly in depth order and
    // already form long monotone runs: descending runs are reversed and the runs merged
    // pairwise. All (depth, code) keys differ, so the order is total.
    constexpr std::size_t kMinRun = 8;
    auto insert_from = [&](std::size_t begin, std::size_t from, std::size_t end) {
        for (std::size_t i = from; i < end; ++i) {
            const Fragment f = k[i];
            std::size_t j = i;
            while (j > begin && depth_order(f, k[j - 1])) {
                k[j] = k[j - 1];
                --j;
            }
            k[j] = f;
        }
    };
    if (n <= 28) { // insertion sort alone is faster here
        insert_from(0, 1, n);
        return;
    }
    runs.clear();
    for (std::size_t i = 0; i < n;) {
        std::size_t j = i + 1;
        if (j < n && depth_order(k[j], k[i])) {
            while (j < n && depth_order(k[j], k[j - 1])) ++j;
            std::reverse(k + i, k + j);
        } else {
            while (j < n && !depth_order(k[j], k[j - 1])) ++j;
        }
        if (j - i < kMinRun) {
            const std::size_t end = std::min(n, i + kMinRun);
            insert_from(i, j, end);
            j = end;
        }
        runs.push_back(static_cast<std::uint32_t>(i));
        i = j;
    }
    runs.push_back(static_cast<std::uint32_t>(n));
    if (scratch.size() < n) scratch.resize(n);
    Fragment* src = k;
    Fragment* dst = scratch.data();
    while (runs.size() > 2) {
        std::size_t out = 0, r = 0;
        for (; r + 2 < runs.size(); r += 2) {
            const Fragment *a = src + runs[r], *a_end = src + runs[r + 1];
            const Fragment *b = a_end, *b_end = src + runs[r + 2];
            Fragment* d = dst + runs[r];
            while (a != a_end && b != b_end) *d++ = depth_order(*b, *a) ? *b++ : *a++;
            d = std::copy(a, a_end, d);
            std::copy(b, b_end, d);
            runs[out++] = runs[r];
        }
        if (r + 1 < runs.size()) {
            std::copy(src + runs[r], src + runs[r + 1], dst + runs[r]);
            runs[out++] = runs[r];
        }
        runs[out++] = static_cast<std::uint32_t>(n);
        runs.resize(out);
        std::swap(src, dst);
    }
    if (src != k) std::copy(src, src + n, k);
}

} // namespace cellfx::fx::scanline
