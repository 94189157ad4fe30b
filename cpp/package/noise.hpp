// asperity::noise: the procedural noises of the detail operators (Perlin's improved noise,
// its fractal sums, Gabor and phasor noise; thesis §3.3, §4.7.3) evaluated at given points,
// with every parameter of `asperity noise`.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "asperity/errors.hpp"
#include "asperity/fields.hpp"
#include "asperity/mesh_arrays.hpp"

namespace asperity {

/// The library's noise request (`asperity noise`'s parameters, see `asperity noise --help`);
/// unset options take their kind's defaults, and an option of another kind is refused.
struct NoiseOptions {
  /// perlin, fbm, turbulence, marble, multifractal, wood, gabor or phasor.
  std::string kind = "perlin";
  std::optional<std::uint32_t> octaves;
  std::optional<double> lacunarity;
  std::optional<double> gain;
  /// The multifractal's offset d (eq. 4.12).
  std::optional<double> offset;
  /// Gabor and phasor: magnitude K, bandwidth a, frequency F0, orientation ω0, impulses.
  std::optional<double> k;
  std::optional<double> a;
  std::optional<double> f0;
  std::optional<double> omega;
  std::optional<double> impulses;
  bool isotropic = false;
  /// Phasor noise's profile: sine, square or sawtooth.
  std::optional<std::string> profile;
  std::uint64_t seed = 0;
  /// "f64" (the default) or "f32": single precision, a different noise (Perlin and fBm).
  std::optional<std::string> precision;
};

namespace impl {

/// The options as the library's noise request (`asperity::noise::NoiseRequest`).
inline std::string noise_fields(const NoiseOptions& o) {
  Fields f;
  f.add("kind", o.kind).add("octaves", o.octaves).add("lacunarity", o.lacunarity).add("gain", o.gain);
  f.add("offset", o.offset).add("k", o.k).add("a", o.a).add("f0", o.f0).add("omega", o.omega);
  f.add("impulses", o.impulses).add("isotropic", o.isotropic).add("profile", o.profile).add("seed", o.seed);
  f.add("precision", o.precision);
  return f.json();
}

template <std::size_t D>
std::vector<double> sample(const std::vector<std::array<double, D>>& points, const NoiseOptions& options) {
  std::vector<double> flat;
  flat.reserve(D * points.size());
  for (const auto& p : points) flat.insert(flat.end(), p.begin(), p.end());
  const auto fields = noise_fields(options);
  const auto values = call([&] { return ffi::noise(slice(flat), D, fields); });
  return std::vector<double>(values.begin(), values.end());
}

}  // namespace impl

/// The noise at points in space (the global frame), one value per point.
inline std::vector<double> noise(const std::vector<Vec3>& points, const NoiseOptions& options = NoiseOptions()) {
  return impl::sample(points, options);
}

/// The noise at points of the plane, as `asperity noise`'s images sample it.
inline std::vector<double> noise(const std::vector<std::array<double, 2>>& points,
                                 const NoiseOptions& options = NoiseOptions()) {
  return impl::sample(points, options);
}

}  // namespace asperity
