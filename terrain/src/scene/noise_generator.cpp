// Fractal 2-D gradient noise for scene files (terrain/scene.hpp NoiseSpec): fBm of improved
// Perlin noise from fx::Noise (docs/noise.md) — seedable, the same on every platform, smooth far
// from the origin, octave amplitudes normalised to sum to 1.
#include <cmath>

#include "fx/error.hpp"
#include "fx/noise.hpp"
#include "terrain/scene.hpp"

namespace cellfx::terrain {

HeightGenerator make_noise_generator(const NoiseSpec& spec) {
    if (!(spec.frequency > 0.0) || !std::isfinite(spec.frequency)) throw fx::Error("noise: frequency must be positive");
    if (spec.octaves < 1 || spec.octaves > 16) throw fx::Error("noise: octaves must be in 1..16");
    if (!(spec.lacunarity > 0.0) || !(spec.gain > 0.0) || !std::isfinite(spec.lacunarity) || !std::isfinite(spec.gain))
        throw fx::Error("noise: lacunarity and gain must be positive");
    if (!std::isfinite(spec.amplitude) || !std::isfinite(spec.offset)) throw fx::Error("noise: amplitude and offset must be finite");
    fx::Fractal fractal;
    fractal.basis = fx::NoiseBasis::perlin;
    fractal.type = fx::FractalType::fbm;
    fractal.octaves = spec.octaves;
    fractal.frequency = spec.frequency;
    fractal.lacunarity = spec.lacunarity;
    fractal.gain = float(spec.gain);
    const fx::Noise noise(spec.seed);
    noise.fractal2(fractal, 0.0, 0.0); // checks the settings once, here, rather than per sample
    return [noise, fractal, spec](double x, double y) {
        return spec.offset + spec.amplitude * double(noise.fractal2(fractal, x, y));
    };
}

} // namespace cellfx::terrain
