#include "core/photons/photon_tracer.h"

#include "core/util/cancel_flag.h"
#include "core/util/denormals.h"
#include "core/shading/medium_stack.h"
#include "core/shading/optics.h"
#include "core/util/radiance_range.h"
#include "core/render/random.h"
#include "core/scene/source_location.h"
#include "core/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

namespace caustica {
namespace {

constexpr double pi = 3.14159265358979323846;
constexpr long long block_size = 4096;

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

float mean(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

/// Van der Corput radical inverse in base 2.
float radical_inverse2(std::uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x00ff00ffu) << 8) | ((i & 0xff00ff00u) >> 8);
    i = ((i & 0x0f0f0f0fu) << 4) | ((i & 0xf0f0f0f0u) >> 4);
    i = ((i & 0x33333333u) << 2) | ((i & 0xccccccccu) >> 2);
    i = ((i & 0x55555555u) << 1) | ((i & 0xaaaaaaaau) >> 1);
    return static_cast<float>(i >> 8) * (1.0f / 16777216.0f);
}

/// Uniform direction on the sphere from a point of the unit square (area-preserving).
glm::vec3 sphere_direction(float u, float v) {
    const float y = 1.0f - 2.0f * u;
    const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
    const float phi = 2.0f * static_cast<float>(pi) * v;
    return {r * std::cos(phi), y, r * std::sin(phi)};
}

/// A cosine-weighted direction about the unit normal `n` (Lambertian reflection).
glm::vec3 cosine_direction(const glm::vec3& n, float u1, float u2) {
    const float r = std::sqrt(u1), phi = 2.0f * static_cast<float>(pi) * u2;
    const glm::vec3 helper = std::fabs(n.x) > 0.9f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 t = glm::normalize(glm::cross(helper, n)), b = glm::cross(n, t);
    return glm::normalize(r * std::cos(phi) * t + r * std::sin(phi) * b + std::sqrt(std::max(0.0f, 1.0f - u1)) * n);
}

/// One photon path, or with splitting one branch of it, being followed.
struct Branch {
    Ray ray;
    glm::vec3 power;
    MediumStack media;
    int depth = 0, specular_bounces = 0, bounces = 0;
};

/// With splitting, a branch that keeps less than this share of its parent's power plays roulette
/// (survives with probability share / this, its power divided by that): the 4% a glass reflects
/// is traced one time in five, at five times the power.
constexpr float split_floor = 0.2f;
/// Room reserved for branches waiting to be followed (a photon rarely splits more often; the
/// depth limit bounds how many can wait).
constexpr int pending_branches_reserved = 16;

float mean_of(const glm::vec3& v) { return (v.x + v.y + v.z) / 3.0f; }

/// The dielectric interface a photon meets: the media on either side, their indices and Fresnel's
/// reflectance for its direction (n faces the side it comes from).
struct Interface {
    MediumTransition transition;
    float n1 = 1.0f, n2 = 1.0f, reflectance = 0.0f;
};

Interface interface_at(const std::vector<Material>& materials, const SurfaceHit& hit, const Branch& b,
                       const glm::vec3& n) {
    Interface i{medium_transition(hit, b.ray.direction, b.media)};
    i.n1 = i.transition.from < 0 ? 1.0f : materials[i.transition.from].refractive_index;
    i.n2 = i.transition.to < 0 ? 1.0f : materials[i.transition.to].refractive_index;
    i.reflectance = fresnel_reflectance(i.n1, i.n2, -glm::dot(n, b.ray.direction));
    return i;
}

/// Traces one photon (and, when `split`, every branch it splits into at mirrors and dielectrics);
/// appends to `out` each time it reaches a diffuse surface after a specular bounce. Once `cancel`
/// is set its rays meet nothing: the photon ends at once.
void trace_photon(const RenderScene& scene, Ray ray, glm::vec3 power, int max_depth, float unit_distance,
                  bool global_illumination, bool split, RandomStream& random, std::vector<Photon>& out,
                  const std::atomic<bool>* cancel) {
    const auto& materials = scene.materials();
    const float eps = scene.epsilon();
    // Roulette ends GI paths; the cap only stops pathological ones (albedo 0.9: 0.9^64 = 1e-3 left).
    const int depth_limit = global_illumination ? std::max(max_depth, 64) : max_depth;
    split = split && !global_illumination;
    // Only a splitting photon has branches waiting (allocated then only: a roulette photon's
    // trace must not pay for clearing them).
    std::vector<Branch> pending;
    if (split) pending.reserve(pending_branches_reserved);
    Branch b{ray, power, MediumStack{}, 0, 0, 0};
    for (;;) {
        // Follows branch b until it ends, then the next one waiting.
        bool ended = b.depth > depth_limit;
        SurfaceHit hit;
        if (!ended && !scene.intersect(b.ray, hit, cancel)) ended = true;
        if (ended) {
            if (pending.empty()) return;
            b = pending.back();
            pending.pop_back();
            continue;
        }
        ++b.depth;
        if (const int medium = b.media.top(); medium >= 0)
            b.power = saturate(b.power * medium_transmittance(materials[medium].medium_colour, hit.t, unit_distance));
        const Material& m = materials[hit.material];
        // A diffuse surface reached after a specular interaction stores the photon (an L S+ D
        // path); its incident power is kept, kd is applied when the estimate is shaded.
        if (!m.transparent && m.kd != glm::vec3(0.0f) && (b.specular_bounces > 0 || (global_illumination && b.bounces > 0)))
            out.push_back({hit.position, b.power, b.ray.direction});
        ++b.bounces;
        const RouletteOdds odds = roulette_odds(m);
        const glm::vec3 n = glm::dot(hit.normal, b.ray.direction) < 0.0f ? hit.normal : -hit.normal;
        const glm::vec3 ks = m.air ? glm::vec3(1.0f) : m.ks;
        if (split && odds.specular > 0.0f) {
            // Splitting: the specular part continues with its weight instead of its odds (the
            // diffuse part ends a caustic path, and is stored above); at a dielectric both the
            // reflected and the refracted branch go on. A weak branch plays roulette.
            auto keep = [&](Branch& branch, const glm::vec3& factor) {
                const float share = mean_of(factor);
                if (!(share > 0.0f)) return false;
                branch.power = saturate(branch.power * factor);
                if (share < split_floor) {
                    if (random.uniform() >= share / split_floor) return false;
                    branch.power = saturate(branch.power * (split_floor / share));
                }
                return true;
            };
            ++b.specular_bounces;
            if (!m.transparent) {
                b.ray = Ray{hit.position, glm::reflect(b.ray.direction, n), eps, ray_infinity};
                if (!keep(b, ks)) b.depth = depth_limit + 1;
                continue;
            }
            const Interface face = interface_at(materials, hit, b, n);
            const float reflectance = face.reflectance;
            glm::vec3 refracted;
            const bool refracts = reflectance < 1.0f && refract_direction(b.ray.direction, n, face.n1, face.n2, refracted);
            Branch reflected = b;
            reflected.ray = Ray{hit.position, glm::reflect(b.ray.direction, n), eps, ray_infinity};
            const bool reflects = keep(reflected, ks * (refracts ? reflectance : 1.0f));
            if (refracts) {
                b.media = face.transition.after;
                b.ray = Ray{hit.position, refracted, eps, ray_infinity};
                if (!keep(b, glm::vec3(1.0f - reflectance))) b.depth = depth_limit + 1;
                if (reflects) pending.push_back(reflected);
            } else {
                b = reflected;
                if (!reflects) b.depth = depth_limit + 1;
            }
            continue;
        }
        // Russian roulette decides what happens next (docs/CAUSTICS.md, "Photon paths"). Diffuse
        // reflection ends a caustic path (the caustic map holds no diffuse bounce); so does
        // absorption.
        const float xi = random.uniform();
        if (xi >= odds.diffuse + odds.specular) {  // absorbed
            b.depth = depth_limit + 1;
            continue;
        }
        if (xi < odds.diffuse) {
            if (!global_illumination) {  // the caustic map holds no diffuse bounce
                b.depth = depth_limit + 1;
                continue;
            }
            // Lambertian bounce on the side the photon came from; power kd / P(diffuse) keeps energy.
            b.power = saturate(b.power * (m.kd / odds.diffuse));
            const float u1 = random.uniform(), u2 = random.uniform();
            b.ray = Ray{hit.position, cosine_direction(n, u1, u2), eps, ray_infinity};
            continue;
        }
        // The medium colour: a reflection carries ks; a transmission carries nothing at the
        // surface, the medium's ks^(d/d_u) is applied along the segment inside (above).
        const glm::vec3 reflected_power = saturate(b.power * (ks / odds.specular));  // ks / odds is at most 3
        ++b.specular_bounces;
        if (!m.transparent) {
            b.power = reflected_power;
            b.ray = Ray{hit.position, glm::reflect(b.ray.direction, n), eps, ray_infinity};
            continue;
        }
        const Interface face = interface_at(materials, hit, b, n);
        glm::vec3 refracted;
        if (random.uniform() >= face.reflectance && refract_direction(b.ray.direction, n, face.n1, face.n2, refracted)) {
            b.power = saturate(b.power / odds.specular);
            b.media = face.transition.after;
            b.ray = Ray{hit.position, refracted, eps, ray_infinity};
        } else {
            b.power = reflected_power;
            b.ray = Ray{hit.position, glm::reflect(b.ray.direction, n), eps, ray_infinity};
        }
    }
}

}  // namespace

glm::vec3 photon_energy(const Light& light, double unit_distance, long long photons, double fudge) {
    const double scale = 4.0 * pi * unit_distance * unit_distance / (light.falloff.z * static_cast<double>(photons));
    // scene_validate refuses powers above max_photon_power; the cap keeps the float cast defined.
    const double power = std::fmin(scale * fudge, static_cast<double>(max_radiance));
    return saturate(glm::vec3(light.colour) * static_cast<float>(power));
}

RouletteOdds roulette_odds(const Material& m) {
    RouletteOdds odds;
    if (m.air) {
        odds.specular = 1.0f;
        return odds;
    }
    odds.diffuse = m.transparent ? 0.0f : mean(m.kd);
    odds.specular = (m.reflective || m.transparent) ? mean(m.ks) : 0.0f;
    return odds;
}

double photon_memory_bound(double photons) {
    // Stored photon twice (block buffers, then the map), its tree position, order entry and node share.
    constexpr double bytes_per_photon = sizeof(Photon) * 2 + sizeof(glm::vec3) + 4 + 16.0 / 6.0;
    return photons * bytes_per_photon;
}

void check_photon_memory(double photons, long long requested, double budget_bytes, const char* option) {
    const double budget = budget_bytes > 0.0 ? budget_bytes : default_render_memory_bytes();
    const double needed = photon_memory_bound(photons);
    if (needed <= budget) return;
    char message[320];
    std::snprintf(message, sizeof message,
                  "%s %lld: the %.3g photons the projection maps let through would need up to "
                  "%.1f GiB for the photon map, more than the %.1f GiB the renderer's memory budget leaves "
                  "for photons (--render-memory MiB raises it)",
                  option, requested, photons, needed / (1 << 30), budget / (1 << 30));
    throw InputError(message);
}

PhotonPassResult shoot_caustic_photons(const RenderScene& scene, const std::vector<Light>& lights,
                                       const PhotonPassSettings& settings, const std::atomic<bool>* cancel) {
    PhotonPassResult result;
    if (settings.reuse) {
        result.photons.swap(*settings.reuse);
        result.photons.clear();
    }
    result.maps.resize(lights.size());
    result.lights.resize(lights.size());
    const long long given = settings.photons_per_light;
    // The most directions a light's count may be raised to (--caustic-num-photons' own limit).
    constexpr double max_directions = 1e11;
    const double min_traced = settings.min_traced_per_light > 0.0 ? std::min(settings.min_traced_per_light, max_directions) : 0.0;
    const char* count_option = settings.global_illumination ? "--gi-num-photons" : "--caustic-num-photons";
    double expected_photons = 0.0;  // over all lights: what the maps let through, at most stored
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const Light& light = lights[l];
        LightPhotonReport& report = result.lights[l];
        if (!(light.falloff.z > 0.0f)) {
            report.warning = "has no quadratic falloff (c2 = 0), so it gets no caustic photons";
            continue;
        }
        // Auto decides from what the map would cost (one ray per cell) and save (the photons
        // outside it): no map with fewer photons than twice its cells, and none when a coarse map
        // (1/16 of the rays) shows 90% of the sphere occupied. Measured in docs/PERFORMANCE.md.
        const bool automatic = settings.projection_map == ProjectionMapMode::automatic;
        const long long cells = 2LL * settings.projection_map_granularity * settings.projection_map_granularity;
        const bool prebuilt = !settings.prebuilt_maps.empty();
        // Raised to the minimum traced even if nothing is rejected. With a minimum the map is
        // always worth trying: a map that rejects directions raises the count past its cells.
        const long long unmapped = std::max(given, static_cast<long long>(std::ceil(min_traced)));
        bool try_map = !prebuilt && !settings.global_illumination &&
                       (settings.projection_map == ProjectionMapMode::on ||
                        (automatic && (unmapped > 2 * cells || min_traced > 0.0)));
        const auto t_map = std::chrono::steady_clock::now();
        if (prebuilt && l < settings.prebuilt_maps.size() && settings.prebuilt_maps[l]) {
            result.maps[l] = *settings.prebuilt_maps[l];
            report.occupied_fraction = result.maps[l].occupied_fraction();
            report.projection_map_used = true;
        }
        if (try_map && automatic) {
            ProjectionMap coarse(std::max(8, settings.projection_map_granularity / 4));
            coarse.build(scene, light.position, nullptr, cancel);
            report.occupied_fraction = coarse.occupied_fraction();
            try_map = report.occupied_fraction < 0.9;
        }
        if (try_map) {
            ProjectionMap map(settings.projection_map_granularity);
            map.build(scene, light.position, nullptr, cancel);
            report.occupied_fraction = map.occupied_fraction();
            report.projection_map_used = !automatic || report.occupied_fraction < 0.9;
            result.maps[l] = std::move(map);
        }
        report.map_seconds = seconds_since(t_map);
        const ProjectionMap* map = report.projection_map_used ? &result.maps[l] : nullptr;
        // The directions of this light's pass: enough that min_traced_per_light are traced where
        // the map lets only its occupied fraction through.
        long long count = unmapped;
        if (map && min_traced > 0.0 && report.occupied_fraction > 0.0)
            count = std::max(given, static_cast<long long>(std::ceil(std::min(min_traced / report.occupied_fraction,
                                                                               max_directions))));
        // Progress is counted in directions of the count as given (what the session's total
        // holds), whatever the count was raised to.
        const double progress_scale = static_cast<double>(given) / static_cast<double>(std::max(count, 1LL));
        // Refuse before anything is allocated for photons; margin for the map's padding.
        expected_photons += static_cast<double>(count) * (map ? std::min(1.0, 1.1 * report.occupied_fraction) : 1.0);
        check_photon_memory(expected_photons, count, settings.memory_budget_bytes,
                            count > given ? (std::string("--photons-per-pixel raised ") + count_option + " to").c_str()
                                          : count_option);
        const auto t0 = std::chrono::steady_clock::now();
        const glm::vec3 energy = photon_energy(light, settings.unit_distance, count, settings.energy_fudge);
        const bool low_discrepancy = settings.emission == PhotonEmission::low_discrepancy;
        std::vector<std::vector<Photon>> stored;
        std::vector<long long> traced;
        auto shoot = [&](RandomStream& random, const glm::vec3& direction, const glm::vec3& power, std::vector<Photon>& out) {
            glm::vec3 origin = light.position;
            if (light.radius > 0.0f) {  // spherical light: leave from its surface
                glm::vec3 s = sphere_direction(random.uniform(), random.uniform());
                if (glm::dot(s, direction) < 0.0f) s = -s;
                origin += light.radius * s;
            }
            trace_photon(scene, Ray{origin, direction, 0.0f, ray_infinity}, power, settings.max_depth,
                         static_cast<float>(settings.unit_distance), settings.global_illumination, settings.split, random,
                         out, cancel);
        };
        if (map) {
            // Directions are drawn inside the map's occupied cells only: each cell gets its share
            // of the count (rounded as below, right on average), every photon the energy of one
            // direction of the count, in an even pattern inside the cell (a Hammersley set). Pass
            // after pass the patterns move by a low-discrepancy step (R2), so the passes together
            // stay evenly spread.
            const OccupiedCells occupied(*map);
            const auto& cells = occupied.cells();
            // Guided emission: cell c gets its share times m_c of the count, each of its photons
            // the energy of 1 / m_c directions; the m_c are the weights scaled so that the shares
            // still add up to the occupied fraction (the count is kept).
            const std::vector<float>* weights = l < settings.emission_weights.size() ? settings.emission_weights[l] : nullptr;
            if (weights && weights->size() != cells.size()) weights = nullptr;
            std::vector<double> multiplier;
            if (weights) {
                double weighted = 0.0;
                for (std::size_t c = 0; c < cells.size(); ++c) weighted += cells[c].share * static_cast<double>((*weights)[c]);
                if (weighted > 0.0 && std::isfinite(weighted)) {
                    multiplier.resize(cells.size());
                    for (std::size_t c = 0; c < cells.size(); ++c)
                        multiplier[c] = static_cast<double>((*weights)[c]) * occupied.fraction() / weighted;
                }
            }
            auto multiplier_of = [&](std::size_t c) { return multiplier.empty() ? 1.0 : multiplier[c]; };
            if (settings.record_cells) {
                report.cells.traced.assign(cells.size(), 0);
                report.cells.stored.assign(cells.size(), 0);
            }
            // Systematic sampling of the counts: cell c gets floor(C_c + rho) - floor(C_{c-1} + rho)
            // photons, C the cumulative expected count and rho one offset for the pass, so the total
            // is the expected one to a photon and neighbouring cells are rounded in opposite ways.
            std::vector<long long> first(cells.size() + 1, 0);
            // Progress: the directions of the count as given that the cells up to c stand for, so
            // that the light's increments add up to that count exactly.
            std::vector<long long> progress_at(settings.progress ? cells.size() + 1 : 0, 0);
            {
                RandomStream offset(settings.sequence_seed, 0x726f756e64 ^ l, 9);
                double rho = offset.uniform() + static_cast<double>(settings.pass) * 0.6180339887498949;
                rho -= std::floor(rho);
                double cumulative = 0.0, cumulative_share = 0.0;
                for (std::size_t c = 0; c < cells.size(); ++c) {
                    cumulative += static_cast<double>(count) * cells[c].share * multiplier_of(c);
                    first[c + 1] = static_cast<long long>(std::floor(cumulative + rho));
                    cumulative_share += cells[c].share;
                    if (settings.progress)
                        progress_at[c + 1] = c + 1 == cells.size() ? given
                                                                   : std::llround(static_cast<double>(given) *
                                                                                  cumulative_share / occupied.fraction());
                }
            }
            constexpr std::size_t cells_per_block = 32;
            const std::size_t blocks = (cells.size() + cells_per_block - 1) / cells_per_block;
            stored.resize(blocks);
            traced.assign(blocks, 0);
            const double step_s = 0.7548776662466927, step_t = 0.5698402909980532;  // the R2 sequence
            const double pass = static_cast<double>(settings.pass);
            caustica::parallel_for(tbb::blocked_range<std::size_t>(0, blocks, 1), [&](const tbb::blocked_range<std::size_t>& r) {
                const ScopedFlushDenormals flush;
                for (std::size_t b = r.begin(); b != r.end(); ++b) {
                    if (cancel && cancel->load(std::memory_order_relaxed)) return;
                    for (std::size_t c = b * cells_per_block; c < std::min(cells.size(), (b + 1) * cells_per_block); ++c) {
                        RandomStream base(settings.sequence_seed, (static_cast<std::uint64_t>(l) << 40) ^ c, 9);
                        const double base_s = base.uniform(), base_t = base.uniform();
                        const long long n = first[c + 1] - first[c];
                        double shift_s = base_s + pass * step_s, shift_t = base_t + pass * step_t;
                        shift_s -= std::floor(shift_s);
                        shift_t -= std::floor(shift_t);
                        if (settings.progress)
                            settings.progress->fetch_add(progress_at[c + 1] - progress_at[c], std::memory_order_relaxed);
                        const glm::vec3 power = saturate(energy / static_cast<float>(multiplier_of(c)));
                        const std::size_t stored_before = stored[b].size();
                        for (long long j = 0; j < n; ++j) {
                            // A cell may hold any share of the count: the flag is read within it.
                            if (j % steps_between_cancel_checks == 0 && is_cancelled(cancel)) return;
                            // Beyond 2^24 photons in a cell (a count raised per pixel can get
                            // there) the packed key would reach the next cell's: hashed instead.
                            const auto jj = static_cast<std::uint64_t>(j);
                            const std::uint64_t key =
                                jj < (std::uint64_t{1} << 24)
                                    ? (static_cast<std::uint64_t>(l) << 56) ^ (static_cast<std::uint64_t>(c) << 24) ^ jj
                                    : hash_combine(hash_combine(0x6d616e79ULL ^ static_cast<std::uint64_t>(l), c), jj);
                            RandomStream random(settings.seed, key, 3);
                            double u, v;
                            if (low_discrepancy) {
                                u = (static_cast<double>(j) + 0.5) / static_cast<double>(n) + shift_s;
                                v = radical_inverse2(static_cast<std::uint32_t>(j)) + shift_t;
                                u -= std::floor(u);
                                v -= std::floor(v);
                            } else {
                                u = random.uniform();
                                v = random.uniform();
                            }
                            ++traced[b];
                            shoot(random, occupied.direction(c, u, v), power, stored[b]);
                        }
                        if (settings.record_cells) {  // each cell is one thread's: no race
                            constexpr long long most = std::numeric_limits<std::uint32_t>::max();
                            report.cells.traced[c] = static_cast<std::uint32_t>(std::min(n, most));
                            report.cells.stored[c] = static_cast<std::uint32_t>(
                                std::min(static_cast<long long>(stored[b].size() - stored_before), most));
                        }
                    }
                }
            });
        } else {
            const long long blocks = (count + block_size - 1) / block_size;
            stored.resize(static_cast<std::size_t>(blocks));
            traced.assign(static_cast<std::size_t>(blocks), 0);
            RandomStream rotation_stream(settings.seed, 0x70686f746f6e ^ l, 7);
            const float rotate_u = rotation_stream.uniform(), rotate_v = rotation_stream.uniform();
            caustica::parallel_for(tbb::blocked_range<long long>(0, blocks, 1), [&](const tbb::blocked_range<long long>& r) {
                const ScopedFlushDenormals flush;
                for (long long b = r.begin(); b != r.end(); ++b) {
                    if (cancel && cancel->load(std::memory_order_relaxed)) return;
                    const long long begin = b * block_size, end = std::min(count, (b + 1) * block_size);
                    if (settings.progress)
                        settings.progress->fetch_add(std::llround(static_cast<double>(end) * progress_scale) -
                                                         std::llround(static_cast<double>(begin) * progress_scale),
                                                     std::memory_order_relaxed);
                    for (long long i = begin; i < end; ++i) {
                        RandomStream random(settings.seed, (static_cast<std::uint64_t>(l) << 40) ^ static_cast<std::uint64_t>(i), 3);
                        float u, v;
                        if (low_discrepancy) {  // a Hammersley set over the sphere, rotated
                            const double w = (static_cast<double>(i) + 0.5) / static_cast<double>(count) + rotate_u;
                            u = static_cast<float>(w - std::floor(w));
                            v = radical_inverse2(static_cast<std::uint32_t>(i)) + rotate_v;
                            v -= std::floor(v);
                        } else {
                            u = random.uniform();
                            v = random.uniform();
                        }
                        ++traced[static_cast<std::size_t>(b)];
                        shoot(random, sphere_direction(u, v), energy, stored[static_cast<std::size_t>(b)]);
                    }
                }
            });
        }
        report.candidates = count;
        for (std::size_t b = 0; b < stored.size(); ++b) {
            report.traced += traced[b];
            report.stored += static_cast<long long>(stored[b].size());
            result.photons.insert(result.photons.end(), stored[b].begin(), stored[b].end());
        }
        report.shoot_seconds = seconds_since(t0);
    }
    return result;
}

}  // namespace caustica
