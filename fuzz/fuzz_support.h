// What the fuzz targets share: a private temporary folder for the files they hand to readers
// that take a path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace caustica::fuzz {

/// A folder made with mkdtemp under $TMPDIR (or /tmp) on first use, removed at process exit.
class FuzzFolder {
public:
    /// The folder of this process (one per process, shared by the targets).
    static const FuzzFolder& get();

    const std::string& path() const { return path_; }
    /// `path()/name`, holding exactly `size` bytes of `data` (replaced each call).
    std::string write(const std::string& name, const std::uint8_t* data, std::size_t size) const;
    std::string write(const std::string& name, const std::string& text) const;

private:
    FuzzFolder();
    std::string path_;
};

}  // namespace caustica::fuzz
