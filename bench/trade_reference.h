// Stored reference images for bench/trade: float-faithful PFM files plus a small text file that
// says what made them, so a reference that no longer matches its scene is detected.
#pragma once

#include "core/scene/scene_desc.h"

#include "core/render/image.h"

#include <cstdint>
#include <string>

namespace caustica::trade {

/// What a stored reference was rendered from; written beside the image as NAME.txt.
struct ReferenceInfo {
    std::string scene_file;         ///< relative to the source tree, e.g. scenes/default.lua
    std::uint64_t scene_hash = 0;   ///< scene_content_hash of the scene as the script builds it
    int width = 0, height = 0;
    long long photons = 0;          ///< photon directions per light, per run
    int neighbours = 0;
    double max_dist = 0.0;
    int runs = 0;                   ///< independent runs averaged (seeds 1..runs)
    double seconds = 0.0;           ///< wall time it took to make
    double noise = 0.0;             ///< its own relative RMSE over the caustic region, from run-to-run spread
    std::string command;            ///< the exact command that made it
};

/// Writes a colour PFM (little-endian 32-bit floats, bottom row first, as the format says).
void write_pfm(const std::string& path, const Image& image);

/// Reads a colour PFM written by write_pfm (either byte order). Throws std::runtime_error.
Image read_pfm(const std::string& path);

/// FNV-1a 64-bit hash of a file's bytes. Throws std::runtime_error when it cannot be read.
/// What a caustics-only reference depends on: the geometry and materials (geometry_fingerprint),
/// the camera, the lights, and the options that change photon energies or paths (unit distance,
/// energy fudge, recursion depth). Not the photon count, N or gather distance (the recipe sets
/// them), nor comments or image options: editing those does not make a reference stale.
std::uint64_t scene_content_hash(const caustica::RenderJob& job);

/// Writes `info` as "key = value" lines.
void write_reference_info(const std::string& path, const ReferenceInfo& info);

/// Reads a file written by write_reference_info. Throws std::runtime_error.
ReferenceInfo read_reference_info(const std::string& path);

/// Why a stored reference cannot be used for `expected` (missing files, another scene hash,
/// resolution or settings), or "" when it matches.
std::string reference_problem(const std::string& image_path, const std::string& info_path,
                              const ReferenceInfo& expected);

}  // namespace caustica::trade
