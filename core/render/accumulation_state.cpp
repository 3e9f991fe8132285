#include "core/render/accumulation_state.h"

#include "core/integrators/progressive_accumulator.h"
#include "core/io/atomic_file.h"
#include "core/io/regular_file.h"
#include "core/render/fingerprints.h"
#include "core/render/random.h"
#include "core/scene/options.h"

#include <bit>
#include <cmath>
#include <cstring>
#include <functional>

namespace caustica {
namespace {

static_assert(std::endian::native == std::endian::little, "the state file is written little-endian, as held");

// The file (docs/OUTPUT.md, "Resuming an accumulation"): a 128-byte header, the arrays, and a
// checksum of everything before it.
constexpr char state_magic[16] = {'C', 'A', 'U', 'S', 'T', 'I', 'C', 'A', '-', 'S', 'T', 'A', 'T', 'E', '\r', '\n'};
constexpr std::uint32_t state_version = 1;
constexpr std::size_t header_bytes = 128;
constexpr std::uint32_t has_radius_factors = 1, has_adapted_sums = 2;
/// The largest image a state may describe: the image readers' pixel budget (docs/OUTPUT.md, "Reading").
constexpr int max_side = 65536;

/// A 64-bit checksum of a byte stream (FNV-1a over 8-byte words, the tail zero-padded).
class Checksum {
public:
    void add(const void* data, std::size_t count) {
        const auto* bytes = static_cast<const std::uint8_t*>(data);
        for (std::size_t i = 0; i < count; ++i) {
            pending_ |= static_cast<std::uint64_t>(bytes[i]) << (8 * filled_);
            if (++filled_ == 8) flush();
        }
    }
    std::uint64_t value() {
        if (filled_ > 0) flush();
        return hash_ ^ (hash_ >> 29);
    }

private:
    void flush() {
        hash_ = (hash_ ^ pending_) * 0x100000001b3ULL;
        pending_ = 0;
        filled_ = 0;
    }
    std::uint64_t hash_ = 0xcbf29ce484222325ULL, pending_ = 0;
    int filled_ = 0;
};

/// The header's first fields: what the format and the arrays are.
struct Preamble {
    std::uint32_t version = state_version;
    std::uint32_t sums_per_pixel = ProgressiveAccumulator::sums_per_pixel;
    std::uint32_t snapshot_slots = ProgressiveAccumulator::snapshot_slots;
    std::uint32_t flags = 0;
};

/// Visits the header's fields in file order (after the magic): the preamble, then the state's own
/// numbers (int32, int64 and double as they are held).
template <typename P, typename S, typename Visit>
void for_each_field(P& p, S& s, Visit&& visit) {
    static_assert(sizeof s.key.width == 4 && sizeof s.next_pass == 4 && sizeof s.photons_emitted == 8);
    visit(p.version), visit(p.sums_per_pixel), visit(p.snapshot_slots), visit(p.flags);
    visit(s.key.width), visit(s.key.height), visit(s.next_pass), visit(s.scale_pass);
    visit(s.seed), visit(s.photons_emitted);
    visit(s.scale2), visit(s.first_radius), visit(s.radius), visit(s.typical_radius), visit(s.seconds);
    visit(s.key.scene), visit(s.key.camera), visit(s.key.options);
}

/// The header's 128 bytes.
std::string header_bytes_of(const AccumulationState& s) {
    Preamble p;
    p.flags = (s.radius_factors.empty() ? 0 : has_radius_factors) | (s.adapted_sums.empty() ? 0 : has_adapted_sums);
    std::string bytes(state_magic, sizeof state_magic);
    for_each_field(p, s, [&](const auto& field) {
        bytes.append(reinterpret_cast<const char*>(&field), sizeof field);
    });
    bytes.resize(header_bytes, '\0');
    return bytes;
}

/// Hands the file's bytes to `put` in order, the checksum last.
void for_each_chunk(const AccumulationState& s, const std::function<void(const void*, std::size_t)>& put) {
    Checksum checksum;
    auto chunk = [&](const void* data, std::size_t count) {
        checksum.add(data, count);
        put(data, count);
    };
    const std::string header = header_bytes_of(s);
    chunk(header.data(), header.size());
    chunk(s.sums.data(), s.sums.size() * sizeof(std::int64_t));
    chunk(s.radius_factors.data(), s.radius_factors.size() * sizeof(float));
    chunk(s.adapted_sums.data(), s.adapted_sums.size() * sizeof(std::int64_t));
    const std::uint64_t sum = checksum.value();
    put(&sum, sizeof sum);
}

/// Reads `count` bytes at `offset` of the source; fewer when it ends.
using ByteSource = std::function<std::size_t(void* out, std::size_t count, std::uint64_t offset)>;

/// A checked number of the header: InputError "NAME: reason" when `ok` is false.
void require(bool ok, const std::string& name, const std::string& reason) {
    if (!ok) throw InputError(name + ": " + reason);
}

bool finite_at_least_zero(double x) { return std::isfinite(x) && x >= 0.0; }

const std::string cannot_continue = "cannot continue this accumulation: ";

/// Why a state of one image size cannot continue as another.
std::string size_mismatch(int saved_width, int saved_height, int width, int height) {
    return "it was saved for a " + std::to_string(saved_width) + " x " + std::to_string(saved_height) +
           " image, this render is " + std::to_string(width) + " x " + std::to_string(height);
}

/// Checks the header against the format and the image size expected; returns the file length it implies.
std::uint64_t checked_length(const Preamble& p, const AccumulationState& s, const std::string& name, int width, int height) {
    require(p.version == state_version, name,
            "accumulation state version " + std::to_string(p.version) + "; this caustica reads version " +
                std::to_string(state_version));
    require(p.sums_per_pixel == ProgressiveAccumulator::sums_per_pixel && p.snapshot_slots == ProgressiveAccumulator::snapshot_slots,
            name, "holds " + std::to_string(p.sums_per_pixel) + " sums a pixel; this caustica keeps " +
                      std::to_string(ProgressiveAccumulator::sums_per_pixel));
    require((p.flags & ~(has_radius_factors | has_adapted_sums)) == 0, name, "unknown flags in the header");
    const int w = s.key.width, h = s.key.height;
    require(w > 0 && h > 0 && w <= max_side && h <= max_side, name,
            "declares an image of " + std::to_string(w) + " x " + std::to_string(h) + " pixels");
    require(w == width && h == height, name, cannot_continue + size_mismatch(w, h, width, height));
    require(s.next_pass >= 0 && s.next_pass <= max_accumulated_passes, name,
            "declares " + std::to_string(s.next_pass) + " passes");
    require(s.scale_pass >= 0 && s.scale_pass <= s.next_pass && s.photons_emitted >= 0, name,
            "its pass counts are inconsistent");
    require(std::isfinite(s.scale2) && s.scale2 > 0.0 && s.scale2 <= 16.0 && finite_at_least_zero(s.first_radius) &&
                finite_at_least_zero(s.radius) && finite_at_least_zero(s.typical_radius) && finite_at_least_zero(s.seconds),
            name, "a radius or time in its header is out of range");
    const std::uint64_t pixels = static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(h);
    std::uint64_t length = header_bytes + pixels * ProgressiveAccumulator::sums_per_pixel * sizeof(std::int64_t);
    if (p.flags & has_radius_factors) length += pixels * sizeof(float);
    if (p.flags & has_adapted_sums) length += pixels * ProgressiveAccumulator::snapshot_slots * sizeof(std::int64_t);
    return length + sizeof(std::uint64_t);
}

/// Checks what the checksum cannot: every pixel's samples within the passes, every radius factor
/// within the range the adaptation keeps (docs/CAUSTICS.md, "A radius per pixel").
void check_arrays(const AccumulationState& s, const std::string& name) {
    const std::size_t pixels = s.sums.size() / ProgressiveAccumulator::sums_per_pixel;
    for (std::size_t i = 0; i < pixels; ++i) {
        const std::int64_t samples = s.sums[i * ProgressiveAccumulator::sums_per_pixel + ProgressiveAccumulator::sample_count_slot];
        require(samples >= 0 && samples <= s.next_pass, name,
                "pixel " + std::to_string(i) + " has " + std::to_string(samples) + " samples of " +
                    std::to_string(s.next_pass) + " passes");
    }
    for (float f : s.radius_factors)
        require(std::isfinite(f) && f > 0.0f && f <= 1.0f, name, "a pixel's radius factor is out of range");
}

template <typename T>
void read_array(const ByteSource& source, std::uint64_t& offset, std::vector<T>& out, std::size_t count,
                Checksum& checksum, const std::string& name) {
    out.resize(count);
    const std::size_t bytes = count * sizeof(T);
    require(source(out.data(), bytes, offset) == bytes, name, "truncated while reading");
    checksum.add(out.data(), bytes);
    offset += bytes;
}

AccumulationState decode(const ByteSource& source, std::uint64_t length, const std::string& name, int width, int height) {
    require(length >= header_bytes + sizeof(std::uint64_t), name,
            "not an accumulation state (" + std::to_string(length) + " bytes, shorter than its header)");
    char bytes[header_bytes];
    require(source(bytes, header_bytes, 0) == header_bytes, name, "truncated while reading");
    require(std::memcmp(bytes, state_magic, sizeof state_magic) == 0, name, "not a caustica accumulation state");
    Preamble p;
    AccumulationState s;
    std::size_t at = sizeof state_magic;
    for_each_field(p, s, [&](auto& field) {
        std::memcpy(&field, bytes + at, sizeof field);
        at += sizeof field;
    });
    const std::uint64_t expected = checked_length(p, s, name, width, height);
    require(length == expected, name,
            "is " + std::to_string(length) + " bytes, its header declares " + std::to_string(expected) +
                (length < expected ? " (truncated)" : ""));
    Checksum checksum;
    checksum.add(bytes, header_bytes);
    std::uint64_t offset = header_bytes;
    const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    read_array(source, offset, s.sums, pixels * ProgressiveAccumulator::sums_per_pixel, checksum, name);
    if (p.flags & has_radius_factors) read_array(source, offset, s.radius_factors, pixels, checksum, name);
    if (p.flags & has_adapted_sums)
        read_array(source, offset, s.adapted_sums, pixels * ProgressiveAccumulator::snapshot_slots, checksum, name);
    std::uint64_t stored = 0;
    require(source(&stored, sizeof stored, offset) == sizeof stored, name, "truncated while reading");
    require(stored == checksum.value(), name, "its checksum does not match: the file is damaged");
    check_arrays(s, name);
    return s;
}

}  // namespace

AccumulationKey accumulation_key(const RenderJob& job) {
    AccumulationKey key;
    key.scene = scene_content_fingerprint(job);
    const CameraDesc& c = job.camera;
    for (double v : {c.eye.x, c.eye.y, c.eye.z, c.view.x, c.view.y, c.view.z, c.up.x, c.up.y, c.up.z, c.fovy_degrees})
        key.camera = hash_double(key.camera, v);
    // The stopping rules decide how far the accumulation goes, not what it adds.
    Options feeding = job.options;
    feeding.passes = 0;
    feeding.passes_given = true;
    feeding.time_limit = 0.0;
    feeding.target_error = 0.0;
    key.options = hash_options_feeding(0, feeding, stage_scene | stage_photons | stage_image);
    const int r = job.options.resolution_override;
    key.width = r > 0 ? r : job.width;
    key.height = r > 0 ? r : job.height;
    return key;
}

std::string accumulation_mismatch(const AccumulationKey& saved, const AccumulationKey& job_key) {
    if (saved.width != job_key.width || saved.height != job_key.height)
        return size_mismatch(saved.width, saved.height, job_key.width, job_key.height);
    if (saved.options != job_key.options)
        return "it was saved with other options feeding the accumulation (all but --passes, --time, "
               "--target-error and the output, reporting and thread options must be the same)";
    if (saved.scene != job_key.scene)
        return "it was saved for another scene (its geometry, materials, textures or lights differ)";
    if (saved.camera != job_key.camera) return "it was saved for another camera";
    return "";
}

std::string accumulation_state_path(const std::string& image_path) { return image_path + ".caustica-state"; }

std::string encode_accumulation_state(const AccumulationState& state) {
    std::string bytes;
    for_each_chunk(state, [&](const void* data, std::size_t count) {
        bytes.append(static_cast<const char*>(data), count);
    });
    return bytes;
}

void write_accumulation_state(const std::string& path, const AccumulationState& state, bool inside_current_folder) {
    write_file_atomic(
        path,
        [&](std::FILE* file, std::string& error) {
            bool ok = true;
            for_each_chunk(state, [&](const void* data, std::size_t count) {
                if (ok && count > 0 && std::fwrite(data, 1, count, file) != count) ok = false;
            });
            if (!ok) error = std::strerror(errno);
            return ok ? FileWriteOutcome::written : FileWriteOutcome::failed;
        },
        nullptr, inside_current_folder ? OutputPlace::inside_current_folder : OutputPlace::anywhere);
}

AccumulationState read_accumulation_state(const std::string& path, int width, int height) {
    io::Descriptor file;
    const std::uint64_t length = io::open_regular(path, file);
    return decode([&](void* out, std::size_t count, std::uint64_t offset) { return io::read_at(file.fd, out, count, offset); },
                  length, path, width, height);
}

AccumulationState decode_accumulation_state(const std::string& bytes, const std::string& name, int width, int height) {
    return decode(
        [&](void* out, std::size_t count, std::uint64_t offset) {
            if (offset >= bytes.size()) return std::size_t{0};
            const std::size_t n = std::min<std::size_t>(count, bytes.size() - offset);
            std::memcpy(out, bytes.data() + offset, n);
            return n;
        },
        bytes.size(), name, width, height);
}

}  // namespace caustica
