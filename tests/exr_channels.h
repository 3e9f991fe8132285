// Every channel of an OpenEXR file by name, as floats: what tests of multilayer files compare.
#pragma once

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfInputFile.h>

#include <map>
#include <string>
#include <vector>

namespace caustica::testing {

inline std::map<std::string, std::vector<float>> read_exr_channels(const std::string& path, int& width, int& height) {
    Imf::InputFile file(path.c_str());
    const Imath::Box2i window = file.header().dataWindow();
    width = window.max.x - window.min.x + 1;
    height = window.max.y - window.min.y + 1;
    std::map<std::string, std::vector<float>> channels;
    for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it)
        channels[it.name()].resize(static_cast<std::size_t>(width) * height);
    Imf::FrameBuffer frame;
    for (auto& [name, values] : channels)
        frame.insert(name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(values.data()), sizeof(float),
                                      sizeof(float) * width));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return channels;
}

inline std::map<std::string, std::vector<float>> read_exr_channels(const std::string& path) {
    int width = 0, height = 0;
    return read_exr_channels(path, width, height);
}

}  // namespace caustica::testing
