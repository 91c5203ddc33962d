// Fractal 2-D gradient noise for scene files (terrain/scene.hpp NoiseSpec): fBm over Perlin's
// improved noise from stb_perlin (libstb), normalised so the octaves' amplitudes sum to 1.
#include <cmath>

#include <stb_perlin.h>

#include "fx/error.hpp"
#include "terrain/scene.hpp"

namespace terrain {

HeightGenerator make_noise_generator(const NoiseSpec& spec) {
    if (!(spec.frequency > 0.0) || !std::isfinite(spec.frequency)) throw fx::Error("noise: frequency must be positive");
    if (spec.octaves < 1 || spec.octaves > 16) throw fx::Error("noise: octaves must be in 1..16");
    if (!(spec.lacunarity > 0.0) || !(spec.gain > 0.0)) throw fx::Error("noise: lacunarity and gain must be positive");
    double norm = 0.0, a = 1.0;
    for (int o = 0; o < spec.octaves; ++o) norm += a, a *= spec.gain;
    // Different seeds sample different slices of the 3-D noise (its lattice repeats every 256).
    const float slice = float(0.5 + 37.13 * double(spec.seed % 6u) + 0.61803 * double(spec.seed / 6u % 61u));
    return [spec, norm, slice](double x, double y) {
        double sum = 0.0, amplitude = 1.0, frequency = spec.frequency;
        for (int o = 0; o < spec.octaves; ++o) {
            sum += amplitude * stb_perlin_noise3_seed(float(std::fmod(x * frequency, 256.0)),
                                                      float(std::fmod(y * frequency, 256.0)), slice, 0, 0, 0,
                                                      int(spec.seed + 101u * unsigned(o)));
            amplitude *= spec.gain;
            frequency *= spec.lacunarity;
        }
        return spec.offset + spec.amplitude * sum / norm;
    };
}

} // namespace terrain
