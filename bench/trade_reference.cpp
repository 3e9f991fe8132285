#include "bench/trade_reference.h"

#include "core/render/random.h"
#include "core/render/render_session.h"

#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace caustica::trade {
namespace {

std::uint32_t byte_swap(std::uint32_t v) {
    return (v >> 24) | ((v >> 8) & 0xff00u) | ((v << 8) & 0xff0000u) | (v << 24);
}

std::string format_hash(std::uint64_t h) {
    char text[17];
    std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
    return text;
}

}  // namespace

void write_pfm(const std::string& path, const Image& image) {
    std::ostringstream header;
    header << "PF\n" << image.width << ' ' << image.height << "\n-1.0\n";  // negative scale: little-endian
    std::vector<std::uint32_t> data;
    data.reserve(image.pixels.size() * 3);
    for (int y = image.height - 1; y >= 0; --y)  // PFM stores the bottom row first
        for (int x = 0; x < image.width; ++x)
            for (int c = 0; c < 3; ++c) {
                std::uint32_t bits = std::bit_cast<std::uint32_t>(image.at(x, y)[c]);
                if constexpr (std::endian::native == std::endian::big) bits = byte_swap(bits);
                data.push_back(bits);
            }
    const std::string temporary = path + ".tmp";
    {
        std::ofstream out(temporary, std::ios::binary);
        out << header.str();
        out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * 4));
        if (!out) throw std::runtime_error(path + ": cannot write");
    }
    std::filesystem::rename(temporary, path);
}

Image read_pfm(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(path + ": cannot open");
    std::string magic;
    int width = 0, height = 0;
    double scale = 0.0;
    in >> magic >> width >> height >> scale;
    in.get();  // the single white-space character before the data
    if (!in || magic != "PF" || width <= 0 || height <= 0 || scale == 0.0)
        throw std::runtime_error(path + ": not a colour PFM file");
    const bool little = scale < 0.0;
    const bool swap = little != (std::endian::native == std::endian::little);
    std::vector<std::uint32_t> data(static_cast<std::size_t>(width) * height * 3);
    in.read(reinterpret_cast<char*>(data.data()), static_cast<std::streamsize>(data.size() * 4));
    if (!in) throw std::runtime_error(path + ": truncated PFM data");
    Image image(width, height);
    std::size_t i = 0;
    for (int y = height - 1; y >= 0; --y)
        for (int x = 0; x < width; ++x)
            for (int c = 0; c < 3; ++c) {
                const std::uint32_t bits = swap ? byte_swap(data[i++]) : data[i++];
                image.at(x, y)[c] = std::bit_cast<float>(bits);
            }
    return image;
}

std::uint64_t scene_content_hash(const caustica::RenderJob& job) {
    std::uint64_t h = caustica::geometry_fingerprint(job);
    auto mix = [&h](double v) { h = caustica::hash_double(h, v); };
    const caustica::CameraDesc& c = job.camera;
    for (int i = 0; i < 3; ++i) mix(c.eye[i]), mix(c.view[i]), mix(c.up[i]);
    mix(c.fovy_degrees);
    for (int index : job.lights) {
        const caustica::LightDesc& l = job.scene->lights.at(index);
        for (int i = 0; i < 3; ++i) mix(l.position[i]), mix(l.colour[i]), mix(l.falloff[i]);
        mix(l.radius);
    }
    mix(job.options.unit_distance);
    mix(job.options.energy_fudge);
    mix(job.options.max_depth);
    for (int i = 0; i < 3; ++i) mix(job.miss_colour[i]);
    mix(static_cast<double>(job.options.integrator));
    // Bumped when what a scene means (docs/SCENE_LANGUAGE.md) changes under the same numbers; this
    // version: media of colour ks, the horizontal camera angle, the white miss colour.
    constexpr double scene_rules_version = 10.0;
    mix(scene_rules_version);
    return h;
}

void write_reference_info(const std::string& path, const ReferenceInfo& info) {
    std::ofstream out(path);
    out << "# Made by bench/trade --make-references; read by bench/trade to detect a stale reference.\n"
        << "scene_file = " << info.scene_file << '\n'
        << "scene_hash = " << format_hash(info.scene_hash) << '\n'
        << "width = " << info.width << '\n'
        << "height = " << info.height << '\n'
        << "photons = " << info.photons << '\n'
        << "neighbours = " << info.neighbours << '\n'
        << "max_dist = " << info.max_dist << '\n'
        << "runs = " << info.runs << '\n'
        << "seconds = " << info.seconds << '\n'
        << "noise = " << info.noise << '\n'
        << "command = " << info.command << '\n';
    if (!out) throw std::runtime_error(path + ": cannot write");
}

ReferenceInfo read_reference_info(const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path + ": cannot open");
    ReferenceInfo info;
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        const auto eq = line.find(" = ");
        if (eq == std::string::npos) throw std::runtime_error(path + ": bad line '" + line + "'");
        const std::string key = line.substr(0, eq), value = line.substr(eq + 3);
        if (key == "scene_file") info.scene_file = value;
        else if (key == "scene_hash") info.scene_hash = std::stoull(value, nullptr, 16);
        else if (key == "width") info.width = std::stoi(value);
        else if (key == "height") info.height = std::stoi(value);
        else if (key == "photons") info.photons = std::stoll(value);
        else if (key == "neighbours") info.neighbours = std::stoi(value);
        else if (key == "max_dist") info.max_dist = std::stod(value);
        else if (key == "runs") info.runs = std::stoi(value);
        else if (key == "seconds") info.seconds = std::stod(value);
        else if (key == "noise") info.noise = std::stod(value);
        else if (key == "command") info.command = value;
    }
    return info;
}

std::string reference_problem(const std::string& image_path, const std::string& info_path,
                              const ReferenceInfo& expected) {
    namespace fs = std::filesystem;
    if (!fs::exists(image_path)) return "missing " + image_path;
    if (!fs::exists(info_path)) return "missing " + info_path;
    const ReferenceInfo stored = read_reference_info(info_path);
    if (stored.scene_hash != expected.scene_hash)
        return expected.scene_file + " changed since the reference was made (hash " + format_hash(stored.scene_hash) +
               ", now " + format_hash(expected.scene_hash) + ")";
    if (stored.width != expected.width || stored.height != expected.height)
        return "reference is " + std::to_string(stored.width) + "x" + std::to_string(stored.height) +
               ", the harness renders " + std::to_string(expected.width) + "x" + std::to_string(expected.height);
    if (stored.photons != expected.photons || stored.neighbours != expected.neighbours ||
        stored.runs != expected.runs || std::abs(stored.max_dist - expected.max_dist) > 1e-9 * expected.max_dist)
        return "reference settings differ from the harness's (photons, neighbours, max distance or runs)";
    return {};
}

}  // namespace caustica::trade
