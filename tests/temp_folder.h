// A fresh folder under the system temp dir for a test's files, removed at the end of the test;
// and running in a folder for a while (the current folder a user runs caustica in).
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace caustica::testing {

class TempFolder {
public:
    explicit TempFolder(const std::string& prefix = "caustica_test") {
        static int counter = 0;
        path_ = std::filesystem::temp_directory_path() /
                (prefix + "_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~TempFolder() {
        std::error_code ignored;
        std::filesystem::remove_all(path_, ignored);
    }
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;

    /// Writes `text` to `name` (folders created) and returns the full path.
    std::string write(const std::string& name, const std::string& text) const {
        const std::filesystem::path file = path_ / name;
        std::filesystem::create_directories(file.parent_path());
        std::ofstream(file, std::ios::binary) << text;
        return file.string();
    }
    /// The full path of `name` in the folder.
    std::string file(const std::string& name) const { return (path_ / name).string(); }
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
};

/// Makes `folder` the process's current folder for its lifetime, then goes back.
struct InFolder {
    const std::filesystem::path previous = std::filesystem::current_path();
    explicit InFolder(const std::filesystem::path& folder) { std::filesystem::current_path(folder); }
    ~InFolder() {
        std::error_code ignored;
        std::filesystem::current_path(previous, ignored);
    }
};

}  // namespace caustica::testing
