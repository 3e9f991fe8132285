// A progressive accumulation saved to a file, so that a later run continues it (`caustica render
// --resume`): the accumulator's integer sums, the per-pixel radius factors, where the pass, radius
// and random sequences stand, and the keys of the job it belongs to. docs/OUTPUT.md, "Resuming an
// accumulation" describes the format; reading validates everything and allocates only what the
// job's own image size needs.
#pragma once

#include "core/scene/scene_desc.h"

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace caustica {

/// What an accumulation's passes depend on, in parts, so that a refusal can say which part
/// differs: the scene by content (geometry, materials, texture names, lights, ambient and
/// background), the camera, and the options that feed the accumulation (every option feeding the
/// scene, photon or image stages but the stopping rules --passes, --time and --target-error).
struct AccumulationKey {
    std::uint64_t scene = 0, camera = 0, options = 0;
    int width = 0, height = 0;  ///< the image size rendered (after --minres and the like)
    bool operator==(const AccumulationKey&) const = default;
};

/// The key of a job's accumulation.
AccumulationKey accumulation_key(const RenderJob& job);

/// Why an accumulation saved with `saved` cannot continue as `job_key` ("" when it can): the
/// first part that differs, in words ("it was saved for another camera").
std::string accumulation_mismatch(const AccumulationKey& saved, const AccumulationKey& job_key);

/// The whole state of a progressive accumulation between two passes (or after a cancelled one).
struct AccumulationState {
    AccumulationKey key;
    int next_pass = 0;            ///< 0-based index of the next pass
    int scale_pass = 0;           ///< the pass scale2 is for
    double scale2 = 1.0;          ///< (r_i / r_1)^2 of pass scale_pass, in (0, 16] (--auto-radius scales it)
    double first_radius = 0.0, radius = 0.0, typical_radius = 0.0;
    std::uint64_t seed = 0;       ///< base of the photon and pixel streams
    long long photons_emitted = 0;
    double seconds = 0.0;         ///< rendering time over every run so far
    std::vector<std::int64_t> sums;           ///< ProgressiveAccumulator::sums()
    std::vector<float> radius_factors;        ///< per pixel, or empty (all 1)
    std::vector<std::int64_t> adapted_sums;   ///< the sums at the last radius update, or empty
};

/// The file an image's accumulation is saved in: "IMAGE.caustica-state" beside it.
std::string accumulation_state_path(const std::string& image_path);

/// The file's bytes for `state`.
std::string encode_accumulation_state(const AccumulationState& state);

/// Writes `state` to `path` atomically (core/io/atomic_file.h; `inside_current_folder` as for a
/// script's image). Throws std::runtime_error "cannot write 'PATH': reason".
void write_accumulation_state(const std::string& path, const AccumulationState& state, bool inside_current_folder);

/// Reads the state saved in `path` for an image of width x height, checking the magic, the
/// version, the sizes (against that image size before anything is allocated, and against the
/// file's length), every field's range and the checksum. Throws InputError("PATH: reason").
AccumulationState read_accumulation_state(const std::string& path, int width, int height);

/// The same, from bytes already in memory (`name` stands for the file in messages).
AccumulationState decode_accumulation_state(const std::string& bytes, const std::string& name, int width, int height);

}  // namespace caustica
