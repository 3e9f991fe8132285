#include "core/photons/classic_photons.h"

#include "core/shading/classic_interface.h"
#include "core/shading/optics.h"
#include "core/shading/texture.h"
#include "core/util/cancel_flag.h"
#include "core/util/denormals.h"
#include "core/util/radiance_range.h"
#include "core/util/parallel.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <utility>

namespace caustica {
namespace {

constexpr double pi = 3.14159265358979323846;

// Emission cells (docs/CAUSTICS.md, "The emission cells"). The original split the sphere into the
// 1 310 720 triangles of an icosahedron whose faces were subdivided 8 times, each triangle into
// four at its edge midpoints, every midpoint pushed onto the unit sphere as soon as it was made (a
// geodesic subdivision: the largest cell's solid angle is 1.30 times the smallest's), and shot
// floor(N a_T) photons in each, a_T the cell's share of the sphere. We do the same without storing
// the triangles: a cell is named by its face and the child taken at each level (corner a, b, c or
// the middle), and its vertices are found by descending from the face.
// The photons are shot from blocks of 4^5 cells (a level-3 triangle each, 1280 blocks), walked
// depth first. Inside a cell the direction is uniform in solid angle: a point p uniform on the flat
// triangle through the cell's vertices, projected, has density proportional to |p|^3, so it is
// accepted with probability (r / |p|)^3, r a lower bound of |p| over the triangle (nearly every
// point is accepted at once).
constexpr int block_levels = 5;  // levels walked inside a block
constexpr int top_levels = classic_emission_levels - block_levels;
constexpr long long cells_per_block = 1LL << (2 * block_levels);
constexpr int emission_blocks = static_cast<int>(classic_emission_cells / cells_per_block);

struct Icosahedron {
    std::array<glm::dvec3, 12> vertices;
    std::array<std::array<int, 3>, 20> faces;
};

/// The icosahedron inscribed in the unit sphere: vertices (0, +-1, +-phi) and their cyclic
/// permutations, faces the triples whose vertices are pairwise one edge (2 before normalising)
/// apart, oriented outwards.
const Icosahedron& icosahedron() {
    static const Icosahedron shape = [] {
        Icosahedron s{};
        const double phi = 0.5 * (1.0 + std::sqrt(5.0));
        int v = 0;
        for (double p : {-1.0, 1.0})
            for (double q : {-phi, phi}) {
                s.vertices[v++] = {0.0, p, q};
                s.vertices[v++] = {p, q, 0.0};
                s.vertices[v++] = {q, 0.0, p};
            }
        auto adjacent = [&](int i, int j) {
            const glm::dvec3 d = s.vertices[i] - s.vertices[j];
            return std::fabs(glm::dot(d, d) - 4.0) < 1e-9;
        };
        int f = 0;
        for (int i = 0; i < 12; ++i)
            for (int j = i + 1; j < 12; ++j)
                for (int k = j + 1; k < 12; ++k) {
                    if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
                    const glm::dvec3 &a = s.vertices[i], &b = s.vertices[j], &c = s.vertices[k];
                    const bool outward = glm::dot(glm::cross(b - a, c - a), a + b + c) > 0.0;
                    s.faces[f++] = outward ? std::array<int, 3>{i, j, k} : std::array<int, 3>{i, k, j};
                }
        for (glm::dvec3& vertex : s.vertices) vertex = glm::normalize(vertex);
        return s;
    }();
    return shape;
}

/// One subdivision step of a triangle with unit vertices: the child `digit` (0, 1, 2: at corner
/// a, b, c; 3: the middle one), cut at the edge midpoints pushed onto the unit sphere.
void subdivide(glm::dvec3& a, glm::dvec3& b, glm::dvec3& c, int digit) {
    const glm::dvec3 ab = glm::normalize(a + b), bc = glm::normalize(b + c), ca = glm::normalize(c + a);
    switch (digit) {
        case 0: b = ab, c = ca; break;
        case 1: a = ab, c = bc; break;
        case 2: a = ca, b = bc; break;
        default: a = ab, b = bc, c = ca; break;
    }
}

/// The triangle named by the `levels` digits of `prefix` (a face index then base-4 digits).
void descend(long long prefix, int levels, glm::dvec3& a, glm::dvec3& b, glm::dvec3& c) {
    const Icosahedron& ico = icosahedron();
    const auto& face = ico.faces[static_cast<std::size_t>(prefix >> (2 * levels))];
    a = ico.vertices[face[0]], b = ico.vertices[face[1]], c = ico.vertices[face[2]];
    for (int level = levels - 1; level >= 0; --level) subdivide(a, b, c, static_cast<int>((prefix >> (2 * level)) & 3));
}

/// Calls visit(cell, a, b, c) for every cell under the triangle (a, b, c), `levels` further
/// down, in cell order; `cell` is the triangle's prefix.
template <class Visit>
void visit_cells(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, int levels, long long cell,
                 Visit& visit) {
    if (levels == 0) {
        visit(cell, a, b, c);
        return;
    }
    for (int digit = 0; digit < 4; ++digit) {
        glm::dvec3 ca = a, cb = b, cc = c;
        subdivide(ca, cb, cc, digit);
        visit_cells(ca, cb, cc, levels - 1, cell * 4 + digit, visit);
    }
}

/// Calls visit(cell, a, b, c) for every cell of emission block `block`.
template <class Visit>
void visit_block(int block, Visit& visit) {
    glm::dvec3 a, b, c;
    descend(block, top_levels, a, b, c);
    visit_cells(a, b, c, block_levels, block, visit);
}

/// Solid angle of the cell with unit vertices (a, b, c).
double cell_solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    return spherical_triangle_solid_angle(a, b, c);
}

/// floor(N a_T) for a cell of solid angle `omega`. Below one photon per cell (N under
/// 1 310 720) that rule would shoot nothing at all under 1 086 326 photons (the largest cell's
/// 1 / a_T), the default --gi-num-photons of 10^6 included, so there each cell's share is rounded
/// up or down by a uniform number fixed per cell: N photons on average, and a map that works.
long long cell_photons(long long requested, double omega, long long cell) {
    const double share = static_cast<double>(requested) * omega / (4.0 * pi);
    if (requested >= classic_emission_cells) return static_cast<long long>(std::floor(share));
    const double u = static_cast<double>(mix64(static_cast<std::uint64_t>(cell) + 0x5eedULL) >> 11) * 0x1.0p-53;
    return static_cast<long long>(std::floor(share + u));
}

/// A lower bound of |p| over the flat cell (a, b, c): no point of it is farther than the longest
/// edge from a vertex, and none is nearer to the centre than the face's plane (`plane_distance`).
double cell_min_radius(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double plane_distance) {
    const double edge = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    const double vertex = std::min({glm::length(a), glm::length(b), glm::length(c)});
    return std::max(plane_distance, vertex - edge);
}

/// A direction uniform in solid angle inside the flat cell (a, b, c), from the photon's stream.
glm::vec3 direction_in_cell(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, double min_radius,
                            RandomStream& random) {
    const double r3 = min_radius * min_radius * min_radius;
    glm::dvec3 p;
    for (int attempt = 0; attempt < 256; ++attempt) {  // about 97% are accepted at the first attempt
        const double s = std::sqrt(static_cast<double>(random.uniform()));
        const double t = random.uniform();
        p = (1.0 - s) * a + s * (1.0 - t) * b + s * t * c;
        const double r = glm::length(p);
        if (static_cast<double>(random.uniform()) * r * r * r <= r3) break;
    }
    return glm::vec3(glm::normalize(p));
}

/// Whether any direction of the spherical cell (a, b, c) can fall in a set cell of the
/// projection map: the map cells over the rows and columns its vertices span, widened by one
/// each way for the arcs' bulge (and all columns when the cell is near a pole or its longitudes
/// wrap widely). Conservative: a cell it rejects holds no photon the map would keep, so skipping
/// its photons changes nothing but the time (the per-photon test stays).
bool cell_may_reach_map(const ProjectionMap& map, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    const glm::dvec3 v[3] = {glm::normalize(a), glm::normalize(b), glm::normalize(c)};
    const int rows = map.rows(), columns = map.columns();
    int row_lo = rows, row_hi = -1;
    double phi[3];
    bool near_pole = false;
    for (int i = 0; i < 3; ++i) {
        const int row = static_cast<int>(std::acos(std::clamp(v[i].y, -1.0, 1.0)) / pi * rows);
        row_lo = std::min(row_lo, row), row_hi = std::max(row_hi, row);
        near_pole = near_pole || std::fabs(v[i].y) > 0.999;
        phi[i] = std::atan2(v[i].z, v[i].x) / (2.0 * pi);
        if (phi[i] < 0.0) phi[i] += 1.0;
    }
    row_lo = std::max(0, row_lo - 1), row_hi = std::min(rows - 1, row_hi + 1);
    double lo = std::min({phi[0], phi[1], phi[2]}), hi = std::max({phi[0], phi[1], phi[2]});
    if (hi - lo > 0.5) {  // the cell straddles phi = 0: measure it the other way round
        for (double& p : phi)
            if (p < 0.5) p += 1.0;
        lo = std::min({phi[0], phi[1], phi[2]}), hi = std::max({phi[0], phi[1], phi[2]});
    }
    int column_lo = static_cast<int>(std::floor(lo * columns)) - 1, column_hi = static_cast<int>(std::floor(hi * columns)) + 1;
    if (near_pole || hi - lo > 0.25) column_lo = 0, column_hi = columns - 1;
    for (int row = row_lo; row <= row_hi; ++row)
        for (int column = column_lo; column <= column_hi; ++column)
            if (map.cell(row, ((column % columns) + columns) % columns)) return true;
    return false;
}

/// The diffuse choice, the specular one or absorption, by the cumulative luma odds ("roulette").
enum class Choice { diffuse, specular, absorbed };

/// What a photon sees of the material it enters ("The material entered"): air (the outside or
/// gr.air()) has kd = 0, ks = 1 and is transparent.
struct EnteredSurface {
    glm::vec3 kd{0.0f}, ks{1.0f};
    bool reflective = false, transparent = true;
};

EnteredSurface entered_surface(const std::vector<Material>& materials, const TextureSet* textures, int entered,
                               const SurfaceHit& hit) {
    EnteredSurface s;
    if (classic_is_air(materials, entered)) return s;
    const Material& m = materials[static_cast<std::size_t>(entered)];
    s.kd = textures ? textures->diffuse(entered, hit, m.kd) : m.kd;
    s.ks = m.ks;
    s.reflective = m.reflective;
    s.transparent = m.transparent;
    return s;
}

Choice choose(const EnteredSurface& m, RandomStream& random) {
    const double xi = random.uniform();
    const double p_diffuse = classic_luma(m.kd);
    if (xi < p_diffuse) return Choice::diffuse;
    const double p_specular = (m.reflective || m.transparent) ? classic_luma(m.ks) : 0.0;
    return xi < p_diffuse + p_specular ? Choice::specular : Choice::absorbed;
}

/// Random-stream key of photon j of a cell, for a map and a light.
std::uint64_t photon_key(ClassicMapKind kind, std::size_t light, long long cell, long long j) {
    std::uint64_t h = hash_combine(kind == ClassicMapKind::caustic ? 0x636c6173736963ULL : 0x676900ULL, light);
    return hash_combine(hash_combine(h, static_cast<std::uint64_t>(cell)), static_cast<std::uint64_t>(j));
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Shoots the photons of one map for one light into `out`; fills the report's counts.
void shoot_light(const RenderScene& scene, const TextureSet* textures, const Light& light, std::size_t l,
                 ClassicMapKind kind, long long requested, const glm::vec3& energy, const ProjectionMap* map,
                 std::uint64_t seed, const std::atomic<bool>* cancel, int share_rank, int share_size,
                 std::atomic<long long>* progress, std::vector<Photon>& out, std::uint32_t* block_counts,
                 LightPhotonReport& report) {
    std::vector<std::vector<Photon>> stored(emission_blocks);
    std::vector<long long> offered(emission_blocks, 0), traced(emission_blocks, 0);
    caustica::parallel_for(tbb::blocked_range<int>(0, emission_blocks, 1), [&](const tbb::blocked_range<int>& range) {
        const ScopedFlushDenormals flush;
        for (int block = range.begin(); block != range.end(); ++block) {
            if (cancel && cancel->load(std::memory_order_relaxed)) return;
            if (block % share_size != share_rank) continue;  // another rank's
            auto visit = [&](long long cell, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
                const long long count = cell_photons(requested, cell_solid_angle(a, b, c), cell);
                offered[block] += count;
                if (count == 0 || (map && !cell_may_reach_map(*map, a, b, c))) return;
                const double h = std::fabs(glm::dot(glm::normalize(glm::cross(b - a, c - a)), a));
                const double min_radius = cell_min_radius(a, b, c, h);
                for (long long j = 0; j < count; ++j) {
                    // A block's cells may hold any share of the photons: the flag is read within them.
                    if (j % steps_between_cancel_checks == 0 && is_cancelled(cancel)) return;
                    RandomStream random(seed, photon_key(kind, l, cell, j), 5);
                    const glm::vec3 direction = direction_in_cell(a, b, c, min_radius, random);
                    if (map) {  // the map's cells by u = (1 - cos theta) / 2 and phi / 2 pi
                        double v = std::atan2(static_cast<double>(direction.z), static_cast<double>(direction.x)) / (2.0 * pi);
                        if (v < 0.0) v += 1.0;
                        const float u = 0.5f * (1.0f - direction.y);
                        if (!map->occupied_uv(u, static_cast<float>(v))) continue;
                    }
                    ++traced[block];
                    trace_classic_photon(scene, textures, kind, Ray{light.position, direction, 0.0f, ray_infinity},
                                         energy, random, stored[block], cancel);
                }
            };
            visit_block(block, visit);
            if (progress) progress->fetch_add(offered[block], std::memory_order_relaxed);
        }
    });
    for (int block = 0; block < emission_blocks; ++block) {
        report.candidates += offered[block];
        report.traced += traced[block];
        report.stored += static_cast<long long>(stored[block].size());
        block_counts[block] = static_cast<std::uint32_t>(stored[block].size());
        out.insert(out.end(), stored[block].begin(), stored[block].end());
    }
}

}  // namespace

double spherical_triangle_solid_angle(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
    // tan(omega / 2) = |a . (b x c)| / (1 + a.b + b.c + c.a) (Van Oosterom and Strackee).
    const double triple = std::fabs(glm::dot(a, glm::cross(b, c)));
    return 2.0 * std::atan2(triple, 1.0 + glm::dot(a, b) + glm::dot(b, c) + glm::dot(c, a));
}

void classic_emission_cell(long long cell, glm::dvec3& a, glm::dvec3& b, glm::dvec3& c) {
    descend(cell, classic_emission_levels, a, b, c);
    a = glm::normalize(a), b = glm::normalize(b), c = glm::normalize(c);
}

namespace {

/// classic_photons_offered without its cache: a walk over every cell.
long long sum_offered(long long requested) {
    return caustica::parallel_reduce(
        tbb::blocked_range<int>(0, emission_blocks, 1), 0LL,
        [&](const tbb::blocked_range<int>& range, long long sum) {
            auto visit = [&](long long cell, const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c) {
                sum += cell_photons(requested, cell_solid_angle(a, b, c), cell);
            };
            for (int block = range.begin(); block != range.end(); ++block) visit_block(block, visit);
            return sum;
        },
        [](long long x, long long y) { return x + y; });
}

}  // namespace

long long classic_photons_offered(long long requested) {
    if (requested <= 0) return 0;
    // A few (requested, offered) pairs, replaced oldest first; the sum is computed outside the lock.
    static std::mutex mutex;
    static std::array<std::pair<long long, long long>, 4> recent{};
    static std::size_t next = 0;
    {
        std::lock_guard lock(mutex);
        for (const auto& [asked, offered] : recent)
            if (asked == requested) return offered;
    }
    const long long offered = sum_offered(requested);
    std::lock_guard lock(mutex);
    recent[next] = {requested, offered};
    next = (next + 1) % recent.size();
    return offered;
}

glm::vec3 classic_diffuse_direction(const glm::vec3& incoming, const glm::vec3& normal, float u1, float u2) {
    const glm::vec3 mirror = glm::reflect(incoming, normal);
    // An orthonormal basis around the mirror direction (Duff et al. 2017, branchless).
    const float sign = std::copysign(1.0f, mirror.z);
    const float a = -1.0f / (sign + mirror.z);
    const float b = mirror.x * mirror.y * a;
    const glm::vec3 t1(1.0f + sign * mirror.x * mirror.x * a, sign * b, -sign * mirror.x);
    const glm::vec3 t2(b, sign + mirror.y * mirror.y * a, -mirror.y);
    const float sin_alpha = u1, cos_alpha = std::sqrt(std::fmax(0.0f, 1.0f - u1 * u1));
    const float azimuth = 2.0f * static_cast<float>(pi) * u2;
    glm::vec3 d = cos_alpha * mirror + sin_alpha * (std::cos(azimuth) * t1 + std::sin(azimuth) * t2);
    return glm::normalize(d);  // below the surface it goes on into the solid: the lobe is not clipped
}

bool classic_projection_target(const Material& m) {
    return m.air || classic_luma(m.ks) > classic_projection_ks_luma;  // air counts with ks = 1
}

int trace_classic_photon(const RenderScene& scene, const TextureSet* textures, ClassicMapKind kind, Ray ray,
                         glm::vec3 power, RandomStream& random, std::vector<Photon>& out,
                         const std::atomic<bool>* cancel) {
    const auto& materials = scene.materials();
    const float eps = scene.epsilon();
    bool after_specular = false, after_diffuse = false;
    int hits = 0;
    while (hits < classic_max_hits) {
        SurfaceHit hit;
        if (!scene.intersect(ray, hit, cancel)) break;
        ++hits;  // every surface counts, gr.air() ones included
        // The odds, the power and what is stored all come from the material entered, as for view
        // rays.
        const ClassicInterface side = classic_interface(materials, hit, ray.direction);
        const EnteredSurface m = entered_surface(materials, textures, side.entered, hit);
        // Storing looks at what came before this hit, whatever the hit chooses next.
        if (kind == ClassicMapKind::caustic && after_specular) {
            const glm::vec3 stored = saturate(power * m.kd);
            if (classic_luma(stored) > 0.0) out.push_back({hit.position, stored, ray.direction});
        } else if (kind == ClassicMapKind::gi && after_diffuse && !classic_is_air(materials, side.entered)) {
            out.push_back({hit.position, saturate(power * m.kd), ray.direction});
        }
        const Choice choice = choose(m, random);
        if (choice == Choice::absorbed) break;
        const glm::vec3 n = side.entering ? hit.normal : -hit.normal;  // faces the photon
        if (choice == Choice::diffuse) {
            if (kind == ClassicMapKind::caustic) break;  // a caustic path holds no diffuse bounce
            after_diffuse = true;
            power = saturate(power * m.kd);  // not divided by P(diffuse): "roulette"
            const float u1 = random.uniform(), u2 = random.uniform();
            ray = Ray{hit.position, classic_diffuse_direction(ray.direction, n, u1, u2), eps, ray_infinity};
            continue;
        }
        after_specular = true;
        power = saturate(power * m.ks);  // not divided by P(specular): "roulette"
        if (!m.transparent) {  // a mirror reflects always (R = 1)
            ray = Ray{hit.position, glm::reflect(ray.direction, n), eps, ray_infinity};
            continue;
        }
        // A dielectric interface (air included): Fresnel chooses reflection or refraction.
        const float n1 = classic_index(materials, side.near_side), n2 = classic_index(materials, side.far_side);
        const float reflectance = fresnel_reflectance(n1, n2, -glm::dot(n, ray.direction));
        glm::vec3 refracted;
        if (random.uniform() >= reflectance && refract_direction(ray.direction, n, n1, n2, refracted))
            ray = Ray{hit.position, refracted, eps, ray_infinity};
        else
            ray = Ray{hit.position, glm::reflect(ray.direction, n), eps, ray_infinity};
    }
    return hits;
}

ClassicPhotonResult shoot_classic_photons(const RenderScene& scene, const TextureSet* textures,
                                          const std::vector<Light>& lights, const ClassicPhotonSettings& settings,
                                          const std::atomic<bool>* cancel) {
    ClassicPhotonResult result;
    result.maps.resize(lights.size());
    result.caustic_lights.resize(lights.size());
    result.gi_lights.resize(lights.size());
    result.caustic_blocks.assign(lights.size() * emission_blocks, 0);
    result.gi_blocks.assign(lights.size() * emission_blocks, 0);
    const int share_size = std::max(1, settings.share_size);
    const int share_rank = std::clamp(settings.share_rank, 0, share_size - 1);
    const long long caustic_offered = classic_photons_offered(settings.caustic_photons);
    const long long gi_offered = classic_photons_offered(settings.gi_photons);
    double expected_caustic = 0.0, expected_gi = 0.0;  // over all lights, checked before shooting
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const Light& light = lights[l];
        LightPhotonReport& caustic = result.caustic_lights[l];
        LightPhotonReport& gi = result.gi_lights[l];
        if (!(light.falloff.z > 0.0f)) {  // photon_energy divides by c2: as the progressive pass
            caustic.warning = gi.warning = settings.gi_photons > 0
                                               ? "has no quadratic falloff (c2 = 0), so it gets no caustic or GI photons"
                                               : "has no quadratic falloff (c2 = 0), so it gets no caustic photons";
            continue;
        }
        const auto t_map = std::chrono::steady_clock::now();
        const ProjectionMap* map = nullptr;
        const bool shoot_caustics = settings.caustic_photons > 0;
        if ((shoot_caustics || settings.build_projection_maps) && settings.projection_map != ProjectionMapMode::off) {
            // The original always used its maps; they cost one ray per cell (64 800 at the default
            // granularity) against the million photons the cells need to shoot any.
            ProjectionMap built(settings.projection_map_granularity);
            built.build(scene, light.position, classic_projection_target, cancel);
            caustic.occupied_fraction = built.occupied_fraction();
            caustic.projection_map_used = true;
            result.maps[l] = std::move(built);
            map = &result.maps[l];
        }
        caustic.map_seconds = seconds_since(t_map);
        // The energy of a photon is set by N requested, never by the photons shot
        // ("photon emission").
        if (shoot_caustics) {
            expected_caustic += static_cast<double>(caustic_offered) * (map ? std::min(1.0, 1.1 * caustic.occupied_fraction) : 1.0);
            check_photon_memory(expected_caustic + expected_gi, settings.caustic_photons, settings.memory_budget_bytes);
            const auto t0 = std::chrono::steady_clock::now();
            const glm::vec3 energy = photon_energy(light, settings.unit_distance, settings.caustic_photons, settings.energy_fudge);
            shoot_light(scene, textures, light, l, ClassicMapKind::caustic, settings.caustic_photons, energy, map,
                        settings.seed, cancel, share_rank, share_size, settings.progress, result.caustic,
                        &result.caustic_blocks[l * emission_blocks], caustic);
            caustic.shoot_seconds = seconds_since(t0);
        }
        if (settings.gi_photons > 0) {  // no projection map: diffuse surfaces everywhere matter
            expected_gi += static_cast<double>(gi_offered);
            check_photon_memory(expected_caustic + expected_gi, settings.gi_photons, settings.memory_budget_bytes,
                                "--gi-num-photons");
            const auto t0 = std::chrono::steady_clock::now();
            const glm::vec3 energy = photon_energy(light, settings.unit_distance, settings.gi_photons, settings.energy_fudge);
            shoot_light(scene, textures, light, l, ClassicMapKind::gi, settings.gi_photons, energy, nullptr,
                        settings.seed, cancel, share_rank, share_size, settings.progress, result.gi,
                        &result.gi_blocks[l * emission_blocks], gi);
            gi.shoot_seconds = seconds_since(t0);
        }
    }
    return result;
}

int classic_emission_blocks() { return emission_blocks; }

ClassicPhotonShare share_of(const ClassicPhotonResult& result) {
    ClassicPhotonShare share;
    share.caustic = reinterpret_cast<const std::uint8_t*>(result.caustic.data());
    share.caustic_count = result.caustic.size();
    share.gi = reinterpret_cast<const std::uint8_t*>(result.gi.data());
    share.gi_count = result.gi.size();
    share.caustic_blocks = result.caustic_blocks;
    share.gi_blocks = result.gi_blocks;
    share.caustic_lights = result.caustic_lights;
    share.gi_lights = result.gi_lights;
    return share;
}

namespace {

/// One map's photons from the shares in one process's order: where each block's photons come
/// from and go to (a pass over the counts), then the copies, blocks in parallel.
std::vector<Photon> merge_map(const std::vector<ClassicPhotonShare>& shares, bool caustic) {
    const std::size_t n = shares.size();
    auto blocks_of = [&](const ClassicPhotonShare& s) -> const std::vector<std::uint32_t>& {
        return caustic ? s.caustic_blocks : s.gi_blocks;
    };
    const std::size_t cells = blocks_of(shares[0]).size();
    std::vector<std::size_t> from(cells), to(cells);
    std::vector<std::size_t> cursor(n, 0);
    std::size_t total = 0;
    for (std::size_t i = 0; i < cells; ++i) {
        const std::size_t owner = (i % emission_blocks) % n;  // block index within its light
        const std::uint32_t count = blocks_of(shares[owner])[i];
        from[i] = cursor[owner];
        to[i] = total;
        cursor[owner] += count;
        total += count;
    }
    for (std::size_t r = 0; r < n; ++r)
        if (cursor[r] > (caustic ? shares[r].caustic_count : shares[r].gi_count))
            throw std::runtime_error("merging photon shares: a share holds fewer photons than its block counts say");
    std::vector<Photon> merged(total);
    caustica::parallel_for(tbb::blocked_range<std::size_t>(0, cells, 64), [&](const tbb::blocked_range<std::size_t>& range) {
        for (std::size_t i = range.begin(); i != range.end(); ++i) {
            const ClassicPhotonShare& s = shares[(i % emission_blocks) % n];
            const std::uint32_t count = blocks_of(s)[i];
            if (count == 0) continue;
            const std::uint8_t* source = (caustic ? s.caustic : s.gi) + from[i] * sizeof(Photon);
            std::memcpy(static_cast<void*>(merged.data() + to[i]), source, count * sizeof(Photon));
        }
    });
    return merged;
}

void add_reports(std::vector<LightPhotonReport>& into, const std::vector<LightPhotonReport>& from) {
    for (std::size_t l = 0; l < into.size() && l < from.size(); ++l) {
        into[l].candidates += from[l].candidates;
        into[l].traced += from[l].traced;
        into[l].stored += from[l].stored;
    }
}

}  // namespace

ClassicPhotonResult merge_classic_photons(const std::vector<ClassicPhotonShare>& shares) {
    if (shares.empty()) return {};
    for (const ClassicPhotonShare& s : shares)
        if (s.caustic_blocks.size() != shares[0].caustic_blocks.size() || s.gi_blocks.size() != shares[0].gi_blocks.size())
            throw std::runtime_error("merging photon shares: the ranks shot for different light counts");
    ClassicPhotonResult merged;
    merged.caustic = merge_map(shares, true);
    merged.gi = merge_map(shares, false);
    merged.caustic_lights = shares[0].caustic_lights;
    merged.gi_lights = shares[0].gi_lights;
    for (std::size_t r = 1; r < shares.size(); ++r) {
        add_reports(merged.caustic_lights, shares[r].caustic_lights);
        add_reports(merged.gi_lights, shares[r].gi_lights);
    }
    return merged;
}

}  // namespace caustica
