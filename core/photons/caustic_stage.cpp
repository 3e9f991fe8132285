#include "core/photons/caustic_stage.h"

#include "core/render/cluster.h"
#include "core/render/random.h"
#include "core/scene/source_location.h"
#include "core/shading/texture.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <random>

namespace caustica {
namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

bool is_specular(const MaterialDesc& m) { return m.reflective || m.refractive_index.has_value() || m.air; }

/// Whether the job wants the classic GI map: it needs lights, not a specular object.
bool gi_map_wanted(const RenderJob& job) {
    const Options& o = job.options;
    return o.gi_wanted() && o.gi_num_photons > 0 && !job.lights.empty();
}

/// What the renderer's memory budget leaves for photons once the scene is built (docs/RELIABILITY.md,
/// "Bounded memory"); never 0, which check_photon_memory reads as the default budget.
double photon_memory_left(const RenderJob& job, const RenderScene& scene) {
    return std::max(job.options.render_memory_bytes() - scene.info().estimated_bytes, 1.0);
}

std::uint64_t stage_seed(const Options& o) {
    return o.reproducible ? static_cast<std::uint64_t>(o.seed) : (static_cast<std::uint64_t>(o.seed) ^ std::random_device{}());
}

void build_progressive_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                             const std::atomic<bool>* cancel, const PhotonPassExtras& extras);
void build_classic_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                         const std::atomic<bool>* cancel, const TextureSet* textures, Cluster* cluster,
                         std::atomic<long long>* progress);

}  // namespace

std::vector<Light> job_lights(const RenderJob& job) {
    std::vector<Light> lights;
    for (int index : job.lights) {
        const LightDesc& d = job.scene->lights.at(index);
        lights.push_back({glm::vec3(d.position), glm::vec3(d.colour), glm::vec3(d.falloff), static_cast<float>(d.radius)});
    }
    return lights;
}

bool caustic_map_wanted(const RenderJob& job) {
    const Options& o = job.options;
    if (job.lights.empty() || o.no_caustic_map) return false;
    if (o.caustic_num_photons <= 0 && !o.show_projection_map) return false;
    for (const NodeDesc& node : job.scene->nodes)
        if (node.material >= 0 && is_specular(job.scene->materials[node.material])) return true;
    return false;
}

bool classic_photons_wanted(const RenderJob& job) { return caustic_map_wanted(job) || gi_map_wanted(job); }

bool progressive_photons_wanted(const RenderJob& job) {
    // --gi: one map of every path with a bounce, whatever the materials.
    if (job.options.gi_wanted()) return !job.lights.empty() && job.options.gi_num_photons > 0;
    return caustic_map_wanted(job);
}

std::uint64_t caustic_fingerprint(const RenderJob& job, std::uint64_t geometry_key) {
    std::uint64_t h = mix64(geometry_key ^ 0x63617573746963ULL);
    for (const Light& l : job_lights(job)) {
        for (int i = 0; i < 3; ++i) h = hash_double(hash_double(hash_double(h, l.position[i]), l.colour[i]), l.falloff[i]);
        h = hash_double(h, l.radius);
    }
    // Every option that feeds the photon stage, as the option table declares (core/scene/options.h).
    h = hash_options_feeding(h, job.options, stage_photons);
    // --photons-per-pixel makes the image's size a photon count.
    if (job.options.photons_per_pixel > 0.0)
        h = mix64(h ^ (static_cast<std::uint64_t>(static_cast<std::uint32_t>(job.width)) << 32 |
                       static_cast<std::uint32_t>(job.height)));
    return h | 1;  // never 0, which means "nothing built"
}

void build_classic_photon_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                                const std::atomic<bool>* cancel, const TextureSet* textures, Cluster* cluster,
                                std::atomic<long long>* progress) {
    build_classic_stage(stage, scene, job, cancel, textures, cluster && cluster->size() > 1 ? cluster : nullptr,
                        progress);
}

long long classic_photon_directions(const RenderJob& job) {
    const Options& o = job.options;
    // As build_classic_stage asks shoot_classic_photons: N of each map wanted, every light with c2 > 0.
    const long long per_light = (caustic_map_wanted(job) ? classic_photons_offered(o.caustic_num_photons) : 0) +
                                (gi_map_wanted(job) ? classic_photons_offered(o.gi_num_photons) : 0);
    return per_light * shooting_lights(job);
}

int shooting_lights(const RenderJob& job) {
    int shooting = 0;
    for (const Light& light : job_lights(job)) shooting += light.falloff.z > 0.0f ? 1 : 0;
    return shooting;
}

long long progressive_photon_directions(const RenderJob& job) {
    const Options& o = job.options;
    return (o.gi_wanted() ? o.gi_num_photons : o.caustic_num_photons) * shooting_lights(job);
}

long long photon_directions(const CausticStage& stage) {
    long long directions = 0;
    for (const LightCausticStats& l : stage.lights) directions += l.candidates;
    return directions;
}

void build_progressive_pass(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                            const std::atomic<bool>* cancel, const PhotonPassExtras& extras) {
    build_progressive_stage(stage, scene, job, cancel, extras);
}

namespace {

void build_progressive_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                             const std::atomic<bool>* cancel, const PhotonPassExtras& extras) {
    const Options& o = job.options;
    // The roulette needs P(diffuse) + P(specular) <= 1 where a surface is a mirror
    // (docs/CAUSTICS.md, "Photon paths").
    // A transparent material's kd is its medium colour, not a reflectance: it is not counted.
    for (const MaterialDesc& m : job.scene->materials) {
        if (!m.reflective || m.refractive_index.has_value() || m.air) continue;
        const double sum = (m.kd.x + m.kd.y + m.kd.z) / 3.0 + (m.ks.x + m.ks.y + m.ks.z) / 3.0;
        if (sum > 1.0 + 1e-9)
            throw InputError(m.where, "gr.material: mean(kd) + mean(ks) = " + std::to_string(sum) +
                                          " exceeds 1 on a specular material: photons would gain energy");
    }
    stage = CausticStage{};
    stage.key = caustic_fingerprint(job, 0);
    const std::vector<Light> lights = job_lights(job);
    PhotonPassSettings settings;
    settings.global_illumination = o.gi_wanted();
    // With --gi one map holds every indirect path, caustics included: --gi-num-photons are shot.
    settings.photons_per_light = settings.global_illumination ? o.gi_num_photons : o.caustic_num_photons;
    settings.unit_distance = o.unit_distance;
    settings.energy_fudge = o.energy_fudge;
    settings.projection_map = o.projection_map;
    settings.projection_map_granularity = o.caustic_pm_gran;
    settings.emission = o.photon_random_emission ? PhotonEmission::random : PhotonEmission::low_discrepancy;
    settings.seed = extras.first ? extras.seed : stage_seed(o);
    settings.sequence_seed = extras.first ? extras.first->sequence_seed : settings.seed;
    if (extras.group > 0) settings.sequence_seed = hash_combine(settings.sequence_seed, static_cast<std::uint64_t>(extras.group));
    settings.pass = extras.pass;
    settings.max_depth = o.max_depth;
    settings.split = o.photon_split;
    // --photons-per-pixel: shared by the lights that shoot photons (c2 > 0), only when photons are
    // asked for at all (0 shoots none).
    const int shooting = shooting_lights(job);
    if (shooting > 0 && settings.photons_per_light > 0 && o.photons_per_pixel > 0.0)
        settings.min_traced_per_light = o.photons_per_pixel * static_cast<double>(job.width) *
                                        static_cast<double>(job.height) / static_cast<double>(shooting);
    settings.memory_budget_bytes = photon_memory_left(job, scene);
    settings.progress = extras.progress;
    settings.reuse = extras.reuse;
    if (extras.first) {  // a later pass: the first pass's projection maps, as it used them
        settings.prebuilt_maps.assign(lights.size(), nullptr);
        settings.emission_weights.assign(lights.size(), nullptr);
        for (std::size_t l = 0; l < lights.size() && l < extras.first->lights.size(); ++l) {
            if (extras.first->lights[l].projection_map_used && l < extras.first->projection_maps.size())
                settings.prebuilt_maps[l] = &extras.first->projection_maps[l];
            if (settings.prebuilt_maps[l] && extras.emission_weights && l < extras.emission_weights->size() &&
                !(*extras.emission_weights)[l].empty())
                settings.emission_weights[l] = &(*extras.emission_weights)[l];
        }
    }
    // Guided emission learns from the first pass, which shoots as without it: its cells are
    // recorded whether or not the option is on (a few bytes a cell), so that the option changes
    // the passes that follow and not this one.
    settings.record_cells = !extras.first;
    PhotonPassResult pass = shoot_caustic_photons(scene, lights, settings, cancel);
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const LightPhotonReport& r = pass.lights[l];
        stage.lights.push_back({r.candidates, r.traced, r.stored, r.projection_map_used, r.occupied_fraction});
        stage.map_seconds += r.map_seconds;
        stage.shoot_seconds += r.shoot_seconds;
        if (!r.warning.empty())
            stage.warnings.push_back(job.scene->lights[job.lights[l]].where.str() + ": gr.light: " + r.warning);
        stage.light_positions.push_back(lights[l].position);
    }
    stage.sequence_seed = settings.sequence_seed;
    const auto t0 = std::chrono::steady_clock::now();
    // A cancelled pass is thrown away: no tree, and no maps (one may have been cut short).
    if (cancel && cancel->load()) return;
    stage.projection_maps = std::move(pass.maps);
    if (settings.record_cells)
        for (LightPhotonReport& r : pass.lights) stage.emission_cells.push_back(std::move(r.cells));
    stage.photon_pass = settings.photons_per_light > 0;
    stage.photons = std::move(pass.photons);
    // The tree keeps its own copy, in its own order: the passes' grid is given the photons as
    // stored either way, and so sums them in the same order with or without lookups.
    if (!extras.photons_only && stage.photon_pass) stage.map = std::make_unique<PhotonMap>(stage.photons);
    stage.tree_seconds = seconds_since(t0);
}

/// A rank's share of the classic photons as bytes, and back (the ranks run the same binary).
class ShareWriter {
public:
    template <typename T>
    void put(const T& value) { put_bytes(&value, sizeof value); }
    template <typename T>
    void put_vector(const std::vector<T>& v) {
        put<std::uint64_t>(v.size());
        put_bytes(v.data(), v.size() * sizeof(T));
    }
    Cluster::Bytes bytes;

private:
    void put_bytes(const void* p, std::size_t n) {
        if (n == 0) return;
        const auto* b = static_cast<const std::uint8_t*>(p);
        bytes.insert(bytes.end(), b, b + n);
    }
};

class ShareReader {
public:
    explicit ShareReader(const Cluster::Bytes& bytes) : bytes_(bytes) {}
    template <typename T>
    T get() {
        T value;
        get_bytes(&value, sizeof value);
        return value;
    }
    /// `count` T (a u64 count, then the values) left where they are: their first byte.
    template <typename T>
    const std::uint8_t* get_span(std::size_t& count) {
        const std::uint64_t n = get<std::uint64_t>();
        if (n > (bytes_.size() - at_) / sizeof(T)) throw std::runtime_error("photon share: truncated message");
        const std::uint8_t* first = bytes_.data() + at_;
        at_ += static_cast<std::size_t>(n) * sizeof(T);
        count = static_cast<std::size_t>(n);
        return first;
    }
    template <typename T>
    std::vector<T> get_vector() {
        const std::uint64_t n = get<std::uint64_t>();
        if (n > (bytes_.size() - at_) / sizeof(T)) throw std::runtime_error("photon share: truncated message");
        std::vector<T> v(static_cast<std::size_t>(n));
        get_bytes(v.data(), v.size() * sizeof(T));
        return v;
    }

private:
    void get_bytes(void* p, std::size_t n) {
        if (n > bytes_.size() - at_) throw std::runtime_error("photon share: truncated message");
        if (n == 0) return;  // an empty vector's data() may be null
        std::memcpy(p, bytes_.data() + at_, n);
        at_ += n;
    }
    const Cluster::Bytes& bytes_;
    std::size_t at_ = 0;
};

Cluster::Bytes share_bytes(const ClassicPhotonResult& r) {
    ShareWriter w;
    w.put_vector(r.caustic);
    w.put_vector(r.gi);
    w.put_vector(r.caustic_blocks);
    w.put_vector(r.gi_blocks);
    for (const std::vector<LightPhotonReport>* reports : {&r.caustic_lights, &r.gi_lights})
        for (const LightPhotonReport& l : *reports) {
            w.put(l.candidates);
            w.put(l.traced);
            w.put(l.stored);
        }
    return std::move(w.bytes);
}

/// A share as it lies in the bytes another rank sent: the photons stay there until merged.
ClassicPhotonShare share_view(const Cluster::Bytes& bytes, std::size_t lights) {
    ShareReader reader(bytes);
    ClassicPhotonShare share;
    share.caustic = reader.get_span<Photon>(share.caustic_count);
    share.gi = reader.get_span<Photon>(share.gi_count);
    share.caustic_blocks = reader.get_vector<std::uint32_t>();
    share.gi_blocks = reader.get_vector<std::uint32_t>();
    share.caustic_lights.resize(lights);
    share.gi_lights.resize(lights);
    for (std::vector<LightPhotonReport>* reports : {&share.caustic_lights, &share.gi_lights})
        for (LightPhotonReport& l : *reports) {
            l.candidates = reader.get<long long>();
            l.traced = reader.get<long long>();
            l.stored = reader.get<long long>();
        }
    return share;
}

/// Every rank's share of the photons, merged on every rank in one process's order.
ClassicPhotonResult gather_classic_photons(Cluster& cluster, ClassicPhotonResult mine, std::size_t lights) {
    std::vector<Cluster::Bytes> all = cluster.all_gather(share_bytes(mine));
    // The photons: one copy from where they arrived into the merged maps.
    std::vector<ClassicPhotonShare> shares;
    shares.reserve(all.size());
    for (const Cluster::Bytes& bytes : all) shares.push_back(share_view(bytes, lights));
    ClassicPhotonResult merged = merge_classic_photons(shares);
    shares.clear();
    all.clear();
    // The projection maps, timings and warnings are this rank's own (the same maps on every rank).
    merged.maps = std::move(mine.maps);
    for (std::size_t l = 0; l < lights; ++l) {
        for (auto [into, from] : {std::pair{&merged.caustic_lights[l], &mine.caustic_lights[l]},
                                  std::pair{&merged.gi_lights[l], &mine.gi_lights[l]}}) {
            into->projection_map_used = from->projection_map_used;
            into->occupied_fraction = from->occupied_fraction;
            into->map_seconds = from->map_seconds;
            into->shoot_seconds = from->shoot_seconds;
            into->warning = from->warning;
        }
    }
    return merged;
}

void build_classic_stage(CausticStage& stage, const RenderScene& scene, const RenderJob& job,
                         const std::atomic<bool>* cancel, const TextureSet* textures, Cluster* cluster,
                         std::atomic<long long>* progress) {
    const Options& o = job.options;
    stage = CausticStage{};
    stage.key = caustic_fingerprint(job, 0);
    // The photons see kd(uv) (a texture replaces kd): load the textures here when the session did
    // not pass them.
    std::unique_ptr<TextureSet> own_textures;
    if (!textures) {
        bool textured = false;
        for (const MaterialDesc& m : job.scene->materials) textured |= m.texture >= 0;
        if (textured) own_textures = std::make_unique<TextureSet>(*job.scene);
        textures = own_textures.get();
    }
    if (textures && textures->empty()) textures = nullptr;
    const bool caustic = caustic_map_wanted(job) && o.caustic_num_photons > 0;
    const bool gi = gi_map_wanted(job);
    const std::vector<Light> lights = job_lights(job);
    ClassicPhotonSettings settings;
    settings.caustic_photons = caustic ? o.caustic_num_photons : 0;
    settings.gi_photons = gi ? o.gi_num_photons : 0;
    settings.unit_distance = o.unit_distance;
    settings.energy_fudge = o.energy_fudge;
    settings.projection_map = o.projection_map;
    settings.projection_map_granularity = o.caustic_pm_gran;
    settings.build_projection_maps = caustic_map_wanted(job) && o.show_projection_map;
    settings.seed = stage_seed(o);
    settings.memory_budget_bytes = photon_memory_left(job, scene);
    settings.progress = progress;
    ClassicPhotonResult pass;
    if (!cluster) {
        pass = shoot_classic_photons(scene, textures, lights, settings, cancel);
    } else {
        // Each rank shoots its share; a failure or an interruption on any rank stops every rank
        // here, before the gather that would wait for it.
        settings.share_rank = cluster->rank();
        settings.share_size = cluster->size();
        std::exception_ptr error;
        try {
            pass = shoot_classic_photons(scene, textures, lights, settings, cancel);
        } catch (const InputError& e) {
            error = std::make_exception_ptr(job.located_option_error(e));  // as one process says it
        } catch (...) {
            error = std::current_exception();
        }
        cluster->checkpoint(error, cancel);
        pass = gather_classic_photons(*cluster, std::move(pass), lights.size());
    }
    for (std::size_t l = 0; l < lights.size(); ++l) {
        const LightPhotonReport& c = pass.caustic_lights[l];
        const LightPhotonReport& g = pass.gi_lights[l];
        stage.lights.push_back({c.candidates, c.traced, c.stored, c.projection_map_used, c.occupied_fraction});
        if (gi) stage.gi_lights.push_back({g.candidates, g.traced, g.stored, false, 1.0});
        stage.map_seconds += c.map_seconds;
        stage.shoot_seconds += c.shoot_seconds + g.shoot_seconds;
        const std::string& warning = c.warning.empty() ? g.warning : c.warning;
        if (!warning.empty())
            stage.warnings.push_back(job.scene->lights[job.lights[l]].where.str() + ": gr.light: " + warning);
        stage.light_positions.push_back(lights[l].position);
    }
    // A cancelled pass is thrown away: no trees, and no maps (one may have been cut short).
    if (cancel && cancel->load()) return;
    stage.projection_maps = std::move(pass.maps);
    // A GI photon may be stored at every hit of its path: check what was stored before the trees
    // double it.
    const double stored = static_cast<double>(pass.caustic.size() + pass.gi.size());
    check_photon_memory(stored, gi ? o.gi_num_photons : o.caustic_num_photons, settings.memory_budget_bytes,
                        gi ? "--gi-num-photons" : "--caustic-num-photons");
    const auto t0 = std::chrono::steady_clock::now();
    // Each map holds its photons in its tree's order: the stored ones go as soon as it is built.
    if (caustic) stage.map = std::make_unique<PhotonMap>(pass.caustic);
    pass.caustic = {};
    if (gi) stage.gi_map = std::make_unique<PhotonMap>(pass.gi);
    pass.gi = {};
    stage.tree_seconds = seconds_since(t0);
}

}  // namespace

}  // namespace caustica
